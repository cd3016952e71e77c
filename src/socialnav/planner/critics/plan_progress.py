"""Plan-progress critic: the length of the global plan still to go from a trajectory's end.

The goal-distance critic (ROS ``GoalCostFunction``) measures a free-space BFS distance to the
local goal. Where the plan bends away from the straight line to the goal — it approaches the
goal from the side because someone stands near it and the global planner's costmap keeps their
personal space — following the plan *raises* that distance while cutting toward the goal raises
the path distance, and a differential-drive robot facing along the plan then finds turning on
the spot cheapest, cycle after cycle, 2 m short of the goal (generated ``crowdnav_visible``,
Pioneer). Measuring the distance still to go *along the plan* makes following it progress, as
in the path-following critics of Nav2's MPPI controller (``PathFollowCritic``,
``PathAlignCritic``) and the progress terms of model-predictive path followers.

Exact definition (m), at the end point ``(x, y)`` of each trajectory:
1. ``i`` = nearest vertex of the global plan densified to ``spacing`` m, searched only among the
   vertices within the planner's reach + ``margin`` m (default 2 m, as the heading critic) of
   plan length from its start, so a plan that loops back near the robot does not shortcut the
   search;
2. cost = (plan length from vertex ``i`` to the plan's end) + ``|(x, y) − vertex i|``.
At the plan's end it is the straight-line distance to the goal. Legality is the goal-distance
critic's (it shares that critic's BFS grid): an end point from which the local goal cannot be
reached — a person or an obstacle closes the corridor — is ``unreachable``, so a robot facing
someone who blocks a narrow corridor has no legal move toward them and waits (``WAITING``)
instead of creeping up to them on the plan's progress.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
from socialnav.planner.critics.base import CRITICS, CriticScore
from socialnav.planner.critics.goal_distance import GoalDistanceCritic
from socialnav.planner.critics.map_grid import densify_path

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


@CRITICS.register("plan_progress")
@dataclass(frozen=True)
class PlanProgressCritic(GoalDistanceCritic):
    """Plan length (m) still to go from each trajectory's end point; ``spacing`` (m) of the
    densified plan; ``margin`` (m) of plan searched beyond the planner's reach. The illegal
    masks are :class:`GoalDistanceCritic`'s (``unreachable``, ``off_map``)."""

    name: ClassVar[str] = "plan_progress"
    unit: ClassVar[str] = "m"

    spacing: float = 0.05
    margin: float = 2.0

    def __post_init__(self) -> None:
        if not (self.spacing > 0 and self.margin >= 0):
            raise ValueError("plan_progress: spacing must be > 0 and margin >= 0")

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Remaining plan length (m) ``(N,)`` from each end point (see the module docstring)
        and the goal-distance critic's illegal masks.

        Raises :class:`~socialnav.planner.critics.base.CriticUnavailable` when no plan cell is
        in view (an empty plan included)."""
        # the goal distance's grid raises CriticUnavailable when no plan cell is in view
        legality = super().score(trajs, ctx).illegal
        dense = densify_path(np.asarray(ctx.global_path, dtype=float).reshape(-1, 2), self.spacing)
        seg = np.hypot(*np.diff(dense, axis=0).T)
        s = np.concatenate([[0.0], np.cumsum(seg)])
        reach = ctx.cache.reach
        horizon = float(np.inf if reach is None else reach) + self.margin
        kept = max(int(np.searchsorted(s, horizon, side="right")), 1)
        near = dense[:kept]
        end = trajs.poses[:, -1, :2].astype(float)
        if kernels.enabled() and np.isfinite(near).all():
            i = kernels.nearest_vertex(end, near)
        else:
            d2 = ((end[:, None, :] - near[None, :, :]) ** 2).sum(axis=-1)
            i = np.argmin(d2, axis=1)
        offset = np.hypot(*(end - near[i]).T)
        return CriticScore(np.ascontiguousarray(s[-1] - s[i] + offset), legality)

"""Heading critic: how far the trajectory's final yaw is from the way the plan goes.

Banisetty et al., eq. "Cost function", term γ·Δ_heading (``Compute_Heading_Diff``); the paper's
prose ("the distance that the robot is from the global path") duplicates Δ_path, so this follows
ROS ``base_local_planner`` ``heading_scoring`` (``TrajectoryPlanner::headingDiff``) instead.

Exact definition (rad, in ``[0, pi]``), evaluated at the end pose ``(x, y, yaw)``:
1. ``i`` = nearest vertex of the global plan (densified to ``spacing`` m) to ``(x, y)``;
2. ``j`` = the first vertex at least ``heading_lookahead`` m further along the plan (or the last);
3. the desired direction is ``atan2`` of plan[j] − (x, y), or — when that point is closer than
   ``heading_lookahead / 2`` (at the end of the plan) — the plan's tangent at ``j``;
4. cost = ``|wrap(yaw − desired)|``.
Deviation from ROS: ROS picks the furthest plan point in line of sight (a costmap ray test per
sample); the look-ahead point along the plan needs no ray casting and is vectorized.
Near the goal (the robot within ``near_goal`` m of it) the cost is 0: the plan's last few cells
point in arbitrary directions there, and chasing them made the robot dither short of the goal
(the "oscillation at the goal" users report); Nav2 likewise drops its alignment critics near the
goal, and the goal-handling stage turns the robot to the goal yaw.

With ``goal_align`` (off in ROS; on in the ``paccet`` preset), a holonomic base is scored
against the goal's yaw instead, ``|wrap(yaw − goal yaw)|``, once the goal is within its reach:
the robot within ``near_goal`` m or within the metres its rollouts can travel this cycle
(``ctx.cache.reach``) of the goal (Nav2 MPPI ``GoalAngleCritic``, whose ``threshold_to_consider``
is 0.5 m). The base then turns to the goal's yaw while it drives in, and turns in place after
arriving only for what is left (most of the turn for a goal facing back the way it came).
Every rollout of the cycle is scored the same way: judging only those that end at the plan's
end by the goal's yaw made a PR2 slow down short of a goal facing back the way it came, and
judging them by the plan's last grid segment (cell centre to goal, pointing anywhere) had
turned it up to 1.4 rad away from the goal's yaw in the last metre. Not at a social waypoint
the robot passes through (``steers_to_waypoint``): its yaw is not an end pose. Not for a
differential drive, which can only turn while it drives by bending its path: in the recorded
crowds that cost the Pioneer time and successes (measurements at
``presets.RECOMMENDED_PARAMS``).

Only the first ``horizon`` m of the plan are searched (the planner's reach + 2 m), so a plan that
loops back near the robot does not confuse the nearest-vertex search.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from socialnav.core.errors import checked_bool
from socialnav.core.geometry import wrap_angle
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
from socialnav.planner.cache import HeadingPlan
from socialnav.planner.critics.base import CRITICS, Critic, CriticScore, CriticUnavailable
from socialnav.planner.critics.map_grid import densify_path

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


@CRITICS.register("heading")
@dataclass(frozen=True)
class HeadingCritic(Critic):
    """``heading_lookahead`` (m) along the plan; ``spacing`` (m) of the densified plan;
    ``near_goal`` (m): no heading cost within this distance of the goal; ``goal_align``: a
    holonomic base is scored against the goal's yaw within its reach of the goal (module
    docstring; ignored for a differential drive and at a social waypoint). ``ValueError`` on a
    non-positive length, ``ConfigurationError`` (a ``ValueError``) on a non-bool
    ``goal_align``."""

    name: ClassVar[str] = "heading"
    unit: ClassVar[str] = "rad"

    heading_lookahead: float = 0.325
    spacing: float = 0.05
    near_goal: float = 0.5
    goal_align: bool = False

    def __post_init__(self) -> None:
        if not (self.heading_lookahead > 0 and self.spacing > 0):
            raise ValueError("heading_lookahead and spacing must be positive")
        object.__setattr__(self, "goal_align", checked_bool(self.goal_align, "goal_align"))

    def _aligns(self, ctx: PlanningContext) -> bool:
        return self.goal_align and ctx.robot.holonomic and not ctx.steers_to_waypoint()

    def prepare(self, ctx: PlanningContext) -> None:
        """Densify the plan near the robot and its tangents (per cycle)."""
        if ctx.cache.heading_plan is not None:
            return
        path = np.asarray(ctx.global_path, dtype=float).reshape(-1, 2)
        if path.shape[0] == 0:
            raise CriticUnavailable("empty global plan")
        dense = densify_path(path, self.spacing)
        reach = ctx.cache.reach
        horizon = float(np.inf if reach is None else reach) + 2.0 + self.heading_lookahead
        if kernels.enabled() and dense.dtype == np.float64 and np.isfinite(dense).all():
            # One pass for the arc lengths; they never decrease, so the kept vertices are a
            # prefix (the same ones as the mask below).
            s = kernels.arc_lengths(dense)
            kept = max(int(np.searchsorted(s, horizon, side="right")), 1)
            dense, s = dense[:kept].copy(), s[:kept].copy()
        else:
            s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
            keep = s <= horizon
            keep[0] = True
            dense, s = dense[keep], s[keep]
        # Tangent at each vertex: direction of the segment arriving at it (first: leaving it).
        if dense.shape[0] > 1:
            d = np.diff(dense, axis=0)
            seg = np.arctan2(d[:, 1], d[:, 0])
            tangent = np.concatenate([seg[:1], seg])
        else:
            tangent = np.array([float(ctx.goal[2])])
        ctx.cache.heading_plan = HeadingPlan(dense, s, tangent)

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Heading error (rad) ``(N,)`` of each end pose against the plan ahead (with
        ``goal_align``, within reach of the goal, against the goal's yaw)."""
        to_goal = float(np.hypot(*(np.asarray(ctx.pose[:2]) - np.asarray(ctx.goal[:2]))))
        if self._aligns(ctx) and to_goal < max(self.near_goal, ctx.cache.reach or 0.0):
            yaw = trajs.poses[:, -1, 2].astype(float)
            return CriticScore(np.abs(wrap_angle(yaw - float(ctx.goal[2]))))
        if to_goal < self.near_goal:
            return CriticScore(np.zeros(len(trajs)))
        plan = ctx.cache.heading_plan
        if plan is None:
            self.prepare(ctx)
            plan = ctx.cache.heading_plan
            assert plan is not None  # prepare stores it or raises
        dense, s, tangent = plan.dense, plan.s, plan.tangent
        end = trajs.poses[:, -1].astype(float)
        if kernels.enabled():
            i = kernels.nearest_vertex(end, dense)
        else:
            d2 = (end[:, None, 0] - dense[None, :, 0]) ** 2 + (
                end[:, None, 1] - dense[None, :, 1]
            ) ** 2
            i = np.argmin(d2, axis=1)
        j = np.minimum(np.searchsorted(s, s[i] + self.heading_lookahead - 1e-9), s.size - 1)
        delta = dense[j] - end[:, :2]
        far = np.hypot(delta[:, 0], delta[:, 1]) >= 0.5 * self.heading_lookahead
        desired = np.where(far, np.arctan2(delta[:, 1], delta[:, 0]), tangent[j])
        return CriticScore(np.abs(wrap_angle(end[:, 2] - desired)))

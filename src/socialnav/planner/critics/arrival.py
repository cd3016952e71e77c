"""Arrival-time critic: how soon a rollout reaches the goal (seconds).

With ``LocalPlannerParams.stop_at_goal`` a rollout that enters the goal tolerance stands on the
goal's xy from then on (``local_planner.stop_at_goal``), so every arriving rollout scores 0 on
the path and goal distances; this critic prefers the one that arrives first, which is what
drives the robot into the goal at speed instead of creeping (the end-point scoring of ROS
``base_local_planner`` makes the approach speed decay like distance / ``sim_time``).
Cost = the rollout time ``t`` (s) of the first pose exactly on the goal's xy; rollouts that do
not arrive cost ``t[-1] + (t[1] - t[0])`` (one step past the horizon). Not a critic of the
paper; Nav2's MPPI ``GoalCritic`` plays the same role.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from socialnav.core.trajectories import Trajectories
from socialnav.planner.critics.base import CRITICS, Critic, CriticScore

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


@CRITICS.register("arrival_time")
@dataclass(frozen=True)
class ArrivalTimeCritic(Critic):
    """Seconds until the rollout stands on ``ctx.goal``'s xy (see the module docstring)."""

    name: ClassVar[str] = "arrival_time"
    unit: ClassVar[str] = "s"

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Raw cost ``(N,)`` in s: first step on the goal, else the horizon plus one step."""
        t = trajs.t
        late = float(t[-1] + (t[1] - t[0] if t.shape[0] > 1 else 0.0))
        on_goal = (trajs.xy[..., 0] == ctx.goal[0]) & (trajs.xy[..., 1] == ctx.goal[1])
        arrived = on_goal.any(axis=1)
        first = np.argmax(on_goal, axis=1)
        return CriticScore(np.where(arrived, t[first], late).astype(float))

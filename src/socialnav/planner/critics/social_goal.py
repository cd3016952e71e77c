"""Social-goal-distance critic: the paper's SGD objective.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach",
eq. (Social Goal Distance): ``SGD_f = exp(SGD)``, ``SGD`` = distance to the social goal.

Deviations and choices:
- ``SGD`` is measured from the trajectory's end point (the paper's end-point rule) to
  ``ctx.social_goal`` (a :class:`~socialnav.social.goals.SocialGoal`, or any ``(3,)`` pose);
  without a social goal the cost is 0 for every trajectory.
- ``exp`` overflows past ~709; the exponent is clipped at ``max_exponent`` (default 50 m).
  ``relative=True`` scores ``exp(SGD − SGD_now)`` (SGD_now: the robot's current distance): the
  per-cycle constant factor leaves PaCcET's per-cycle normalisation and the ranking unchanged
  while keeping values near 1.
- Optional heading term (not in the paper; off by default): within ``heading_radius`` (m) of a
  stopping goal, ``heading_weight × |wrap(yaw_end − yaw_goal)|`` (rad) is added.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import wrap_angle
from socialnav.core.trajectories import Trajectories
from socialnav.planner.critics.base import CRITICS, Critic, CriticScore

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


def _goal_pose(goal: Any) -> np.ndarray:
    pose = np.asarray(getattr(goal, "pose", goal), dtype=float).reshape(-1)
    return pose if pose.shape == (3,) else np.append(pose[:2], np.nan)


@CRITICS.register("social_goal")
@dataclass(frozen=True)
class SocialGoalCritic(Critic):
    """``SGD_f = exp(SGD)`` at the trajectory end (module docstring for the options).

    Parameters: ``relative`` (bool), ``max_exponent`` (m), ``heading_weight`` (cost/rad, 0 =
    off), ``heading_radius`` (m), ``active_within`` (m or None): when set, the cost is 0 while
    the robot is farther than this from the social goal — far away the navigation objective
    (which already steers to the goal around people) leads, and the straight-line pull of
    ``exp(SGD)`` cannot drag the robot through a group; close by it overcomes the
    interpersonal objective of the people the robot is joining.
    """

    name: ClassVar[str] = "social_goal"
    unit: ClassVar[str] = "exp(m)"

    relative: bool = False
    max_exponent: float = 50.0
    heading_weight: float = 0.0
    heading_radius: float = 0.5
    active_within: float | None = None

    def __post_init__(self) -> None:
        if not 0 < self.max_exponent <= 700:
            raise ConfigurationError("social_goal: max_exponent must be in (0, 700]")
        if self.active_within is not None and not self.active_within > 0:
            raise ConfigurationError("social_goal: active_within must be positive or None")
        if self.heading_weight < 0 or self.heading_radius < 0:
            raise ConfigurationError("social_goal: heading_weight, heading_radius must be >= 0")

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Raw cost ``(N,)`` of the batch (see the class docstring)."""
        n = len(trajs)
        if ctx.social_goal is None:
            return CriticScore(np.zeros(n))
        goal = _goal_pose(ctx.social_goal)
        now = float(np.linalg.norm(ctx.pose[:2] - goal[:2]))
        if self.active_within is not None and now > self.active_within:
            return CriticScore(np.zeros(n))
        end = trajs.end_poses
        sgd = np.linalg.norm(end[:, :2] - goal[:2], axis=1)
        exponent = sgd
        if self.relative:
            exponent = sgd - now
        cost = np.exp(np.minimum(exponent, self.max_exponent))
        waypoint = bool(getattr(ctx.social_goal, "is_waypoint", False))
        if self.heading_weight > 0 and not waypoint and np.isfinite(goal[2]):
            err = np.abs(wrap_angle(end[:, 2] - goal[2]))
            cost = cost + self.heading_weight * err * (sgd <= self.heading_radius)
        return CriticScore(cost)

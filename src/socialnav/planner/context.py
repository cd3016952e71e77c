"""What a critic may read during one control cycle (built once per cycle, read-only)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.cache import CycleCache
from socialnav.world.grid import Costmap

if TYPE_CHECKING:
    from socialnav.social.goals import SocialGoal


@dataclass(frozen=True)
class PlanningContext:
    """The robot's view of the world at one instant.

    - ``pose (3,)`` world pose; ``velocity (3,)`` current body twist ``(vx, vy, wz)``.
    - ``goal (3,)``: the pose the planner steers to this cycle (the social goal when one applies).
    - ``global_path (P, 2)``: the pruned global plan in world coordinates, from the robot onwards.
    - ``costmap``: the inflated costmap the rollout is checked against.
    - ``social``: people, groups, queues, artworks; ``social_goal``: the resolved
      :class:`~socialnav.social.goals.SocialGoal` or ``None``.
    - ``predict_people``: forecast people along the rollout by constant velocity; when ``False``
      people stay where they are now (the paper's end-point evaluation).
    - ``cache``: the typed per-cycle data critics share
      (:class:`~socialnav.planner.cache.CycleCache`: map grids, people distances, ...); the one
      mutable part, filled in ``prepare``.
    """

    pose: FloatArray
    velocity: FloatArray
    goal: FloatArray
    global_path: FloatArray
    costmap: Costmap
    robot: RobotModel
    social: SocialContext = field(default_factory=SocialContext)
    social_goal: SocialGoal | None = None
    predict_people: bool = True
    time: float = 0.0
    cache: CycleCache = field(default_factory=CycleCache, compare=False, repr=False)

    def steers_to_waypoint(self) -> bool:
        """The cycle steers to a social waypoint the robot passes through, not a goal it stops
        at (``SocialGoal.is_waypoint`` at ``goal``): its yaw and tolerance do not stand for the
        real end pose."""
        sg = self.social_goal
        if sg is None or not getattr(sg, "is_waypoint", False):
            return False
        return bool(np.allclose(np.asarray(sg.pose, dtype=float)[:2], self.goal[:2]))

    def people_at(self, t: FloatArray) -> FloatArray:
        """People positions ``(T, K, 2)`` at times ``t (T,)`` seconds from now."""
        positions = self.social.positions()
        if not self.predict_people:
            return np.broadcast_to(positions, (t.shape[0], *positions.shape))
        return positions[None] + t[:, None, None] * self.social.velocities()[None]

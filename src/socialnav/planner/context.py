"""What a critic may read during one control cycle (built once per cycle, read-only)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
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
    - ``extras``: per-cycle shared data that critics compute in ``prepare`` (e.g. BFS grids).
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
    extras: dict[str, Any] = field(default_factory=dict)

    def people_at(self, t: FloatArray) -> FloatArray:
        """People positions ``(T, K, 2)`` at times ``t (T,)`` seconds from now."""
        positions = self.social.positions()
        if not self.predict_people:
            return np.broadcast_to(positions, (t.shape[0], *positions.shape))
        return positions[None] + t[:, None, None] * self.social.velocities()[None]

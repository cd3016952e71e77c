"""The contract between the simulator and a planner: one body twist per control period.

A :class:`Controller` never sees navground: the simulator hands it the robot pose, the body
velocity and the :class:`SocialContext`; it answers with a :class:`ControlOutput`. Planners
register a zero-argument-or-keyword factory in :data:`CONTROLLERS` so that episodes can be run
by name in worker processes (``run_episode(..., controller="paccet")``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.registry import Registry
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext

if TYPE_CHECKING:
    from socialnav.sim.scenario import Scenario

GOAL_REACHED = "GOAL_REACHED"


@dataclass(frozen=True)
class ControlOutput:
    """``cmd (3,)`` body twist ``(vx, vy, wz)`` in m/s and rad/s; ``status`` a planner status name
    (``"OK"``, ``"GOAL_REACHED"``, …); ``diagnostics`` anything the controller wants recorded."""

    cmd: FloatArray
    status: str = "OK"
    diagnostics: Any | None = None


@runtime_checkable
class Controller(Protocol):
    """What the simulator drives: reset once per episode, then one step per control period."""

    def reset(self, scenario: Scenario, robot: RobotModel) -> None: ...

    def step(
        self,
        time: float,
        pose: FloatArray,
        velocity: FloatArray,
        social: SocialContext,
    ) -> ControlOutput:
        """``time`` (s), ``pose (3,)`` world ``(x, y, yaw)``, ``velocity (3,)`` body twist."""
        ...


ControllerFactory = Callable[..., Controller]

#: name → factory ``(**params) -> Controller``; planners add themselves here.
CONTROLLERS: Registry[ControllerFactory] = Registry("controller")


def clamp_to_robot(cmd: FloatArray, robot: RobotModel) -> FloatArray:
    """Clip a body twist ``(3,)`` to the robot's box limits (NaN → 0, no lateral motion on a
    differential drive). Never raises: it runs every control period."""
    c = np.nan_to_num(np.asarray(cmd, dtype=float).reshape(3), nan=0.0, posinf=0.0, neginf=0.0)
    vy_max = robot.max_vel_y if robot.holonomic else 0.0
    return np.array(
        [
            np.clip(c[0], robot.min_vel_x, robot.max_vel_x),
            np.clip(c[1], -vy_max, vy_max),
            np.clip(c[2], -robot.max_vel_theta, robot.max_vel_theta),
        ]
    )

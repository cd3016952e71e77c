"""The contract between the simulator and a planner: one body twist per control period.

A :class:`Controller` never sees navground: the simulator hands it the robot pose, the body
velocity and the :class:`SocialContext`; it answers with a
:class:`~socialnav.planner.local_planner.PlannerResult` (command, status, the evaluation record
when asked, the target it drove toward). Every controller a user can pick by name — our planner
presets, navground's behaviours wrapped as controllers, the simple baselines — is one entry of
:data:`CONTROLLERS`, with its description and display order; the CLI's ``--planner`` choices, the
report's order and the default comparison are views of it (:func:`controller_names`).
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
from socialnav.planner.local_planner import PlannerResult, PlannerStatus

if TYPE_CHECKING:
    from socialnav.sim.scenario import Scenario

GOAL_REACHED = PlannerStatus.GOAL_REACHED


@runtime_checkable
class Controller(Protocol):
    """What the simulator drives: reset once per episode, then one step per control period."""

    def reset(self, scenario: Scenario, robot: RobotModel) -> None:
        """Start an episode of ``scenario`` (already randomized) with ``robot``."""
        ...

    def step(
        self,
        time: float,
        pose: FloatArray,
        velocity: FloatArray,
        social: SocialContext,
    ) -> PlannerResult:
        """``time`` (s), ``pose (3,)`` world ``(x, y, yaw)``, ``velocity (3,)`` body twist.

        Returns the body twist to apply (m/s, rad/s) with a status; never raises on finite
        input (a failure is a status with a safe command)."""
        ...


ControllerFactory = Callable[..., Controller]


@dataclass(frozen=True)
class ControllerEntry:
    """One controller a user can pick by name.

    - ``factory(record=False, **params) -> Controller``; ``record=True`` keeps each cycle's
      evaluation record in the results (for controllers that evaluate candidates);
    - ``description``: one line for listings;
    - ``order``: display order (CLI listing, report tables, default comparisons; ascending);
    - ``compared``: whether ``socialnav compare`` runs it by default (a lower bound such as
      ``go_to_goal`` is runnable by name but not part of the default comparison);
    - ``kind``: ``"stack"`` (our navigation stack), ``"navground"`` (a navground behaviour)
      or ``"baseline"``.
    """

    factory: ControllerFactory
    description: str
    order: int = 1000
    compared: bool = True
    kind: str = "baseline"


#: name → :class:`ControllerEntry`; ``socialnav.sim.stack`` and ``socialnav.sim.baselines``
#: register theirs on import (``socialnav.experiments.planners`` imports both).
CONTROLLERS: Registry[ControllerEntry] = Registry("planner")


def register_controller(
    name: str,
    factory: ControllerFactory,
    description: str,
    *,
    order: int = 1000,
    compared: bool = True,
    kind: str = "baseline",
) -> None:
    """Add a controller under ``name`` (raises ``ConfigurationError`` if the name is taken)."""
    CONTROLLERS.add(name, ControllerEntry(factory, description, order, compared, kind))


def controller_names(compared_only: bool = False) -> list[str]:
    """Registered names in display order (``order``, then name); ``compared_only`` keeps the
    default comparison's."""
    entries = [(CONTROLLERS.get(n).order, n) for n in CONTROLLERS.names()]
    return [n for _, n in sorted(entries) if not compared_only or CONTROLLERS.get(n).compared]


def make_controller(name: str, **params: Any) -> Controller:
    """Build the controller registered as ``name`` (``ConfigurationError`` with the known names
    when there is none)."""
    return CONTROLLERS.get(name).factory(**params)


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

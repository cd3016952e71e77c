"""The local-planner contract shared by :class:`~socialnav.planner.local_planner.LocalPlanner`
and the wrappers around it (:class:`~socialnav.planner.recovery.RecoveringPlanner`): what the
:class:`~socialnav.planner.navigator.Navigator` drives once per control cycle.

Nav2's ``nav2_core::Controller`` plays this role (``computeVelocityCommands``, ``activate`` /
``deactivate``); here it is two methods.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from socialnav.core.robot import RobotModel
from socialnav.planner.context import PlanningContext
from socialnav.planner.local_planner import PlannerResult

__all__ = ["LocalPlannerProtocol"]


@runtime_checkable
class LocalPlannerProtocol(Protocol):
    """One control cycle from a :class:`PlanningContext`; ``reset`` between episodes or goals.

    ``plan`` never raises on a well-typed context: failures are statuses with a zero (or a safe)
    command. With ``record=True`` the result carries the cycle's evaluation record.
    """

    @property
    def robot(self) -> RobotModel:
        """The robot model the planner samples and rolls out for."""
        ...

    def plan(self, ctx: PlanningContext, record: bool = False) -> PlannerResult:
        """The body twist for the cycle described by ``ctx``, with a status."""
        ...

    def reset(self) -> None:
        """Forget per-episode state (latches, oscillation flags, recoveries, critic state)."""
        ...

"""Our navigation stack behind the simulator's :class:`Controller` interface.

Every planner preset (``socialnav.planner.presets.PRESETS``) is registered in ``CONTROLLERS``
under its name, so ``run_episode(scenario, "paccet", …)`` and navground's own YAML experiments
(through the ``SocialNav`` behaviour) can use it.
"""

from __future__ import annotations

import time as clock
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.presets import PRESETS, build_navigator
from socialnav.sim.controller import CONTROLLERS, ControlOutput

if TYPE_CHECKING:
    from socialnav.planner.navigator import Navigator
    from socialnav.sim.scenario import Scenario


class StackController:
    """Global plan + local planner of preset ``preset``; ``record`` keeps per-cycle records."""

    def __init__(self, preset: str = "paccet", record: bool = False) -> None:
        PRESETS.get(preset)
        self.preset = preset
        self.record = record
        self.navigator: Navigator | None = None
        self.plan_seconds: list[float] = []

    def reset(self, scenario: Scenario, robot: RobotModel) -> None:
        self.navigator = build_navigator(
            self.preset,
            robot,
            costmap=scenario.static_costmap(robot),
            goal=np.asarray(scenario.goal, dtype=float),
            social=scenario.social_context(scenario.start),
            record=self.record,
        )
        self.plan_seconds = []

    def step(
        self, time: float, pose: FloatArray, velocity: FloatArray, social: SocialContext
    ) -> ControlOutput:
        if self.navigator is None:
            return ControlOutput(np.zeros(3), "NOT_RESET")
        started = clock.perf_counter()
        result = self.navigator.step(time, pose, velocity, social)
        self.plan_seconds.append(clock.perf_counter() - started)
        return ControlOutput(result.cmd, str(result.status.value), result if self.record else None)

    @property
    def resolved_goal(self) -> FloatArray | None:
        """The goal the navigator plans to (a reachable substitute for a blocked goal)."""
        return None if self.navigator is None else self.navigator.resolved_goal

    @property
    def median_plan_ms(self) -> float:
        return float(np.median(self.plan_seconds) * 1e3) if self.plan_seconds else float("nan")


for _name in PRESETS.names():
    if _name not in CONTROLLERS:
        CONTROLLERS.add(_name, partial(StackController, _name))

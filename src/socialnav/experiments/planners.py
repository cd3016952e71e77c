"""The planners a comparison can run, by name (``--planner NAME``).

Two kinds: our navigation stack with a named local-planner preset (``traditional``,
``weighted_social``, ``proxemic_layer``, ``paccet_paper``, ``paccet``), and navground's own
behaviours driving the robot (``orca``, ``hl``, ``social_force``) — the planners a user would pick
instead of ours.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from socialnav.core.registry import Registry
from socialnav.core.robot import ROBOT_MODELS, RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.presets import PRESETS, build_navigator


@dataclass(frozen=True)
class PlannerEntry:
    """``preset`` names a planner preset of ours; ``behavior`` a navground behaviour."""

    description: str
    preset: str | None = None
    behavior: str | None = None


PLANNERS: Registry[PlannerEntry] = Registry("planner")
for _name in PRESETS.names():
    PLANNERS.add(_name, PlannerEntry(PRESETS.get(_name).description, preset=_name))
PLANNERS.add(
    "orca",
    PlannerEntry("navground ORCA (velocity obstacles) driving the robot", behavior="ORCA"),
)
PLANNERS.add("hl", PlannerEntry("navground HL, the human-like behaviour", behavior="HL"))
PLANNERS.add(
    "social_force",
    PlannerEntry("navground SocialForce (Helbing) driving the robot", behavior="SocialForce"),
)


class StackController:
    """Our navigation stack behind the simulator's controller interface."""

    def __init__(self, preset: str, record: bool = False) -> None:
        self.preset = preset
        self.record = record
        self.navigator: Any = None
        self.plan_seconds: list[float] = []

    def reset(self, scenario: Any, robot: RobotModel) -> None:
        from socialnav.sim.scenario import Scenario

        assert isinstance(scenario, Scenario)
        self.navigator = build_navigator(
            self.preset,
            robot,
            costmap=scenario.static_costmap(robot),
            goal=np.asarray(scenario.goal_pose(), dtype=float),
            social=scenario.social_context(),
        )
        self.plan_seconds = []

    def step(self, time: float, pose: np.ndarray, velocity: np.ndarray, social: SocialContext):
        import time as clock

        from socialnav.sim.controller import ControlOutput

        started = clock.perf_counter()
        result = self.navigator.step(time, pose, velocity, social, record=self.record)
        self.plan_seconds.append(clock.perf_counter() - started)
        return ControlOutput(result.cmd, str(result.status.value), result if self.record else None)


def run_planner_episode(spec: Any, record_diagnostics: bool = False) -> Any:
    """Run one :class:`~socialnav.experiments.suite.EpisodeSpec` with its planner."""
    from socialnav.sim.runner import run_episode
    from socialnav.sim.scenario import load_scenario

    entry = PLANNERS.get(spec.planner)
    scenario = load_scenario(spec.scenario)
    if spec.randomize:
        scenario = scenario.randomize(spec.seed, vary_group_size=True)
    elif scenario.has_jitter():
        scenario = scenario.randomize(spec.seed)
    robot = ROBOT_MODELS[spec.robot]
    controller: Any = entry.behavior
    if entry.preset is not None:
        controller = StackController(entry.preset, record=record_diagnostics)
    result = run_episode(
        scenario,
        controller,
        robot,
        seed=spec.seed,
        humans=spec.humans,
        record_diagnostics=record_diagnostics,
    )
    result.record.meta.update({"planner": spec.planner, "robot": spec.robot, "seed": spec.seed})
    if isinstance(controller, StackController) and controller.plan_seconds:
        result.record.meta["planner_ms_median"] = float(np.median(controller.plan_seconds) * 1e3)
    return result


def scenario_name(path_or_name: str) -> str:
    return Path(path_or_name).stem

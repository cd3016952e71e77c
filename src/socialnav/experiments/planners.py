"""The planners a comparison can run, by name (``--planner NAME``).

Two kinds: our navigation stack with a named local-planner preset (``traditional``,
``weighted_social``, ``proxemic_layer``, ``paccet_paper``, ``paccet``), and navground's own
behaviours driving the robot (``orca``, ``hl``, ``social_force``) — the planners a user would pick
instead of ours.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from socialnav.core.registry import Registry
from socialnav.core.robot import ROBOT_MODELS
from socialnav.planner.presets import PRESETS
from socialnav.sim.scenario import Jitter
from socialnav.sim.stack import StackController

# The randomized suite: people moved by N(0, 0.15 m), walking speeds by N(0, 0.1 m/s), walkers'
# starts by ±0.3 m along their line; group sizes vary by ±1 (``vary_group_sizes``).
RANDOMIZED_JITTER = Jitter(position_sigma=0.15, speed_sigma=0.1, start_shift=0.3)


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


def run_planner_episode(spec: Any, record_diagnostics: bool = False) -> Any:
    """Run one :class:`~socialnav.experiments.suite.EpisodeSpec` with its planner."""
    from socialnav.sim.runner import run_episode
    from socialnav.sim.scenario import load_scenario

    entry = PLANNERS.get(spec.planner)
    if spec.scenario.startswith("generated:"):
        from socialnav.sim.generate import generate

        scenario = generate(spec.scenario.removeprefix("generated:"), spec.seed)
    else:
        scenario = load_scenario(spec.scenario)
    if spec.randomize:
        scenario = scenario.model_copy(update={"jitter": RANDOMIZED_JITTER})
    robot = ROBOT_MODELS[spec.robot]
    controller: Any = entry.behavior
    if entry.preset is not None:
        controller = StackController(entry.preset, record=record_diagnostics)
    # run_episode applies the scenario's jitter from the seed (a no-op for unjittered scenarios).
    result = run_episode(
        scenario,
        controller,
        robot,
        seed=spec.seed,
        humans=spec.humans,
        record_diagnostics=record_diagnostics,
        vary_group_sizes=spec.randomize,
    )
    result.record.meta.update({"planner": spec.planner, "robot": spec.robot, "seed": spec.seed})
    if isinstance(controller, StackController):
        result.record.meta["planner_ms_median"] = controller.median_plan_ms
    return result

"""The planners a comparison can run, by name (``--planner NAME``): a view of the one controller
registry, :data:`socialnav.sim.controller.CONTROLLERS`.

Its entries: our navigation stack with a named local-planner preset (``traditional``,
``weighted_social``, ``proxemic_layer``, ``paccet_paper``, ``paccet``), navground's own behaviours
wrapped as controllers (``orca``, ``hl``, ``social_force``) — the planners a user would pick
instead of ours — and ``go_to_goal``, a lower bound runnable by name but not compared by default.
"""

from __future__ import annotations

from socialnav.core.robot import ROBOT_MODELS
from socialnav.experiments.suite import EpisodeSpec
from socialnav.sim import baselines as _baselines  # noqa: F401  (registers navground, go_to_goal)
from socialnav.sim import stack as _stack  # noqa: F401  (registers the planner presets)
from socialnav.sim.controller import (
    CONTROLLERS,
    ControllerEntry,
    controller_names,
    make_controller,
)
from socialnav.sim.runner import EpisodeResult
from socialnav.sim.scenario import Jitter

__all__ = [
    "CONTROLLERS",
    "RANDOMIZED_JITTER",
    "ControllerEntry",
    "compared_planners",
    "planner_names",
    "run_planner_episode",
]

# The randomized suite: people moved by N(0, 0.15 m), walking speeds by N(0, 0.1 m/s), walkers'
# starts by ±0.3 m along their line; group sizes vary by ±1 (``vary_group_sizes``).
RANDOMIZED_JITTER = Jitter(position_sigma=0.15, speed_sigma=0.1, start_shift=0.3)


def planner_names() -> list[str]:
    """Every registered planner, in display order (the CLI's ``--planner`` choices)."""
    return controller_names()


def compared_planners() -> list[str]:
    """The planners ``socialnav compare`` runs by default, in display order (the report's)."""
    return controller_names(compared_only=True)


def run_planner_episode(spec: EpisodeSpec, record_diagnostics: bool = False) -> EpisodeResult:
    """Run one :class:`~socialnav.experiments.suite.EpisodeSpec` with its planner."""
    from socialnav.sim.runner import run_episode
    from socialnav.sim.scenario import load_scenario

    controller = make_controller(spec.planner, record=record_diagnostics)
    if spec.scenario.startswith("generated:"):
        from socialnav.sim.generate import generate

        scenario = generate(spec.scenario.removeprefix("generated:"), spec.seed)
    else:
        scenario = load_scenario(spec.scenario)
    if spec.randomize:
        scenario = scenario.model_copy(update={"jitter": RANDOMIZED_JITTER})
    robot = ROBOT_MODELS[spec.robot]
    # run_episode applies the scenario's jitter from the seed (a no-op for unjittered scenarios).
    result = run_episode(
        scenario,
        controller,
        robot,
        seed=spec.seed,
        humans=spec.humans,
        record_diagnostics=record_diagnostics,
        vary_group_sizes=spec.randomize,
        context=getattr(spec, "context", "given"),
    )
    result.record.meta.update({"planner": spec.planner, "robot": spec.robot, "seed": spec.seed})
    result.record.meta["planner_ms_median"] = result.step_ms_median
    return result

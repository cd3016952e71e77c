"""Where the environments' episodes come from: a scene source draws a scenario from the env's RNG.

A *scene source* is any callable ``(rng: numpy.random.Generator) -> Scenario``. The built-in one,
:class:`ScenarioPool`, draws one of the packaged scenarios of the requested families and applies
the randomized suite's jitter (``socialnav compare --suite randomized``) with a seed drawn from
the same RNG, so ``env.reset(seed=s)`` fixes the whole episode. A scenario generator (seeded,
one scene per seed) plugs in the same way: ``SocialNavEnv(scenes=lambda rng: generate(family,
seed=int(rng.integers(2**31))))``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.core.success import FAMILIES
from socialnav.experiments.planners import RANDOMIZED_JITTER
from socialnav.sim.scenario import Scenario, builtin_scenarios, load_scenario

__all__ = ["FAMILY_GROUPS", "ScenarioPool", "SceneSource"]

SceneSource = Callable[[np.random.Generator], Scenario]

#: the per-family environments: name → scenario families
FAMILY_GROUPS: dict[str, tuple[str, ...]] = {
    "Hallway": ("hallway",),
    "Gallery": ("gallery_present", "gallery_activity"),
    "Queue": ("queue",),
    "Group": ("group",),
}


class ScenarioPool:
    """Draw one of ``scenarios`` (names of built-in scenarios or YAML paths; default: every
    built-in scenario of ``families``, default all), jittered when ``randomize``.

    Raises :class:`ConfigurationError` for an unknown family or scenario, or an empty pool.
    """

    def __init__(
        self,
        scenarios: Sequence[str | Path] | None = None,
        families: Sequence[str] | None = None,
        randomize: bool = True,
    ) -> None:
        if families is not None:
            unknown = sorted(set(families) - set(FAMILIES.names()))
            if unknown:
                raise ConfigurationError(f"unknown families {unknown}; known: {FAMILIES.names()}")
        names = list(scenarios) if scenarios is not None else builtin_scenarios()
        loaded = [load_scenario(n) for n in names]
        if families is not None:
            loaded = [s for s in loaded if s.family in families]
        if not loaded:
            raise ConfigurationError(f"no scenario in {names} belongs to families {families}")
        self.scenarios = loaded
        self.randomize = randomize

    @property
    def names(self) -> list[str]:
        return [s.name for s in self.scenarios]

    def by_name(self, name: str) -> Scenario:
        for s in self.scenarios:
            if s.name == name:
                return s
        raise ConfigurationError(f"scenario {name!r} is not in this pool: {self.names}")

    def draw(self, rng: np.random.Generator, scenario: Scenario) -> Scenario:
        """``scenario`` with the randomized suite's jitter from a seed drawn from ``rng``."""
        seed = int(rng.integers(2**31))
        if not self.randomize:
            return scenario.randomize(seed)  # the scenario's own jitter (often none)
        jittered = scenario.model_copy(update={"jitter": RANDOMIZED_JITTER})
        return jittered.randomize(seed, vary_group_sizes=True)

    def __call__(self, rng: np.random.Generator) -> Scenario:
        return self.draw(rng, self.scenarios[int(rng.integers(len(self.scenarios)))])

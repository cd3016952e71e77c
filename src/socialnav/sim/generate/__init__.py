"""Seeded scene generators: the generated suite (one module per scenario family).

``generate(family, seed)`` returns a valid :class:`~socialnav.sim.scenario.Scenario` (export it
with :func:`socialnav.sim.generate.common.scenario_yaml`), the same for the same arguments. Every
scene carries ``feasibility`` facts per robot model (largest clearance the geometry allows from
each person, whether collision-free passage exists, whether the social spot is reachable) and
``success`` options: the generated suite's arrival tolerance (0.10 m, and 0.2 rad at social
spots) and, per robot, each condition the geometry makes impossible marked not required with
the reason. Scenes whose task itself is infeasible (no passage, spot unreachable) are drawn
again from the same seed's stream.

Seeds below :data:`REPORTING_SEED` are for development (tuning); the report quotes seeds from
:data:`REPORTING_SEED` up. Ranges per family: see each module's docstring.
"""

from __future__ import annotations

from socialnav.sim.generate.common import (
    GENERATORS,
    REPORTING_SEED,
    Generator,
    generate,
    scenario_yaml,
)

# Importing the family modules registers them (one module per family).
from socialnav.sim.generate import (  # noqa: F401  isort: skip
    crowdnav,
    gallery_pass,
    gallery_present,
    group_join,
    group_lead,
    hallway,
    mixed,
    queue,
)

__all__ = ["GENERATORS", "REPORTING_SEED", "Generator", "generate", "scenario_yaml"]

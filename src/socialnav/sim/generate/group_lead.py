"""Generated groups, "lead": the robot takes the leader's spot of a group gathered on one side.

Ranges: as :mod:`group_join` (2–6 members, radius 0.6–1.5 m, uneven gaps), but the members of
groups of three or more stand within an arc of 90–200°, so the widest gap is the leader's
place (the paper's squeezed group); ``mode: lead``. Success and feasibility as for joining.
"""

from __future__ import annotations

import numpy as np

from socialnav.sim.generate.common import GENERATORS, Generator, uniform
from socialnav.sim.generate.group_join import draw_group_scene
from socialnav.sim.scenario import Scenario

ARC = (np.radians(90.0), np.radians(200.0))


def draw(rng: np.random.Generator, name: str) -> Scenario:
    return draw_group_scene(rng, name, "lead", uniform(rng, *ARC))


GENERATORS.add("group_lead", Generator("group_lead", __doc__ or "", draw))

"""O-formations for the group generators: members on a circle with uneven gaps."""

from __future__ import annotations

import math

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.sim.generate.common import Infeasible, r3, uniform, xy
from socialnav.sim.scenario import GroupSpec, PersonSpec

MEMBERS = (2, 6)
RADIUS = (0.6, 1.5)
MIN_CHORD = 0.6  # m between neighbouring members' centres (shoulder to shoulder)


def draw_group(
    rng: np.random.Generator,
    center: FloatArray,
    mode: str,
    first_id: int = 1,
    arc: float = 2 * math.pi,
) -> tuple[GroupSpec, list[PersonSpec], float]:
    """Members facing ``center`` on a circle of radius in ``RADIUS``, at uneven angles within an
    ``arc`` (rad; ``lead`` scenes squeeze the members into a smaller arc); returns the group
    spec, members and the radius. A pair stands face to face (its circle's diameter)."""
    n = int(rng.integers(MEMBERS[0], MEMBERS[1] + 1))
    radius = uniform(rng, *RADIUS)
    if n == 2:
        a0 = uniform(rng, -math.pi, math.pi)
        angles = np.array([a0, a0 + math.pi])
    else:
        # uneven gaps: Dirichlet-distributed shares of the arc, rejected if two are too close
        min_gap = 2 * math.asin(min(MIN_CHORD / (2 * radius), 1.0))
        for _ in range(50):
            shares = rng.dirichlet(np.full(n, 1.5))
            if arc < 2 * math.pi:
                gaps = shares[: n - 1] / shares[: n - 1].sum() * arc
                angles = np.concatenate([[0.0], np.cumsum(gaps)])
            else:
                angles = np.concatenate([[0.0], np.cumsum(shares[:-1] * arc)])
                gaps = np.diff(np.concatenate([angles, [2 * math.pi]]))
            if np.min(gaps) >= min_gap:
                break
        else:
            raise Infeasible("members too close on the circle")
        angles = angles + uniform(rng, -math.pi, math.pi)
    people = []
    for k, a in enumerate(angles):
        p = center + radius * np.array([math.cos(a), math.sin(a)])
        people.append(PersonSpec(id=first_id + k, position=xy(p), yaw=r3(a + math.pi)))
    return GroupSpec(members=[p.id for p in people], mode=mode), people, radius

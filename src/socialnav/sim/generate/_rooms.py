"""Rooms with an artwork or a desk on/near a wall: shared by the gallery, queue and mixed
generators."""

from __future__ import annotations

import math

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.sim.generate.common import Infeasible, uniform

ROOM = (9.0, 14.0)  # side lengths (m)


def draw_room(rng: np.random.Generator) -> tuple[float, float]:
    return uniform(rng, *ROOM), uniform(rng, *ROOM)


def wall_frame(
    width: float, height: float, wall: int, along: float
) -> tuple[FloatArray, float, FloatArray]:
    """A point on wall ``wall`` (0 south, 1 east, 2 north, 3 west) at fraction ``along``, the
    inward normal's yaw, and the wall's tangent (2,)."""
    if wall == 0:
        p, facing = np.array([along * width, 0.0]), math.pi / 2
    elif wall == 1:
        p, facing = np.array([width, along * height]), math.pi
    elif wall == 2:
        p, facing = np.array([along * width, height]), -math.pi / 2
    else:
        p, facing = np.array([0.0, along * height]), 0.0
    tangent = np.array([-math.sin(facing), math.cos(facing)])
    return p, facing, tangent


def random_free_point(
    rng: np.random.Generator,
    width: float,
    height: float,
    avoid: list[tuple[FloatArray, float]],
    margin: float = 1.0,
    tries: int = 200,
) -> FloatArray:
    """A uniform point in the room ``margin`` m from the walls and outside every
    ``(centre, radius)`` of ``avoid``."""
    for _ in range(tries):
        p = np.array([uniform(rng, margin, width - margin), uniform(rng, margin, height - margin)])
        if all(np.linalg.norm(p - c) >= r for c, r in avoid):
            return p
    raise Infeasible("no free start point")


def inside_room(p: FloatArray, width: float, height: float, margin: float) -> bool:
    return bool(margin <= p[0] <= width - margin and margin <= p[1] <= height - margin)

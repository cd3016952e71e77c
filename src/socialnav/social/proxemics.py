"""Proxemics: Hall's zones and person-distance helpers.

Hall, "The Hidden Dimension" (1966), as used by Banisetty et al. (the interpersonal-distance
objective acts within 1.5 m). Distances are centre-to-centre unless a name says ``edge``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.geometry import FloatArray

#: Hall's zone boundaries, centre-to-centre (m), as fixed in the project's scenarios.md.
INTIMATE = 0.45
PERSONAL = 1.2
SOCIAL = 3.6
#: The paper's interpersonal-distance threshold (m).
ID_THRESHOLD = 1.5

ZONES = ("intimate", "personal", "social", "public")


def distances(points: ArrayLike, people: ArrayLike) -> FloatArray:
    """Centre-to-centre distances from points ``(..., 2)`` to people ``(K, 2)``: ``(..., K)``."""
    p = np.asarray(points, dtype=float)
    h = np.asarray(people, dtype=float)
    return np.linalg.norm(p[..., None, :] - h, axis=-1)


def edge_distances(
    points: ArrayLike, people: ArrayLike, people_radii: ArrayLike, robot_radius: float
) -> FloatArray:
    """Gap between a robot disc and person discs, ``(..., K)``, clipped at 0 (overlap)."""
    d = distances(points, people) - np.asarray(people_radii, dtype=float) - robot_radius
    return np.maximum(d, 0.0)


def hall_zone(distance: ArrayLike) -> np.ndarray:
    """Index into :data:`ZONES` of each centre-to-centre distance (m), same shape as input."""
    return np.searchsorted(np.array([INTIMATE, PERSONAL, SOCIAL]), np.asarray(distance), "right")

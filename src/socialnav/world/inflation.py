"""costmap_2d inflation: obstacle distance → cost, via one Euclidean distance transform.

For the distance ``d`` (m) from a cell centre to the nearest lethal cell centre (the
costmap_2d convention: distances between cell centres):

- ``d == 0`` → LETHAL 254,
- ``0 < d <= inscribed_radius`` → INSCRIBED 253,
- ``inscribed_radius < d <= inflation_radius`` → ``floor(252 · exp(-k (d - inscribed_radius)))``,
- beyond → FREE 0.

Differences from costmap_2d's InflationLayer, on purpose:

- costmap_2d inflates out to ``ceil(inflation_radius / resolution)`` *cells*, so with a radius
  that is not a multiple of the resolution it reaches slightly further; here the cut is exactly
  at ``inflation_radius`` metres.
- Unknown cells (UNKNOWN 255) are not obstacles. As in costmap_2d with ``inflate_unknown=False``
  they stay UNKNOWN unless the inflation cost there is >= INSCRIBED (near an obstacle), and with
  ``inflate_unknown=True`` any positive inflation cost overwrites them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.ndimage import distance_transform_edt

from socialnav.core.errors import InvalidInputError
from socialnav.world.grid import FREE, INSCRIBED, LETHAL, UNKNOWN, Costmap, GridGeometry

# Absorbs floating-point noise in distances computed as (cells × resolution).
_EPS = 1e-9


def _check_params(inscribed_radius: float, inflation_radius: float, k: float) -> None:
    if not (np.isfinite(inscribed_radius) and inscribed_radius >= 0):
        raise InvalidInputError(f"inscribed_radius must be finite and >= 0, got {inscribed_radius}")
    if not (np.isfinite(inflation_radius) and inflation_radius >= inscribed_radius):
        raise InvalidInputError(
            f"inflation_radius ({inflation_radius}) must be finite and >= inscribed_radius "
            f"({inscribed_radius})"
        )
    if not (np.isfinite(k) and k >= 0):
        raise InvalidInputError(f"cost_scaling_factor must be finite and >= 0, got {k}")


def inflation_cost(
    distance: ArrayLike,
    inscribed_radius: float,
    cost_scaling_factor: float = 10.0,
    inflation_radius: float = 0.55,
) -> NDArray[np.uint8]:
    """costmap_2d cost ``(...)`` uint8 for obstacle distances ``(...)`` in metres (>= 0)."""
    _check_params(inscribed_radius, inflation_radius, cost_scaling_factor)
    d = np.asarray(distance, dtype=float)
    if not np.all(np.isfinite(d)) or np.any(d < 0):
        raise InvalidInputError("distance must be finite and >= 0")
    return _cost_unchecked(d, inscribed_radius, cost_scaling_factor, inflation_radius)


def _cost_unchecked(
    d: NDArray[np.float64], r_ins: float, k: float, r_inf: float
) -> NDArray[np.uint8]:
    decay = np.floor((INSCRIBED - 1) * np.exp(-k * np.maximum(d - r_ins, 0.0)))
    cost = np.where(d <= r_inf + _EPS, decay, FREE)
    cost = np.where(d <= r_ins + _EPS, INSCRIBED, cost)
    cost = np.where(d <= 0.0, LETHAL, cost)
    return cost.astype(np.uint8)


def circumscribed_cost(
    circumscribed_radius: float,
    inscribed_radius: float,
    cost_scaling_factor: float = 10.0,
    inflation_radius: float = 0.55,
    resolution: float | None = None,
) -> int:
    """Cost at the circumscribed radius: below it no footprint orientation can touch a lethal cell.

    With ``resolution`` the radius is rounded *up* to whole cells first (costmap_2d's
    ``cellDistance``), which lowers the threshold and keeps the footprint-check shortcut
    conservative. Returns 0 when the circumscribed radius lies beyond ``inflation_radius``: the
    shortcut then never applies (costmap_2d warns about this configuration).
    """
    if not (np.isfinite(circumscribed_radius) and circumscribed_radius >= inscribed_radius):
        raise InvalidInputError(
            f"circumscribed_radius ({circumscribed_radius}) must be >= inscribed_radius "
            f"({inscribed_radius})"
        )
    d = circumscribed_radius
    if resolution is not None:
        if not (np.isfinite(resolution) and resolution > 0):
            raise InvalidInputError(f"resolution must be positive, got {resolution}")
        d = float(np.ceil(d / resolution - _EPS)) * resolution
    return int(inflation_cost(d, inscribed_radius, cost_scaling_factor, inflation_radius))


def obstacle_distance(occupied: NDArray[np.bool_], resolution: float) -> NDArray[np.float64]:
    """Distance (m) ``(rows, cols)`` from each cell centre to the nearest occupied cell centre.

    ``inf`` everywhere when nothing is occupied.
    """
    if not occupied.any():
        return np.full(occupied.shape, np.inf)
    return distance_transform_edt(~occupied, sampling=resolution)


def inflate(
    occupied: ArrayLike,
    geometry: GridGeometry,
    inscribed_radius: float,
    inflation_radius: float = 0.55,
    cost_scaling_factor: float = 10.0,
    unknown: ArrayLike | None = None,
    *,
    inflate_unknown: bool = False,
) -> Costmap:
    """Inflated costmap from an obstacle mask ``occupied (rows, cols) bool``.

    ``unknown (rows, cols) bool`` marks NO_INFORMATION cells (occupied wins where both are set).
    """
    _check_params(inscribed_radius, inflation_radius, cost_scaling_factor)
    occ = np.asarray(occupied, dtype=bool)
    if occ.shape != geometry.shape:
        raise InvalidInputError(f"occupied must have shape {geometry.shape}, got {occ.shape}")
    dist = obstacle_distance(occ, geometry.resolution)
    costs = _cost_unchecked(dist, inscribed_radius, cost_scaling_factor, inflation_radius)
    if unknown is not None:
        unk = np.asarray(unknown, dtype=bool)
        if unk.shape != geometry.shape:
            raise InvalidInputError(f"unknown must have shape {geometry.shape}, got {unk.shape}")
        overwrite = costs > FREE if inflate_unknown else costs >= INSCRIBED
        costs = np.where(unk & ~occ & ~overwrite, np.uint8(UNKNOWN), costs)
    return Costmap(costs.astype(np.uint8), geometry)

"""Costmap operations: the local rolling window and max-combination of layers (costmap_2d)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import as_points
from socialnav.world.grid import UNKNOWN, Costmap, GridGeometry


def crop(costmap: Costmap, center_xy: ArrayLike, size_m: float | tuple[float, float]) -> Costmap:
    """Local rolling window of ``size_m`` (m; scalar or ``(width, height)``) around ``center_xy``.

    As costmap_2d's rolling window, the window's origin snaps to the parent grid so cells line up
    with it (no resampling); the window is ``round(size / res)`` cells per side (at least 1).
    Cells off the parent map read UNKNOWN.
    """
    c = as_points(center_xy, "center_xy")
    if c.shape != (2,):
        raise InvalidInputError(f"center_xy must have shape (2,), got {c.shape}")
    size = np.broadcast_to(np.asarray(size_m, dtype=float), (2,))
    if not np.all(np.isfinite(size)) or np.any(size <= 0):
        raise InvalidInputError(f"size_m must be positive, got {size_m}")
    geo = costmap.geometry
    res = geo.resolution
    cols, rows = np.maximum(np.rint(size / res).astype(int), 1)
    # Lower-left cell index of the window in the parent grid (costmap_2d updateOrigin).
    c0 = int(np.floor((c[0] - geo.origin[0]) / res - cols / 2.0 + 1e-9))
    r0 = int(np.floor((c[1] - geo.origin[1]) / res - rows / 2.0 + 1e-9))
    out = np.full((rows, cols), UNKNOWN, dtype=np.uint8)
    sr0, sr1 = max(r0, 0), min(r0 + rows, geo.shape[0])
    sc0, sc1 = max(c0, 0), min(c0 + cols, geo.shape[1])
    if sr0 < sr1 and sc0 < sc1:
        out[sr0 - r0 : sr1 - r0, sc0 - c0 : sc1 - c0] = costmap.costs[sr0:sr1, sc0:sc1]
    window = GridGeometry(
        shape=(int(rows), int(cols)),
        resolution=res,
        origin=(geo.origin[0] + c0 * res, geo.origin[1] + r0 * res),
    )
    return Costmap(out, window)


def combine_max(
    costmap: Costmap, layer_costs: ArrayLike, *, overwrite_unknown: bool = False
) -> Costmap:
    """Write a layer ``(rows, cols)`` uint8 into ``costmap`` by maximum.

    UNKNOWN cells of the layer are skipped (costmap_2d ``updateWithMax``). UNKNOWN cells of the
    costmap are kept unless ``overwrite_unknown`` — the social_navigation_layers behaviour
    (those layers skip NO_INFORMATION cells); ``overwrite_unknown=True`` is ``updateWithMax``.
    """
    layer = np.asarray(layer_costs)
    if layer.shape != costmap.geometry.shape:
        raise InvalidInputError(
            f"layer_costs must have shape {costmap.geometry.shape}, got {layer.shape}"
        )
    if layer.dtype != np.uint8:
        raise InvalidInputError(f"layer_costs must be uint8, got {layer.dtype}")
    base = costmap.costs
    combined: NDArray[np.uint8] = np.where(layer == UNKNOWN, base, np.maximum(base, layer))
    if overwrite_unknown:
        combined = np.where((base == UNKNOWN) & (layer != UNKNOWN), layer, combined)
    return Costmap(combined.astype(np.uint8), costmap.geometry)


def add_obstacle_discs(
    costmap: Costmap,
    discs: ArrayLike,
    inscribed_radius: float,
    inflation_radius: float = 0.55,
    cost_scaling_factor: float = 10.0,
) -> Costmap:
    """Mark discs ``(D, 3)`` ``[x, y, r]`` as obstacles and re-inflate — costmap_2d's obstacle
    layer seeing people in the laser scan, the way the ROS planner avoids people it treats as
    obstacles. Existing LETHAL and UNKNOWN cells are kept."""
    from socialnav.world.grid import LETHAL
    from socialnav.world.inflation import inflate
    from socialnav.world.raster import rasterize

    d = np.asarray(discs, dtype=float).reshape(-1, 3)
    if d.shape[0] == 0:
        return costmap
    occupied = (costmap.costs == LETHAL) | rasterize(costmap.geometry, discs=d)
    unknown = costmap.costs == UNKNOWN
    return inflate(
        occupied,
        costmap.geometry,
        inscribed_radius,
        inflation_radius,
        cost_scaling_factor,
        unknown=unknown,
    )

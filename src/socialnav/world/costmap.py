"""Costmap operations: the local rolling window and max-combination of layers (costmap_2d)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core import compiled
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
    *,
    reuse_static: bool = False,
) -> Costmap:
    """Mark discs ``(D, 3)`` ``[x, y, r]`` as obstacles and re-inflate — costmap_2d's obstacle
    layer seeing people in the laser scan, the way the ROS planner avoids people it treats as
    obstacles. Existing LETHAL and UNKNOWN cells are kept.

    ``reuse_static=True`` (for a fixed map called on again, e.g. the global costmap at every
    replan): the inflation of the map's own LETHAL cells is computed once and kept, and only
    the cells within the inflation radius of a disc are recomputed — the same costmap, cell
    for cell (:func:`_disc_inflation`); it falls back to the full inflation when that cannot
    be guaranteed."""
    from socialnav.world.grid import LETHAL
    from socialnav.world.inflation import inflate
    from socialnav.world.raster import rasterize

    d = np.asarray(discs, dtype=float).reshape(-1, 3)
    if d.shape[0] == 0:
        return costmap
    raster = rasterize(costmap.geometry, discs=d)
    occupied = (costmap.costs == LETHAL) | raster
    unknown = costmap.costs == UNKNOWN
    if reuse_static:
        fast = _disc_inflation(
            costmap, d, raster, occupied, unknown, inscribed_radius, inflation_radius,
            cost_scaling_factor,
        )  # fmt: skip
        if fast is not None:
            return fast
    return inflate(
        occupied,
        costmap.geometry,
        inscribed_radius,
        inflation_radius,
        cost_scaling_factor,
        unknown=unknown,
    )


@compiled.jit
def _boundary(raster, i, j):  # type: ignore[no-untyped-def]
    """A raster cell with a 4-neighbour outside the raster (or the grid): ``raster & ~interior``
    of :func:`_disc_inflation`."""
    if not raster[i, j]:
        return False
    rows, cols = raster.shape
    if i == 0 or j == 0 or i == rows - 1 or j == cols - 1:
        return True
    return not (raster[i - 1, j] and raster[i + 1, j] and raster[i, j - 1] and raster[i, j + 1])


@compiled.jit
def _disc_finish(raster, costs, raw):  # type: ignore[no-untyped-def]
    """In place: disc cells LETHAL; UNKNOWN map cells outside the discs stay UNKNOWN unless
    inflated to INSCRIBED or more (:func:`_disc_inflation`'s last two steps)."""
    rows, cols = raw.shape
    for i in range(rows):
        for j in range(cols):
            if raster[i, j]:
                raw[i, j] = 254
            elif costs[i, j] == 255 and raw[i, j] < 253:
                raw[i, j] = 255


@compiled.jit
def _disc_costs(raster, boxes, reach, table, raw):  # type: ignore[no-untyped-def]
    """:func:`_disc_inflation`'s per-disc loop: for each disc box ``(r0, r1, c0, c1)`` the
    squared offset of every cell within ``reach`` to the nearest boundary cell
    (:func:`_boundary` of ``raster``) in the box, its
    cost from ``table``, maximum into ``raw`` (integers and maxima: identical). The nearest
    is found row by row: ``min`` over the box's rows ``i'`` of ``(i - i')²`` plus the squared
    column offset to the nearest boundary cell of row ``i'`` (two sweeps), the same minimum
    as over every boundary cell."""
    rows, cols = raw.shape
    last = table.size - 1
    far = 1 << 40
    for d in range(boxes.shape[0]):
        r0, r1, c0, c1 = boxes[d, 0], boxes[d, 1], boxes[d, 2], boxes[d, 3]
        if c0 >= c1 or r0 >= r1:
            continue
        v0, v1 = max(c0 - reach, 0), min(c1 + reach, cols)
        width = v1 - v0
        near = np.full((r1 - r0, width), far, dtype=np.int64)  # column offset, squared
        used = np.zeros(r1 - r0, dtype=np.bool_)
        for i in range(r0, r1):
            row = near[i - r0]
            at = -1  # last boundary column seen (left to right)
            for j in range(v0, v1):
                if c0 <= j < c1 and _boundary(raster, i, j):
                    at = j
                    used[i - r0] = True
                if at >= 0:
                    row[j - v0] = (j - at) * (j - at)
            if not used[i - r0]:
                continue
            at = -1
            for j in range(v1 - 1, v0 - 1, -1):
                if c0 <= j < c1 and _boundary(raster, i, j):
                    at = j
                if at >= 0:
                    q = (at - j) * (at - j)
                    if q < row[j - v0]:
                        row[j - v0] = q
        if not used.any():
            continue
        for i in range(max(r0 - reach, 0), min(r1 + reach, rows)):
            for j in range(v0, v1):
                best = last
                for k in range(r1 - r0):
                    if not used[k]:
                        continue
                    dr = i - (r0 + k)
                    n = dr * dr + near[k, j - v0]
                    if n < best:
                        best = n
                cost = table[best]
                if cost > raw[i, j]:
                    raw[i, j] = cost


# Inflation of a static map's own LETHAL cells, kept per map (the costs array itself is held,
# so an entry can only match the very array it was computed from).
_STATIC_INFLATION: dict[
    tuple[int, float, float, float], tuple[NDArray[np.uint8], NDArray[np.uint8]]
] = {}


@lru_cache(maxsize=16)
def _cost_by_squared_offset(
    resolution: float, r_ins: float, k: float, r_inf: float
) -> NDArray[np.uint8] | None:
    """The inflation cost ``(M,)`` of a cell whose nearest obstacle cell is ``n = dr² + dc²``
    cells away (index ``n``; beyond the table: FREE), computed from the distance exactly as
    :func:`socialnav.world.inflation.obstacle_distance` (SciPy's EDT) does for that offset:
    ``sqrt((dr·res)² + (dc·res)²)``. ``None`` when two offsets with the same ``n`` give
    different costs (rounding at a cost step), i.e. when the cost is not a function of ``n``.
    """
    from socialnav.world.inflation import _cost_unchecked

    reach = int(np.ceil(r_inf / resolution)) + 2
    ga, gb = np.meshgrid(np.arange(reach + 1), np.arange(reach + 1), indexing="ij")
    a, b = ga.ravel(), gb.ravel()
    dt = np.stack([a, b]).astype(np.float64) * resolution
    np.multiply(dt, dt, dt)
    dist = np.sqrt(np.add.reduce(dt, axis=0))
    cost = _cost_unchecked(dist, r_ins, k, r_inf)
    n = a * a + b * b
    size = reach * reach + 1  # every n below this has all its offsets in the table
    lo = np.full(size, 255, dtype=np.int64)
    hi = np.full(size, -1, dtype=np.int64)
    inside = n < size
    np.minimum.at(lo, n[inside], cost[inside])
    np.maximum.at(hi, n[inside], cost[inside])
    present = hi >= 0
    if np.any(lo[present] != hi[present]) or cost[n >= size].any():
        return None  # ambiguous, or the table does not reach FREE
    table = np.zeros(size, dtype=np.uint8)
    table[present] = hi[present]
    return table


def _disc_inflation(
    costmap: Costmap,
    discs: NDArray[np.float64],
    raster: NDArray[np.bool_],
    occupied: NDArray[np.bool_],
    unknown: NDArray[np.bool_],
    r_ins: float,
    r_inf: float,
    k: float,
) -> Costmap | None:
    """``inflate(occupied, ...)`` from the kept inflation of the map's LETHAL cells: the cost
    falls with the distance to the nearest obstacle, so the cost of the union is the maximum
    of the map's and the discs' costs, and a disc changes only the cells within ``r_inf`` of
    it. The discs' part is the cost of the squared cell offset ``n`` to the nearest disc cell
    (a boundary cell: an interior one always has a nearer neighbour), exact when the cost is
    a function of ``n`` (:func:`_cost_by_squared_offset`, else ``None``)."""
    from socialnav.world.grid import INSCRIBED, LETHAL
    from socialnav.world.inflation import _check_params, _cost_unchecked, obstacle_distance

    _check_params(r_ins, r_inf, k)
    geo = costmap.geometry
    table = _cost_by_squared_offset(float(geo.resolution), float(r_ins), float(k), float(r_inf))
    if table is None:
        return None
    key = (id(costmap.costs), float(r_ins), float(r_inf), float(k))
    entry = _STATIC_INFLATION.get(key)
    if entry is None or entry[1] is not costmap.costs:
        lethal = costmap.costs == LETHAL
        static = _cost_unchecked(obstacle_distance(lethal, geo.resolution), r_ins, k, r_inf)
        if len(_STATIC_INFLATION) >= 4:
            _STATIC_INFLATION.pop(next(iter(_STATIC_INFLATION)))
        entry = (static, costmap.costs)
        _STATIC_INFLATION[key] = entry
    raw = entry[0].copy()
    rows, cols = geo.shape
    reach = int(np.sqrt(table.size - 1))  # cells: beyond it every offset costs FREE
    res = geo.resolution
    ox, oy = geo.origin
    if compiled.enabled():  # the same boxes, offsets and maxima in one compiled pass
        x, y, r = discs[:, 0], discs[:, 1], discs[:, 2]
        boxes = np.stack(
            [
                np.maximum(np.floor((y - r - oy) / res - 0.5), 0),
                np.minimum(np.ceil((y + r - oy) / res - 0.5) + 1, rows),
                np.maximum(np.floor((x - r - ox) / res - 0.5), 0),
                np.minimum(np.ceil((x + r - ox) / res - 0.5) + 1, cols),
            ],
            axis=1,
        ).astype(np.int64)
        _disc_costs(raster, boxes, reach, table, raw)
        _disc_finish(raster, costmap.costs, raw)  # the two last steps below, in one pass
        return Costmap(raw, geo)
    pad = np.pad(raster, 1, constant_values=False)
    interior = pad[:-2, 1:-1] & pad[2:, 1:-1] & pad[1:-1, :-2] & pad[1:-1, 2:]
    boundary = raster & ~interior
    for x, y, r in discs:
        # The cells the disc can occupy (as the rasterizer's window), then the affected ones.
        c0 = max(int(np.floor((x - r - ox) / res - 0.5)), 0)
        c1 = min(int(np.ceil((x + r - ox) / res - 0.5)) + 1, cols)
        r0 = max(int(np.floor((y - r - oy) / res - 0.5)), 0)
        r1 = min(int(np.ceil((y + r - oy) / res - 0.5)) + 1, rows)
        if c0 >= c1 or r0 >= r1:
            continue
        src_r, src_c = np.nonzero(boundary[r0:r1, c0:c1])
        if src_r.size == 0:
            continue
        src_r, src_c = src_r + r0, src_c + c0
        w0, w1 = max(r0 - reach, 0), min(r1 + reach, rows)
        v0, v1 = max(c0 - reach, 0), min(c1 + reach, cols)
        dr = np.arange(w0, w1)[:, None, None] - src_r
        dc = np.arange(v0, v1)[None, :, None] - src_c
        n = (dr * dr + dc * dc).min(axis=-1)  # (H, W) squared offset to the nearest source
        cost = table[np.minimum(n, table.size - 1)]
        np.maximum(raw[w0:w1, v0:v1], cost, out=raw[w0:w1, v0:v1])
    raw[raster] = LETHAL
    costs = np.where(unknown & ~occupied & ~(raw >= INSCRIBED), np.uint8(UNKNOWN), raw)
    return Costmap(costs.astype(np.uint8), geo)

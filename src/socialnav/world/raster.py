"""Rasterize vector geometry (wall segments, polygons, discs) into a boolean occupancy grid.

A cell is occupied when its *centre* is within ``max(thickness / 2, res·√2 / 2)`` of a segment
(the √2/2 floor keeps thin walls gap-free, even diagonal ones), inside a polygon (even-odd rule),
or inside a disc. Work is vectorized over the cells of each shape's bounding window; the only
Python loop is over shapes, never over cells.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core import compiled
from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import point_segment_distance, points_in_polygon
from socialnav.world.grid import GridGeometry


def _window(
    geometry: GridGeometry, lo: NDArray[np.float64], hi: NDArray[np.float64]
) -> tuple[slice, slice] | None:
    """Row/col slices of the cells whose centres may lie in the box ``[lo, hi]`` (x, y)."""
    res = geometry.resolution
    ox, oy = geometry.origin
    c0 = max(int(np.floor((lo[0] - ox) / res - 0.5)), 0)
    c1 = min(int(np.ceil((hi[0] - ox) / res - 0.5)) + 1, geometry.shape[1])
    r0 = max(int(np.floor((lo[1] - oy) / res - 0.5)), 0)
    r1 = min(int(np.ceil((hi[1] - oy) / res - 0.5)) + 1, geometry.shape[0])
    if c0 >= c1 or r0 >= r1:
        return None
    return slice(r0, r1), slice(c0, c1)


def _centres(geometry: GridGeometry, win: tuple[slice, slice]) -> NDArray[np.float64]:
    """Cell centres ``(h, w, 2)`` of a window."""
    res = geometry.resolution
    xs = geometry.origin[0] + (np.arange(win[1].start, win[1].stop) + 0.5) * res
    ys = geometry.origin[1] + (np.arange(win[0].start, win[0].stop) + 0.5) * res
    gx, gy = np.meshgrid(xs, ys)
    return np.stack([gx, gy], axis=-1)


def rasterize(
    geometry: GridGeometry,
    segments: ArrayLike | None = None,
    polygons: Sequence[ArrayLike] | None = None,
    discs: ArrayLike | None = None,
    thickness: float = 0.0,
) -> NDArray[np.bool_]:
    """Boolean occupancy ``(rows, cols)`` of the given shapes on ``geometry``.

    ``segments`` ``(S, 2, 2)`` endpoints in metres, ``polygons`` a list of ``(V, 2)`` vertex
    arrays (V >= 3), ``discs`` ``(D, 3)`` rows ``[x, y, r]`` with ``r >= 0``; ``thickness`` (m)
    is the full wall thickness. Shapes off the grid are clipped.
    """
    if not (np.isfinite(thickness) and thickness >= 0):
        raise InvalidInputError(f"thickness must be finite and >= 0, got {thickness}")
    out = np.zeros(geometry.shape, dtype=bool)
    half = max(thickness / 2.0, geometry.resolution * np.sqrt(2.0) / 2.0)

    if segments is not None:
        seg = np.asarray(segments, dtype=float)
        if seg.size and (seg.ndim != 3 or seg.shape[1:] != (2, 2)):
            raise InvalidInputError(f"segments must have shape (S, 2, 2), got {seg.shape}")
        if not np.all(np.isfinite(seg)):
            raise InvalidInputError("segments contain NaN or infinite values")
        for a, b in seg.reshape(-1, 2, 2):
            win = _window(geometry, np.minimum(a, b) - half, np.maximum(a, b) + half)
            if win is None:
                continue
            d = point_segment_distance(_centres(geometry, win), a[None], b[None])[..., 0]
            out[win] |= d <= half

    for k, poly_like in enumerate(polygons or ()):
        poly = np.asarray(poly_like, dtype=float)
        if poly.ndim != 2 or poly.shape[1] != 2 or poly.shape[0] < 3:
            raise InvalidInputError(f"polygon {k} must have shape (V>=3, 2), got {poly.shape}")
        if not np.all(np.isfinite(poly)):
            raise InvalidInputError(f"polygon {k} contains NaN or infinite values")
        win = _window(geometry, poly.min(axis=0), poly.max(axis=0))
        if win is not None:
            out[win] |= points_in_polygon(_centres(geometry, win), poly)

    if discs is not None:
        d_arr = np.asarray(discs, dtype=float)
        if d_arr.size and (d_arr.ndim != 2 or d_arr.shape[1] != 3):
            raise InvalidInputError(f"discs must have shape (D, 3) [x, y, r], got {d_arr.shape}")
        if not np.all(np.isfinite(d_arr)) or np.any(d_arr.reshape(-1, 3)[:, 2] < 0):
            raise InvalidInputError("discs must be finite with radius >= 0")
        if compiled.enabled():  # the same windows and tests in one compiled pass
            ox, oy = geometry.origin
            _disc_cells(out, d_arr.reshape(-1, 3), float(ox), float(oy), geometry.resolution)
            return out
        for x, y, r in d_arr.reshape(-1, 3):
            c = np.array([x, y])
            win = _window(geometry, c - r, c + r)
            if win is not None:
                rel = _centres(geometry, win) - c
                out[win] |= np.einsum("...i,...i->...", rel, rel) <= r * r
    return out


@compiled.jit
def _disc_cells(out, discs, ox, oy, res):  # type: ignore[no-untyped-def]
    """The disc loop of :func:`rasterize`: each disc's :func:`_window` and, per cell, the
    test ``(cx - x)² + (cy - y)² <= r²`` on the centres :func:`_centres` computes (the same
    operations, so the same cells)."""
    rows, cols = out.shape
    for k in range(discs.shape[0]):
        x, y, r = discs[k, 0], discs[k, 1], discs[k, 2]
        c0 = max(int(np.floor((x - r - ox) / res - 0.5)), 0)
        c1 = min(int(np.ceil((x + r - ox) / res - 0.5)) + 1, cols)
        r0 = max(int(np.floor((y - r - oy) / res - 0.5)), 0)
        r1 = min(int(np.ceil((y + r - oy) / res - 0.5)) + 1, rows)
        rr = r * r
        for i in range(r0, r1):
            dy = (oy + (i + 0.5) * res) - y
            for j in range(c0, c1):
                dx = (ox + (j + 0.5) * res) - x
                if dx * dx + dy * dy <= rr:
                    out[i, j] = True

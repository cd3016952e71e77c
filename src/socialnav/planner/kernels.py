"""Compiled (numba) kernels for the hot loops of a planning cycle, with NumPy as the reference.

The rollout, the occupancy critic and the per-person distance minimum are each one pass over
the ``(N, T)`` poses here instead of ~10–40 NumPy array passes with temporaries. Every kernel
computes the *same IEEE operations in the same order* as the NumPy reference it replaces, so
results are bit-identical: sums run in the order ``np.cumsum`` uses, minima and maxima are exact,
and no fast-math flags are set (no FMA contraction, no reassociation). ``cos``/``sin`` are the C
library's in the kernels; NumPy's float64 ``cos``/``sin`` are the same functions on common
builds (a NumPy built with Intel SVML may differ by one ulp, i.e. poses by ~1e-16 relative,
which can only flip a cell lookup for a pose within 1e-15 m of a cell edge). The property tests
in ``tests/test_kernels.py`` check bit-identity on random scenes.

Selection: the compiled path is used when numba is importable and the environment variable
``SOCIALNAV_KERNELS`` is not ``reference`` (``SOCIALNAV_KERNELS=reference`` runs the NumPy
reference everywhere; CI runs the parity tests both ways). :func:`enabled` may be overridden at
run time with :func:`set_enabled`.

Compilation: ``cache=True`` stores machine code beside this module (or in ``NUMBA_CACHE_DIR``);
:func:`warmup` compiles or loads every kernel for the exact argument types the planner passes
and is called when a planner is built, so no control step ever compiles. Its duration is in
:data:`compile_seconds` (benchmarks print it on its own row).
"""

from __future__ import annotations

import math
import os
import threading
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from socialnav.core import compiled
from socialnav.world import meeting_layer, proxemic_layer
from socialnav.world.grid import GridGeometry
from socialnav.world.proxemic_layer import person_windows

try:  # numba is a core dependency; the guard keeps the reference path usable without it.
    import numba as _numba

    _AVAILABLE = True
except ImportError:  # pragma: no cover - exercised only without numba installed
    _AVAILABLE = False

_ENABLED = _AVAILABLE and os.environ.get("SOCIALNAV_KERNELS", "").strip().lower() != "reference"
compiled.set_flag(_ENABLED)
#: Seconds the last :func:`warmup` spent compiling or loading cached kernels (0 if never run).
compile_seconds = 0.0
_warm = False


def enabled() -> bool:
    """Whether the compiled kernels are used (module docstring)."""
    return _ENABLED


def set_enabled(value: bool) -> bool:
    """Switch between the compiled kernels (``True``, needs numba) and the NumPy reference;
    returns the previous setting. Raises ``RuntimeError`` asking for numba when unavailable."""
    global _ENABLED
    if value and not _AVAILABLE:
        raise RuntimeError("the compiled kernels need numba (pip install numba)")
    previous, _ENABLED = _ENABLED, bool(value)
    compiled.set_flag(_ENABLED)  # the kernels of the lower layers (socialnav.moo)
    if value:
        warmup()
    return previous


def _jit(fn):  # type: ignore[no-untyped-def]
    if not _AVAILABLE:
        return fn
    return _numba.njit(cache=True, nogil=True, fastmath=False, error_model="numpy")(fn)


# ---- rollout -------------------------------------------------------------------------------


@_jit
def _wrap(a, two_pi, pi):  # type: ignore[no-untyped-def]
    """``(a + pi) % two_pi - pi`` with NumPy's float remainder; the common cases skip ``fmod``
    with the value it would return (exact: ``fmod(x, b) == x`` for ``|x| < b``)."""
    x = a + pi
    if 0.0 <= x < two_pi:
        return x - pi
    if -two_pi < x < 0.0:
        return (x + two_pi) - pi
    return x % two_pi - pi


@_jit
def _rollout_kernel(x0, y0, th0, twists, w_index, w_values, t, dt, two_pi, pi, out, lo, hi):  # type: ignore[no-untyped-def]
    """``out (N, T, 3)``: the operations of :func:`socialnav.planner.rollout.rollout` in its
    order (heading ``th0 + w t``, Euler step with the previous heading, sequential cumulative
    sum, then the start added, yaw wrapped to ``[-pi, pi)``).

    A sampled batch has few distinct ``w`` (one per ``vth`` sample): the heading, its ``cos``,
    ``sin`` and wrapped yaw are computed once per distinct ``w`` (``w_values (U,)``, row ``i``
    uses ``w_index[i]``; grouped by bit pattern, so every row gets the very values it would
    compute itself). ``lo``/``hi (T, 2)``: the per-time box of the positions, as
    :func:`time_box` computes it."""
    n, steps = twists.shape[0], t.shape[0]
    for k in range(steps):
        for a in range(2):
            lo[k, a] = np.inf
            hi[k, a] = -np.inf
    u = w_values.shape[0]
    cos_t = np.empty((u, steps))
    sin_t = np.empty((u, steps))
    yaw_t = np.empty((u, steps))
    for g in range(u):
        w = w_values[g]
        for k in range(steps):
            th = th0 + w * t[k]
            cos_t[g, k] = np.cos(th)
            sin_t[g, k] = np.sin(th)
            yaw_t[g, k] = _wrap(th, two_pi, pi)
    for i in range(n):
        vx = twists[i, 0]
        vy = twists[i, 1]
        g = w_index[i]
        out[i, 0, 0] = x0
        out[i, 0, 1] = y0
        out[i, 0, 2] = yaw_t[g, 0]
        sx = 0.0
        sy = 0.0
        for k in range(1, steps):
            ck = cos_t[g, k - 1]
            sk = sin_t[g, k - 1]
            sx += (vx * ck - vy * sk) * dt
            sy += (vx * sk + vy * ck) * dt
            px = sx + x0
            py = sy + y0
            out[i, k, 0] = px
            out[i, k, 1] = py
            out[i, k, 2] = yaw_t[g, k]
            if px < lo[k, 0] or px != px:
                lo[k, 0] = px
            if px > hi[k, 0] or px != px:
                hi[k, 0] = px
            if py < lo[k, 1] or py != py:
                lo[k, 1] = py
            if py > hi[k, 1] or py != py:
                hi[k, 1] = py
    if n > 0:  # every rollout starts at the pose
        lo[0, 0] = hi[0, 0] = x0
        lo[0, 1] = hi[0, 1] = y0


def rollout_poses(
    pose: NDArray[np.float64], twists: NDArray[np.float64], t: NDArray[np.float64], dt: float
) -> NDArray[np.float64]:
    """float64 poses ``(N, T, 3)`` of constant ``twists (N, 3)`` from ``pose (3,)`` on the time
    grid ``t (T,)`` s with step ``dt`` s; bit-identical to the NumPy rollout (module doc)."""
    twists = np.ascontiguousarray(twists, dtype=np.float64)
    out = np.empty((twists.shape[0], t.size, 3))
    lo = np.empty((t.size, 2))
    hi = np.empty((t.size, 2))
    # Distinct w by bit pattern (not by value: -0.0 and 0.0, or NaNs, stay apart).
    bits, w_index = np.unique(twists[:, 2].view(np.int64), return_inverse=True)
    _rollout_kernel(
        float(pose[0]),
        float(pose[1]),
        float(pose[2]),
        twists,
        np.ascontiguousarray(w_index, dtype=np.intp).reshape(-1),
        bits.view(np.float64),
        np.ascontiguousarray(t, dtype=np.float64),
        float(dt),
        2.0 * np.pi,
        np.pi,
        out,
        lo,
        hi,
    )
    global _BOX
    _BOX = (out, lo, hi)
    return out


# The per-time box of the last rollout's poses, computed in the rollout pass (time_box reuses
# it for that very array: rollouts are not modified in place, critics share them).
_BOX: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None = None


# ---- occupancy -----------------------------------------------------------------------------


@_jit
def _occupancy_kernel(  # type: ignore[no-untyped-def]
    poses,  # (N, T, 3) float64; poses[:, first:] are scored
    first,
    costs,  # (rows, cols) uint8
    ox,
    oy,
    inv,
    footprint,
    outline,  # (K, 2) float64, far first
    codes,  # flat padded hit codes (uint8): 1 LETHAL, 2 UNKNOWN / off the map
    pad,
    width,
    clearance,  # (rows, cols) uint16 index into need_table, or an empty array
    need_table,  # (L,) intp
    circumscribed,  # threshold cost, or -1 to use the clearance table
    sizes,  # (G,) ascending point counts the need is rounded up to
    chunk,
    worst,  # out (N,) float64
    collision,  # out (N,) bool
    unknown,  # out (N,) bool
):
    n, steps = poses.shape[0], poses.shape[1] - first
    rows, cols = costs.shape
    k_all = outline.shape[0]
    ncodes = codes.shape[0]
    for i in range(n):
        w = 0
        unk = False
        col_hit = False
        first_need = -1  # the first pose whose outline can touch a hard cell (none: -1)
        for k in range(steps):
            cx = np.floor((poses[i, first + k, 0] - ox) * inv)
            cy = np.floor((poses[i, first + k, 1] - oy) * inv)
            v = 255
            if 0.0 <= cy < rows and 0.0 <= cx < cols:
                v = costs[int(cy), int(cx)]
                if footprint and first_need < 0:
                    if circumscribed < 0:
                        need = need_table[clearance[int(cy), int(cx)]]
                    else:
                        need = k_all if v >= circumscribed else 0
                    if need > 0:
                        first_need = k
            if v == 255:
                unk = True
            elif v >= 253:
                col_hit = True
            elif v > w:
                w = v
        worst[i] = w
        if footprint and not unk and not col_hit and first_need >= 0:
            # Outline points per pose (the NumPy reference's need, rounded up to its groups);
            # after a LETHAL hit the current chunk still finishes, as in the reference. Poses
            # before ``first_need`` check no point: the scan starts there.
            stop = steps
            for k in range(first_need, steps):
                if k >= stop:
                    break
                r = int(np.floor((poses[i, first + k, 1] - oy) * inv))
                q = int(np.floor((poses[i, first + k, 0] - ox) * inv))
                if circumscribed < 0:
                    need = need_table[clearance[r, q]]
                else:
                    need = k_all if costs[r, q] >= circumscribed else 0
                if need <= 0:
                    continue
                m = sizes[sizes.shape[0] - 1]
                for g in range(sizes.shape[0]):
                    if sizes[g] >= need:
                        m = sizes[g]
                        break
                px, py = poses[i, first + k, 0], poses[i, first + k, 1]
                ck, sk = np.cos(poses[i, first + k, 2]), np.sin(poses[i, first + k, 2])
                bits = 0
                for j in range(m):
                    bx, by = outline[j, 0], outline[j, 1]
                    x = (px + ck * bx - sk * by - ox) * inv
                    y = (py + sk * bx + ck * by - oy) * inv
                    cell = (int(np.floor(y)) + pad) * width + int(np.floor(x)) + pad
                    if cell < 0:
                        cell = 0
                    elif cell >= ncodes:
                        cell = ncodes - 1
                    bits |= codes[cell]
                if bits & 2:
                    unk = True
                if bits & 1 and not col_hit:
                    col_hit = True
                    stop = (k // chunk + 1) * chunk
        collision[i] = col_hit
        unknown[i] = unk


def occupancy_scan(
    poses: NDArray[np.float64],
    first: int,
    costs: NDArray[np.uint8],
    origin: tuple[float, float],
    resolution: float,
    outline_data: tuple[NDArray[np.float64], NDArray[np.uint8], int, int] | None,
    clearance: tuple[NDArray[np.uint16], NDArray[np.intp]] | None,
    circumscribed: int | None,
    sizes: NDArray[np.intp],
    chunk: int,
) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]:
    """Worst centre cost ``(N,)`` (0..252), footprint ``collision (N,)`` and ``unknown (N,)``
    of ``poses[:, first:]`` (``poses (N, T, 3)`` float64), exactly as the NumPy occupancy
    critic computes them.

    ``outline_data`` = (outline ``(K, 2)`` far first, flat padded hit codes, pad, padded width)
    or ``None`` (centre cell only); ``clearance`` = (per-cell level, need table) for the exact
    shortcut, or ``None`` with ``circumscribed`` the cost threshold.
    """
    n = poses.shape[0]
    worst = np.empty(n)
    collision = np.empty(n, dtype=np.bool_)
    unknown = np.empty(n, dtype=np.bool_)
    poses = np.ascontiguousarray(poses, dtype=np.float64)
    if outline_data is None:
        outline, codes, pad, width = np.zeros((0, 2)), np.zeros(1, np.uint8), 0, 1
    else:
        outline, codes, pad, width = outline_data
    if clearance is None:
        clear, table = np.zeros((1, 1), np.uint16), np.zeros(1, np.intp)
    else:
        clear, table = clearance
    _occupancy_kernel(
        poses,
        int(first),
        np.ascontiguousarray(costs),
        float(origin[0]),
        float(origin[1]),
        1.0 / resolution,
        outline_data is not None,
        np.ascontiguousarray(outline, dtype=np.float64),
        np.ascontiguousarray(codes).reshape(-1),
        int(pad),
        int(width),
        np.ascontiguousarray(clear),
        np.ascontiguousarray(table, dtype=np.intp),
        -1 if circumscribed is None else int(circumscribed),
        np.ascontiguousarray(sizes, dtype=np.intp),
        int(chunk),
        worst,
        collision,
        unknown,
    )
    return worst, collision, unknown


@_jit
def _hit_codes_kernel(costs, inscribed, border, codes, pad):  # type: ignore[no-untyped-def]
    """``codes`` (padded by ``pad``): ``max(cost, inscribed) - inscribed`` inside (0 free,
    1 LETHAL, 2 UNKNOWN for the costmap's 253..255), ``border`` on the pad."""
    rows, cols = costs.shape
    width = codes.shape[1]
    for r in range(codes.shape[0]):
        inner_r = pad <= r < pad + rows
        for c in range(width):
            if inner_r and pad <= c < pad + cols:
                v = costs[r - pad, c - pad]
                codes[r, c] = v - inscribed if v > inscribed else 0
            else:
                codes[r, c] = border


def hit_codes(costs: NDArray[np.uint8], inscribed: int, border: int, pad: int) -> NDArray[np.uint8]:
    """The occupancy critic's padded hit-code map ``(rows + 2 pad, cols + 2 pad)`` uint8 of
    ``costs (rows, cols)`` in one pass (the same values as its NumPy construction)."""
    rows, cols = costs.shape
    codes = np.empty((rows + 2 * pad, cols + 2 * pad), dtype=np.uint8)
    _hit_codes_kernel(
        np.ascontiguousarray(costs, dtype=np.uint8),
        np.uint8(inscribed),
        np.uint8(border),
        codes,
        pad,
    )
    return codes


# ---- people --------------------------------------------------------------------------------


def min_squared_distances(
    xy: NDArray[np.float64],
    forecast: NDArray[np.float64],
    people: NDArray[np.intp],
    out: NDArray[np.float64],
) -> None:
    """``out[:, j] = min_t |xy[:, t] - forecast[t, j]|²`` for ``j`` in ``people``;
    ``xy (N, T, 2)`` m (or poses ``(N, T, 3)``: x, y are read), ``forecast (T, K, 2)`` m,
    ``out (N, K)`` m², written in place."""
    people = np.asarray(people, dtype=np.intp)
    block = np.empty((xy.shape[0], people.size))
    _d2min_culled_kernel(  # an infinite reach: no pair is culled
        np.ascontiguousarray(xy, dtype=np.float64),
        np.ascontiguousarray(np.asarray(forecast, dtype=np.float64)[:, people].transpose(1, 0, 2)),
        np.full(people.size, np.inf),
        block,
    )
    out[:, people] = block


@_jit
def _d2min_ordered(poses, forecast, i, j):  # type: ignore[no-untyped-def]
    """min over ``t`` of one pair's squared distances in order, NaN sticking as in ``np.min``."""
    best = np.inf
    for k in range(poses.shape[1]):
        dx = poses[i, k, 0] - forecast[j, k, 0]
        dy = poses[i, k, 1] - forecast[j, k, 1]
        d = dx * dx + dy * dy
        if d < best or d != d:
            best = d
    return best


@_jit
def _d2min_culled_kernel(poses, forecast, reach2, out):  # type: ignore[no-untyped-def]
    """``out (N, J)`` = min over ``t`` of the squared distance of ``poses[i, t, :2]`` to
    ``forecast[j, t]`` (``forecast (J, T, 2)``; ``np.min``'s value), for every pair whose
    boxes (the trajectory's over all times, the person's over all times) come within
    ``sqrt(reach2[j])``; ``inf`` for the pairs whose boxes are farther apart (their distance
    is too at every time). Pairs with a non-finite point are never culled.

    The minimum runs over four accumulators (the minimum of squared distances, never -0.0,
    is the same whatever the order; one accumulator would make the loop wait on each
    comparison); a pair where a NaN appears is redone in order, as ``np.min`` propagates it."""
    n, t = poses.shape[0], poses.shape[1]
    m = forecast.shape[0]
    cull = False
    for j in range(m):
        if reach2[j] < np.inf:
            cull = True
    plo = np.empty((m, 2))
    phi = np.empty((m, 2))
    pfin = np.ones(m, dtype=np.bool_)
    if cull:
        for j in range(m):
            for a in range(2):
                plo[j, a] = np.inf
                phi[j, a] = -np.inf
            for k in range(t):
                for a in range(2):
                    v = forecast[j, k, a]
                    if not np.isfinite(v):
                        pfin[j] = False
                    if v < plo[j, a]:
                        plo[j, a] = v
                    if v > phi[j, a]:
                        phi[j, a] = v
    t4 = t - t % 4
    for i in range(n):
        xlo = np.inf
        xhi = -np.inf
        ylo = np.inf
        yhi = -np.inf
        tfin = True
        if cull:
            for k in range(t):
                x = poses[i, k, 0]
                y = poses[i, k, 1]
                if not (np.isfinite(x) and np.isfinite(y)):
                    tfin = False
                if x < xlo:
                    xlo = x
                if x > xhi:
                    xhi = x
                if y < ylo:
                    ylo = y
                if y > yhi:
                    yhi = y
        for j in range(m):
            if cull and tfin and pfin[j]:
                gx = max(xlo - phi[j, 0], 0.0) + max(plo[j, 0] - xhi, 0.0)
                gy = max(ylo - phi[j, 1], 0.0) + max(plo[j, 1] - yhi, 0.0)
                if gx * gx + gy * gy > reach2[j]:
                    out[i, j] = np.inf
                    continue
            b0 = np.inf
            b1 = np.inf
            b2 = np.inf
            b3 = np.inf
            nan = False
            for k in range(0, t4, 4):
                dx = poses[i, k, 0] - forecast[j, k, 0]
                dy = poses[i, k, 1] - forecast[j, k, 1]
                d0 = dx * dx + dy * dy
                dx = poses[i, k + 1, 0] - forecast[j, k + 1, 0]
                dy = poses[i, k + 1, 1] - forecast[j, k + 1, 1]
                d1 = dx * dx + dy * dy
                dx = poses[i, k + 2, 0] - forecast[j, k + 2, 0]
                dy = poses[i, k + 2, 1] - forecast[j, k + 2, 1]
                d2 = dx * dx + dy * dy
                dx = poses[i, k + 3, 0] - forecast[j, k + 3, 0]
                dy = poses[i, k + 3, 1] - forecast[j, k + 3, 1]
                d3 = dx * dx + dy * dy
                nan |= (d0 != d0) | (d1 != d1) | (d2 != d2) | (d3 != d3)
                b0 = d0 if d0 < b0 else b0
                b1 = d1 if d1 < b1 else b1
                b2 = d2 if d2 < b2 else b2
                b3 = d3 if d3 < b3 else b3
            for k in range(t4, t):
                dx = poses[i, k, 0] - forecast[j, k, 0]
                dy = poses[i, k, 1] - forecast[j, k, 1]
                d0 = dx * dx + dy * dy
                nan |= d0 != d0
                b0 = d0 if d0 < b0 else b0
            if nan:
                out[i, j] = _d2min_ordered(poses, forecast, i, j)
            else:
                out[i, j] = min(min(b0, b1), min(b2, b3))


def min_squared_distances_culled(
    poses: NDArray[np.float64],
    forecast: NDArray[np.float64],
    people: NDArray[np.intp],
    reach: NDArray[np.float64],
    out: NDArray[np.float64],
) -> None:
    """:func:`min_squared_distances` for ``people`` (column indices), exact for every
    (trajectory, person) pair that can come within ``reach (J,)`` m (one per listed person) and
    ``inf`` for the pairs whose boxes provably stay farther apart (a relative margin of 1e-9
    keeps the cull conservative against rounding); ``poses (N, T, 3)``, ``forecast (T, K, 2)``,
    ``out (N, K)`` m², written in place."""
    people = np.asarray(people, dtype=np.intp)
    limit = np.asarray(reach, dtype=np.float64) * (1.0 + 1e-9) + 1e-9
    block = np.empty((poses.shape[0], people.size))
    _d2min_culled_kernel(
        np.ascontiguousarray(poses, dtype=np.float64),
        np.ascontiguousarray(np.asarray(forecast, dtype=np.float64)[:, people].transpose(1, 0, 2)),
        limit * limit,
        block,
    )
    out[:, people] = block


@_jit
def _person_distance_kernel(  # type: ignore[no-untyped-def]
    d2min, cols, end, start, step, passing, r2, collide, out, hit
):
    """Per trajectory ``i`` and listed person ``c = cols[jj]``: ``out[i, jj]`` = the centre
    distance ``sqrt(d2min[i, c])``, lowered to the passing distance of the walk ``start[c] +
    s step[c]`` (``s`` in [0, 1]) from the end point ``end[i]`` where ``passing[jj]`` (the
    operations of :func:`~socialnav.planner.critics.interpersonal.passing_distances` in its
    order); ``hit[i]`` |= ``d2min[i, c] < r2[c]`` for the people with ``collide[jj]``."""
    n, m = d2min.shape[0], cols.shape[0]
    for i in range(n):
        ex = end[i, 0]
        ey = end[i, 1]
        h = False
        for jj in range(m):
            c = cols[jj]
            d2 = d2min[i, c]
            if collide[jj] and d2 < r2[c]:
                h = True
            d = np.sqrt(d2)
            if passing[jj]:
                wx = ex - start[c, 0]
                wy = ey - start[c, 1]
                sx = step[c, 0]
                sy = step[c, 1]
                uu = sx * sx + sy * sy
                s = 0.0
                if uu > 0:
                    s = (wx * sx + wy * sy) / uu
                s = min(max(s, 0.0), 1.0)
                gx = wx - s * sx
                gy = wy - s * sy
                p = np.sqrt(gx * gx + gy * gy)
                if p < d or p != p:  # np.minimum: NaN propagates
                    d = p
            out[i, jj] = d
        hit[i] = h


def person_distances(
    d2min: NDArray[np.float64],
    cols: NDArray[np.intp],
    end: NDArray[np.float64],
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    passing: NDArray[np.bool_],
    r2: NDArray[np.float64],
    collide: NDArray[np.bool_],
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """``(N, J)`` centre distance (m) to each person of ``cols (J,)`` (the minimum over the
    rollout, and with ``passing (J,)`` over the walk after it: ``start``/``step (K, 2)``, end
    points ``end (N, 2)``) and ``(N,)`` whether any person with ``collide (J,)`` is within
    ``sqrt(r2)`` (``d2min (N, K)`` m², :func:`min_squared_distances_culled`)."""
    n = d2min.shape[0]
    out = np.empty((n, cols.size))
    hit = np.empty(n, dtype=np.bool_)
    _person_distance_kernel(
        np.ascontiguousarray(d2min, dtype=np.float64),
        np.ascontiguousarray(cols, dtype=np.intp),
        np.ascontiguousarray(end, dtype=np.float64),
        np.ascontiguousarray(start, dtype=np.float64),
        np.ascontiguousarray(step, dtype=np.float64),
        np.ascontiguousarray(passing, dtype=np.bool_),
        np.ascontiguousarray(r2, dtype=np.float64),
        np.ascontiguousarray(collide, dtype=np.bool_),
        out,
        hit,
    )
    return out, hit


@_jit
def _approach_kernel(poses, t, forecast, d2min, cols, reach2, contact, speed, out):  # type: ignore[no-untyped-def]
    """The rule of :func:`~socialnav.planner.critics.interpersonal.approaches` in its
    operations: for each listed person ``c`` and each trajectory within ``reach2[c]`` of them,
    at a sample in contact (``dist < contact[c]``) the faster of the steps arriving at and
    leaving it closing faster than ``speed`` makes ``out[i]`` True."""
    n, steps = poses.shape[0], poses.shape[1]
    if steps < 2:
        return
    dt = np.empty(steps - 1)
    for k in range(steps - 1):
        dt[k] = max(t[k + 1] - t[k], 1e-9)
    for jj in range(cols.shape[0]):
        c = cols[jj]
        for i in range(n):
            if out[i] or not d2min[i, c] < reach2[c]:
                continue
            for k in range(steps):
                rx = forecast[k, c, 0] - poses[i, k, 0]
                ry = forecast[k, c, 1] - poses[i, k, 1]
                dist = np.sqrt(rx * rx + ry * ry)
                if not dist < contact[c]:
                    continue
                den = max(dist, 1e-9)
                ux = rx / den
                uy = ry / den
                if k > 0:
                    sx = (poses[i, k, 0] - poses[i, k - 1, 0]) / dt[k - 1]
                    sy = (poses[i, k, 1] - poses[i, k - 1, 1]) / dt[k - 1]
                    closing = sx * ux + sy * uy
                else:
                    closing = 0.0
                if k < steps - 1:
                    sx = (poses[i, k + 1, 0] - poses[i, k, 0]) / dt[k]
                    sy = (poses[i, k + 1, 1] - poses[i, k, 1]) / dt[k]
                    leave = sx * ux + sy * uy
                    if leave > closing or leave != leave:
                        closing = leave
                elif closing < 0.0:
                    closing = 0.0
                if closing > speed:
                    out[i] = True
                    break


def approaches(
    poses: NDArray[np.float64],
    t: NDArray[np.float64],
    forecast: NDArray[np.float64],
    d2min: NDArray[np.float64],
    cols: NDArray[np.intp],
    contact: NDArray[np.float64],
    speed: float,
) -> NDArray[np.bool_]:
    """``(N,)`` trajectories (``poses (N, T, 3)`` float64, times ``t (T,)`` s) that close on a
    person of ``cols`` (forecast ``(T, K, 2)``) faster than ``speed`` m/s while within
    ``contact (K,)`` m of them; bit-identical to the NumPy rule
    (:func:`socialnav.planner.critics.interpersonal.approaches`)."""
    out = np.zeros(poses.shape[0], dtype=np.bool_)
    contact = np.asarray(contact, dtype=np.float64)
    _approach_kernel(
        np.ascontiguousarray(poses, dtype=np.float64),
        np.ascontiguousarray(t, dtype=np.float64),
        np.ascontiguousarray(forecast, dtype=np.float64),
        np.ascontiguousarray(d2min, dtype=np.float64),
        np.ascontiguousarray(cols, dtype=np.intp),
        (contact * (1.0 + 1e-9)) ** 2,
        contact,
        float(speed),
        out,
    )
    return out


@_jit
def _polygon_distance_kernel(points, polygon, out):  # type: ignore[no-untyped-def]
    """:func:`socialnav.core.geometry.signed_distance_to_polygon` in its operations, per point:
    the nearest edge's distance (projection clipped to the edge, degenerate edges as points),
    negative when the even-odd count of edges crossed leftward of the point is odd."""
    v = polygon.shape[0]
    for m in range(points.shape[0]):
        px, py = points[m, 0], points[m, 1]
        best = np.inf
        crossings = 0
        for e in range(v):
            ax, ay = polygon[e, 0], polygon[e, 1]
            bx, by = polygon[(e + 1) % v, 0], polygon[(e + 1) % v, 1]
            abx, aby = bx - ax, by - ay
            denom = abx * abx + aby * aby
            safe = denom if denom > 0.0 else 1.0
            u = ((px - ax) * abx + (py - ay) * aby) / safe
            u = min(max(u, 0.0), 1.0)
            dx = px - (ax + u * abx)
            dy = py - (ay + u * aby)
            d = np.sqrt(dx * dx + dy * dy)
            if d < best:
                best = d
            if (ay > py) != (by > py):
                rise = by - ay if by != ay else 1.0
                if px < ax + (py - ay) * (bx - ax) / rise:
                    crossings += 1
        out[m] = -best if crossings % 2 == 1 else best


def signed_distance_to_polygon(
    points: NDArray[np.float64], polygon: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Signed distance (m) of ``points (..., 2)`` to the boundary of ``polygon (V, 2)``,
    negative inside: shape ``(...)``; bit-identical to the NumPy reference
    (:func:`socialnav.core.geometry.signed_distance_to_polygon`), without its ``(..., V)``
    temporaries (the footprint approach rule calls it on thousands of poses)."""
    pts = np.ascontiguousarray(points, dtype=np.float64)
    out = np.empty(pts.shape[:-1])
    _polygon_distance_kernel(
        pts.reshape(-1, 2), np.ascontiguousarray(polygon, dtype=np.float64), out.reshape(-1)
    )
    return out


@_jit
def _time_box_kernel(xy, lo, hi):  # type: ignore[no-untyped-def]
    n, t = xy.shape[0], xy.shape[1]
    for k in range(t):
        for a in range(2):
            lo[k, a] = np.inf
            hi[k, a] = -np.inf
    for i in range(n):
        for k in range(t):
            for a in range(2):
                v = xy[i, k, a]
                if v < lo[k, a] or v != v:
                    lo[k, a] = v
                if v > hi[k, a] or v != v:
                    hi[k, a] = v


def time_box(xy: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-time box of the rollout points: ``xy.min(axis=0)``, ``xy.max(axis=0)`` ``(T, 2)``
    for ``xy (N, T, 2)`` (or poses ``(N, T, 3)``), with NumPy's NaN propagation."""
    box = _BOX
    if box is not None and box[0] is xy and xy.shape[0] > 0:
        return box[1].copy(), box[2].copy()
    xy = np.ascontiguousarray(xy, dtype=np.float64)
    lo = np.empty((xy.shape[1], 2))
    hi = np.empty((xy.shape[1], 2))
    if xy.shape[0] == 0:  # NumPy raises on an empty reduction: keep that behaviour
        return xy[..., :2].min(axis=0), xy[..., :2].max(axis=0)
    _time_box_kernel(xy, lo, hi)
    return lo, hi


@_jit
def _nearest_vertex_kernel(points, vertices, out):  # type: ignore[no-untyped-def]
    """``out[i]`` = first index of the smallest squared distance (``np.argmin``'s). Finite
    inputs (no NaN possible) split the vertices over four interleaved accumulators, each
    keeping its first minimum, and take the smallest, ties to the lowest index: the same
    index, without waiting on every comparison; otherwise one ordered pass (NaN first)."""
    nv = vertices.shape[0]
    finite = True
    for v in range(nv):
        if not (np.isfinite(vertices[v, 0]) and np.isfinite(vertices[v, 1])):
            finite = False
    v4 = nv - nv % 4
    for i in range(points.shape[0]):
        px, py = points[i, 0], points[i, 1]
        if not (finite and np.isfinite(px) and np.isfinite(py)):
            best = np.inf
            arg = 0
            for v in range(nv):
                dx = px - vertices[v, 0]
                dy = py - vertices[v, 1]
                d = dx * dx + dy * dy
                if d < best:
                    best = d
                    arg = v
                elif d != d:  # argmin returns the first NaN
                    arg = v
                    break
            out[i] = arg
            continue
        b0 = b1 = b2 = b3 = np.inf
        a0, a1, a2, a3 = 0, 1, 2, 3
        for v in range(0, v4, 4):
            dx = px - vertices[v, 0]
            dy = py - vertices[v, 1]
            d = dx * dx + dy * dy
            if d < b0:
                b0, a0 = d, v
            dx = px - vertices[v + 1, 0]
            dy = py - vertices[v + 1, 1]
            d = dx * dx + dy * dy
            if d < b1:
                b1, a1 = d, v + 1
            dx = px - vertices[v + 2, 0]
            dy = py - vertices[v + 2, 1]
            d = dx * dx + dy * dy
            if d < b2:
                b2, a2 = d, v + 2
            dx = px - vertices[v + 3, 0]
            dy = py - vertices[v + 3, 1]
            d = dx * dx + dy * dy
            if d < b3:
                b3, a3 = d, v + 3
        for v in range(v4, nv):
            dx = px - vertices[v, 0]
            dy = py - vertices[v, 1]
            d = dx * dx + dy * dy
            if d < b0:  # a tie keeps a0, the lower index
                b0, a0 = d, v
        # An accumulator that never improved on inf holds a placeholder index: all-inf rows
        # (or fewer than four vertices) must still give argmin's 0.
        best, arg = np.inf, 0
        if b0 < best:
            best, arg = b0, a0
        if b1 < best or (b1 == best and b1 < np.inf and a1 < arg):
            best, arg = b1, a1
        if b2 < best or (b2 == best and b2 < np.inf and a2 < arg):
            best, arg = b2, a2
        if b3 < best or (b3 == best and b3 < np.inf and a3 < arg):
            best, arg = b3, a3
        out[i] = arg


def nearest_vertex(points: NDArray[np.float64], vertices: NDArray[np.float64]) -> NDArray[np.intp]:
    """``(N,)`` index of the vertex ``(P, 2)`` nearest each point ``(N, >= 2)`` (first on ties),
    as ``argmin`` of the squared distances."""
    out = np.empty(points.shape[0], dtype=np.intp)
    if vertices.shape[0] == 0:  # argmin of an empty row raises: keep that behaviour
        raise ValueError("attempt to get argmin of an empty sequence")
    _nearest_vertex_kernel(
        np.ascontiguousarray(points, dtype=np.float64),
        np.ascontiguousarray(vertices, dtype=np.float64),
        out,
    )
    return out


# ---- map-grid end points --------------------------------------------------------------------


@_jit
def _end_point_kernel(poses, ox, oy, res, grid, passable, cost, unreachable, off_map):  # type: ignore[no-untyped-def]
    """The operations of :func:`socialnav.planner.critics.map_grid.score_end_points` per end
    point ``poses[i, -1]``: its cell (``floor((x - origin) / resolution)``), on the grid or
    not, the grid's steps there (float32 widened) times the resolution, or ``inf`` where the
    cell is blocked, unreached or off the map."""
    n, last = poses.shape[0], poses.shape[1] - 1
    rows, cols = grid.shape
    for i in range(n):
        fc = np.floor((poses[i, last, 0] - ox) / res)
        fr = np.floor((poses[i, last, 1] - oy) / res)
        if 0.0 <= fr < rows and 0.0 <= fc < cols:
            r = int(fr)
            c = int(fc)
            steps = np.float64(grid[r, c])
            bad = not passable[r, c] or not np.isfinite(steps)
            unreachable[i] = bad
            off_map[i] = False
            cost[i] = np.inf if bad else steps * res
        else:
            unreachable[i] = False
            off_map[i] = True
            cost[i] = np.inf


def end_point_costs(
    poses: NDArray[np.float64],
    origin: tuple[float, float],
    resolution: float,
    grid: NDArray[np.float32],
    passable: NDArray[np.bool_],
) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]:
    """``cost (N,)`` (m), ``unreachable (N,)`` and ``off_map (N,)`` of the end points of
    ``poses (N, T, 3)`` float64 on a map ``grid (rows, cols)`` float32 of BFS steps with its
    ``passable`` mask (bit-identical to the NumPy reference)."""
    n = poses.shape[0]
    cost = np.empty(n)
    unreachable = np.empty(n, dtype=np.bool_)
    off_map = np.empty(n, dtype=np.bool_)
    _end_point_kernel(
        np.ascontiguousarray(poses, dtype=np.float64),
        float(origin[0]),
        float(origin[1]),
        float(resolution),
        np.ascontiguousarray(grid, dtype=np.float32),
        np.ascontiguousarray(passable, dtype=np.bool_),
        cost,
        unreachable,
        off_map,
    )
    return cost, unreachable, off_map


# ---- global planner graph --------------------------------------------------------------------


@_jit
def _grid_weights_kernel(costs, passable, offsets, steps, neutral, half_factor, out):  # type: ignore[no-untyped-def]
    rows, cols = costs.shape
    for r in range(rows):
        for c in range(cols):
            cu = np.float64(costs[r, c])
            for k in range(offsets.shape[0]):
                dr, dc = offsets[k, 0], offsets[k, 1]
                rn, cn = r + dr, c + dc
                inside = 0 <= rn < rows and 0 <= cn < cols
                ok = passable[r, c] and inside and passable[rn, cn]
                if ok and dr != 0 and dc != 0:
                    ok = passable[rn, c] and passable[r, cn]
                if ok:
                    out[r, c, k] = steps[k] * (
                        neutral + half_factor * (cu + np.float64(costs[rn, cn]))
                    )
                else:
                    out[r, c, k] = np.inf


def grid_weights(
    costs: NDArray[np.uint8],
    passable: NDArray[np.bool_],
    offsets: NDArray[np.int64],
    steps: NDArray[np.float64],
    neutral_cost: float,
    cost_factor: float,
) -> NDArray[np.float64]:
    """Edge weights ``(rows, cols, 8)`` of the global planner's 8-slot grid graph, exactly as
    :func:`socialnav.planner.global_planner.grid_graph` computes them (``inf`` = no edge)."""
    out = np.empty((*costs.shape, offsets.shape[0]))
    _grid_weights_kernel(
        np.ascontiguousarray(costs, dtype=np.uint8),
        np.ascontiguousarray(passable, dtype=np.bool_),
        np.ascontiguousarray(offsets, dtype=np.int64),
        np.ascontiguousarray(steps, dtype=np.float64),
        float(neutral_cost),
        float(cost_factor) * 0.5,
        out,
    )
    return out


# ---- global search (A*) ------------------------------------------------------------------


@_jit
def _heap_up(hk, hn, pos, i, key, node):  # type: ignore[no-untyped-def]
    """Sift ``(key, node)`` up from slot ``i`` of the binary heap (keys ``hk``, nodes ``hn``,
    ordered by ``(key, node)``)."""
    while i > 0:
        parent = (i - 1) >> 1
        pk = hk[parent]
        if pk < key or (pk == key and hn[parent] < node):
            break
        hk[i] = pk
        hn[i] = hn[parent]
        pos[hn[i]] = i
        i = parent
    hk[i] = key
    hn[i] = node
    pos[node] = i


@_jit
def _heap_pop(hk, hn, pos, size):  # type: ignore[no-untyped-def]
    """Remove the root of the heap of ``size`` entries and return the new size. Bottom-up
    (Floyd): the hole at the root moves down along the smaller children to a leaf, where the
    last entry is put and sifted up; fewer comparisons than sifting the last entry down from
    the root, as it usually belongs near the bottom again."""
    size -= 1
    if size == 0:
        return 0
    key, node = hk[size], hn[size]
    i = 0
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        ck, cn = hk[child], hn[child]
        if child + 1 < size:
            rk, rn = hk[child + 1], hn[child + 1]
            if rk < ck or (rk == ck and rn < cn):
                child += 1
                ck, cn = rk, rn
        hk[i] = ck
        hn[i] = cn
        pos[cn] = i
        i = child
    _heap_up(hk, hn, pos, i, key, node)
    return size


@_jit
def _astar_kernel(  # type: ignore[no-untyped-def]
    costs, passable, start, goal, steps, neutral, half_factor, h_scale, dist, pred, pos, hk,
    hn, touched,
):  # fmt: skip
    """A* over the 8-slot grid graph of :func:`grid_weights` (its edge weights, computed on
    the fly with the same operations; the neighbours in the order of ``ASTAR_OFFSETS``, move
    lengths ``steps (8,)``), from ``start`` (flat index) until ``goal`` (flat index, or -1
    for an exhaustive search) is settled. Heap key ``(g + h, node)``; ``h`` = octile
    distance x ``h_scale`` (a lower bound of every move's cost, so consistent).
    ``dist``/``pred``/``pos`` (heap slot, -2 once settled) must hold ``inf``/-1/-1 on entry;
    every node given a cost is listed in ``touched`` (:func:`_astar_reset` restores those).
    Returns how many are listed."""
    rows, cols = costs.shape
    cf = costs.reshape(-1)
    pf = passable.reshape(-1)
    gr, gc = 0, 0
    if goal >= 0:
        gr = goal // cols
        gc = goal - gr * cols
    dist[start] = 0.0
    hk[0] = 0.0
    hn[0] = start
    pos[start] = 0
    touched[0] = start
    listed = 1
    size = 1
    diag = np.sqrt(2.0) - 1.0
    while size > 0:
        u = hn[0]
        pos[u] = -2
        size = _heap_pop(hk, hn, pos, size)
        if u == goal:
            break
        if not pf[u]:
            continue
        r = u // cols
        c = u - r * cols
        du = dist[u]
        cu = np.float64(cf[u])
        # The four sides once per node; a diagonal needs both corner cells passable.
        up = r > 0 and pf[u - cols]
        down = r < rows - 1 and pf[u + cols]
        left = c > 0 and pf[u - 1]
        right = c < cols - 1 and pf[u + 1]
        for k in range(8):  # the order of ASTAR_OFFSETS (ties: the reference's order)
            if k == 0:
                ok, v, dr, dc = up and left and pf[u - cols - 1], u - cols - 1, -1, -1
            elif k == 1:
                ok, v, dr, dc = up, u - cols, -1, 0
            elif k == 2:
                ok, v, dr, dc = up and right and pf[u - cols + 1], u - cols + 1, -1, 1
            elif k == 3:
                ok, v, dr, dc = left, u - 1, 0, -1
            elif k == 4:
                ok, v, dr, dc = right, u + 1, 0, 1
            elif k == 5:
                ok, v, dr, dc = down and left and pf[u + cols - 1], u + cols - 1, 1, -1
            elif k == 6:
                ok, v, dr, dc = down, u + cols, 1, 0
            else:
                ok, v, dr, dc = down and right and pf[u + cols + 1], u + cols + 1, 1, 1
            if not ok:
                continue
            slot = pos[v]
            if slot == -2:
                continue
            nd = du + steps[k] * (neutral + half_factor * (cu + np.float64(cf[v])))
            if nd < dist[v]:
                dist[v] = nd
                pred[v] = u
                h = 0.0
                if goal >= 0:
                    ar = abs(r + dr - gr)
                    ac = abs(c + dc - gc)
                    h = h_scale * (max(ar, ac) + diag * min(ar, ac))
                if slot == -1:
                    slot = size
                    size += 1
                    touched[listed] = v
                    listed += 1
                _heap_up(hk, hn, pos, slot, nd + h, v)
    return listed


@_jit
def _astar_reset(touched, listed, dist, pred, pos):  # type: ignore[no-untyped-def]
    for i in range(listed):
        v = touched[i]
        dist[v] = np.inf
        pred[v] = -1
        pos[v] = -1


def _search_arrays(n: int) -> tuple[Any, ...]:
    """Fresh A* arrays for ``n`` nodes: ``dist`` inf, ``pred`` and ``pos`` -1, and the heap's
    keys, nodes and the touched list (filled as the search goes). Indices are int32 (grids
    stay far below 2³¹ cells; the caller checks): the working set of a 540 × 540 search is
    then 4.7 MB instead of 7 MB, about 1 ms less per replan when other work has evicted it
    from the cache (bench_replan's interleaved rounds)."""
    return (
        np.full(n, np.inf),
        np.full(n, -1, dtype=np.int32),
        np.full(n, -1, dtype=np.int32),
        np.empty(n),
        np.empty(n, dtype=np.int32),
        np.empty(n, dtype=np.int32),
    )


class _SearchWorkspace(threading.local):
    """One set of A* arrays per thread (the replanning worker and the control thread may
    search at once), kept between searches: only the entries the last search touched are
    reset, instead of allocating and filling ``5 x rows·cols`` entries per replan."""

    def __init__(self) -> None:
        self.n = -1
        self.listed = 0

    def arrays(self, n: int) -> tuple[Any, ...]:
        if self.n != n:
            self.kept = _search_arrays(n)
            self.n, self.listed = n, 0
        elif self.listed:
            dist, pred, pos, _, _, touched = self.kept
            _astar_reset(touched, self.listed, dist, pred, pos)
            self.listed = 0
        return self.kept


_WORKSPACE = _SearchWorkspace()
#: The neighbour order of :func:`astar` (that of the global planner's CSR graph).
ASTAR_OFFSETS = ((-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1))


def astar(
    costs: NDArray[np.uint8],
    passable: NDArray[np.bool_],
    start: int,
    goal: int,
    steps: NDArray[np.float64],
    neutral_cost: float,
    cost_factor: float,
    resolution: float,
    reuse: bool = False,
) -> tuple[NDArray[np.float64], NDArray[np.int32]]:
    """Costs-to-come ``(rows·cols,)`` and predecessors (int32, ``-1``: none) of an A* search on the
    global planner's grid graph from flat ``start`` to flat ``goal`` (``-1``: every reachable
    cell, i.e. Dijkstra): the 8 neighbours in the order of :data:`ASTAR_OFFSETS`
    ``(d_row, d_col)``, whose move lengths are ``steps (8,)`` (m; else ``ValueError``).
    Exact where settled: the goal's cost, and with ``goal = -1`` or an unreachable goal the
    set of reachable cells, are those of a full Dijkstra; among paths of equal cost the one
    chosen may differ from SciPy's (ties broken by heap key, node index).
    ``reuse``: the two arrays are the calling thread's kept workspace (the same values),
    valid until that thread's next ``reuse`` search. Runs without the GIL."""
    steps = np.ascontiguousarray(steps, dtype=np.float64)
    if steps.shape != (8,):
        raise ValueError(f"steps must have shape (8,), got {steps.shape}")
    n = costs.size
    if n >= 2**31 - 1:
        raise ValueError(f"a grid of {n} cells is beyond the search's int32 indices")
    dist: NDArray[np.float64]
    pred: NDArray[np.int32]
    if reuse:
        ws = _WORKSPACE
        dist, pred, pos, hk, hn, touched = ws.arrays(n)
        ws.n = -1  # unknown state until the search returns (an interrupted one reallocates)
    else:
        dist, pred, pos, hk, hn, touched = _search_arrays(n)
    # Every move costs at least its length x neutral_cost; a hair less keeps h a lower bound
    # after rounding.
    h_scale = float(neutral_cost) * float(resolution) * (1.0 - 1e-9)
    listed = _astar_kernel(
        np.ascontiguousarray(costs, dtype=np.uint8),
        np.ascontiguousarray(passable, dtype=np.bool_),
        int(start),
        int(goal),
        steps,
        float(neutral_cost),
        float(cost_factor) * 0.5,
        h_scale,
        dist,
        pred,
        pos,
        hk,
        hn,
        touched,
    )
    if reuse:
        ws.n, ws.listed = n, listed
    return dist, pred


@_jit
def _chain_kernel(pred, start, goal):  # type: ignore[no-untyped-def]
    m = 1
    node = goal
    while node != start:
        node = pred[node]
        m += 1
    out = np.empty(m, dtype=np.int64)
    node = goal
    for i in range(m - 1, -1, -1):
        out[i] = node
        if i:
            node = pred[node]
    return out


def predecessor_chain(pred: NDArray[np.integer[Any]], start: int, goal: int) -> NDArray[np.int64]:
    """The flat nodes ``(P,)`` from ``start`` to ``goal`` along ``pred`` (a search tree rooted
    at ``start`` that reaches ``goal``)."""
    out: NDArray[np.int64] = _chain_kernel(pred, int(start), int(goal))
    return out


# ---- personal-space (proxemic) layer ---------------------------------------------------------


@_jit
def _proxemic_exponents(  # type: ignore[no-untyped-def]
    windows, semi, first, last, ox, oy, res, cols_n, variance, threshold, flat, expo
):
    """Windows ``first..last-1`` (rows ``(r0, r1, c0, c1, x, y, cos, sin, var_front,
    one_sided)``): the exponent ``-(mx² / 2σx² + my² / 2σ²)`` of each cell, with the
    reference's operations, for the cells of the window whose centre lies ahead in the
    ellipse ``semi[k] = (along, across)`` or behind in the disc of radius ``across`` (m, the
    cutoff's reach, a hair enlarged: together they contain the whole lobe), one row interval
    at a time; cells at or above ``threshold`` go to
    ``flat``/``expo``. Returns their count."""
    m = 0
    for k in range(first, last):
        r0, r1 = int(windows[k, 0]), int(windows[k, 1])
        c0, c1 = int(windows[k, 2]), int(windows[k, 3])
        x, y, c, s = windows[k, 4], windows[k, 5], windows[k, 6], windows[k, 7]
        var_front = windows[k, 8]
        one_sided = windows[k, 9] != 0.0
        ia = 1.0 / (semi[k, 0] * semi[k, 0])
        ib = 1.0 / (semi[k, 1] * semi[k, 1])
        qa = c * c * ia + s * s * ib  # dx² coefficient of (mx/a)² + (my/b)² (> 0)
        b2 = semi[k, 1] * semi[k, 1]
        for r in range(r0, r1):
            dy = oy + (r + 0.5) * res - y
            # Behind the person (mx <= 0) the lobe is the disc of radius ``across``; ahead,
            # the half of the ellipse with mx >= 0: the hull of the two row intervals.
            lo, hi = np.inf, -np.inf
            qb = 2.0 * dy * c * s * (ia - ib)
            qc = dy * dy * (s * s * ia + c * c * ib) - 1.0
            disc = qb * qb - 4.0 * qa * qc
            if disc >= 0.0:
                root = np.sqrt(disc)
                lo = (-qb - root) / (2.0 * qa)
                hi = (-qb + root) / (2.0 * qa)
                if c > 1e-9:  # mx = dx c + dy s >= 0
                    lo = max(lo, -dy * s / c)
                elif c < -1e-9:
                    hi = min(hi, -dy * s / c)
                if lo > hi:
                    lo, hi = np.inf, -np.inf
            if dy * dy <= b2:
                w = np.sqrt(b2 - dy * dy)
                lo, hi = min(lo, -w), max(hi, w)
            if lo > hi:
                continue
            q0 = max(int(np.floor((x + lo - ox) / res - 0.5)) - 1, c0)
            q1 = min(int(np.ceil((x + hi - ox) / res - 0.5)) + 2, c1)
            for q in range(q0, q1):
                dx = ox + (q + 0.5) * res - x
                mx = dx * c + dy * s
                if one_sided and mx < 0.0:
                    continue
                my = dy * c - dx * s
                sx2 = var_front if mx > 0.0 else variance
                e = -(mx * mx / (2.0 * sx2) + my * my / (2.0 * variance))
                if e >= threshold:
                    if m >= flat.shape[0]:
                        return -1  # cannot happen (the caller's bound): never write past
                    flat[m] = r * cols_n + q
                    expo[m] = e
                    m += 1
    return m


@_jit
def _scatter_cost(flat, e, m, amplitude, cutoff, out):  # type: ignore[no-untyped-def]
    """The reference's ``a = amplitude · e``, kept where ``a >= cutoff``, as
    ``uint8(floor(a))`` maxed into ``out`` at ``flat`` (the first ``m`` entries): the same
    operations in one pass instead of five array passes."""
    for i in range(m):
        a = amplitude * e[i]
        if a >= cutoff:
            v = np.uint8(np.floor(a))
            if v > out[flat[i]]:
                out[flat[i]] = v


_PROXEMIC_BATCH = 1 << 18  # cells per compiled pass (bounds the buffers: 4 MB)


def _batches(
    cells: NDArray[np.int64],
) -> tuple[NDArray[np.int64], NDArray[np.float64], list[tuple[int, int]]]:
    """Cell-index and exponent buffers for one compiled pass, and the window spans
    ``[first, last)`` (in order) whose visited ``cells (K,)`` fit them together (a window
    larger than the batch gets buffers of its own size)."""
    size = int(max(_PROXEMIC_BATCH, cells.max()))
    spans: list[tuple[int, int]] = []
    first = 0
    while first < len(cells):
        last, total = first, 0
        while last < len(cells) and total + cells[last] <= size:
            total += int(cells[last])
            last += 1
        spans.append((first, last))
        first = last
    return np.empty(size, dtype=np.int64), np.empty(size), spans


def proxemic_costs(
    geometry: GridGeometry,
    positions: NDArray[np.float64],
    velocities: NDArray[np.float64],
    amplitude: float = 77.0,
    variance: float = 0.25,
    cutoff: float = 10.0,
    velocity_factor: float = 5.0,
    passing: bool = False,
) -> NDArray[np.uint8]:
    """:func:`socialnav.world.proxemic_layer.proxemic_costs`, the same uint8 layer (same
    errors): a compiled pass visits only the cells of each person's window inside the
    ellipse that bounds the lobe (work ~ the cells the person actually costs, clipped to the
    grid) and computes their exponents; NumPy's ``exp`` (the reference's) runs only on the
    cells that reach ``cutoff``."""
    windows = person_windows(
        geometry, positions, velocities, amplitude, variance, cutoff, velocity_factor, passing
    )
    out = np.zeros(geometry.shape, dtype=np.uint8)
    if not windows:
        return out
    table = np.array(windows, dtype=np.float64)  # (K, 10)
    res = float(geometry.resolution)
    log_ratio = float(np.log(cutoff / amplitude))  # < 0
    # Reach of the cutoff along / across the lobe: sqrt(-2 var log(cutoff / A)), enlarged.
    along = np.sqrt(-2.0 * table[:, 8] * log_ratio) * (1.0 + 1e-6) + 1e-9
    across = np.sqrt(-2.0 * variance * log_ratio) * (1.0 + 1e-6) + 1e-9
    semi = np.column_stack([np.maximum(along, across), np.full(len(windows), across)])
    # A window's visited cells are at most its area, and at most the ellipse's box.
    area = (table[:, 1] - table[:, 0]) * (table[:, 3] - table[:, 2])
    box = (2.0 * semi[:, 0] / res + 8.0) ** 2
    cells = np.minimum(area, box).astype(np.int64)
    threshold = log_ratio - 1e-6  # exp is monotone; the margin absorbs rounding
    ox, oy = geometry.origin
    flat_out = out.reshape(-1)
    flat, expo, spans = _batches(cells)
    for first, last in spans:
        m = _proxemic_exponents(
            table, semi, first, last, float(ox), float(oy), res, int(geometry.shape[1]),
            float(variance), threshold, flat, expo,
        )  # fmt: skip
        if m < 0:  # pragma: no cover - the bound above holds; stay correct regardless
            return proxemic_layer.proxemic_costs(
                geometry, positions, velocities, amplitude, variance, cutoff, velocity_factor,
                passing,
            )  # fmt: skip
        e = np.exp(expo[:m], out=expo[:m])  # NumPy's exp, the reference's
        _scatter_cost(flat, e, m, float(amplitude), float(cutoff), flat_out)
    return out


# ---- meeting layer ---------------------------------------------------------------------------


@_jit
def _meeting_exponents(  # type: ignore[no-untyped-def]
    windows, samples, first, last, ox, oy, res, cols_n, sx, sy, speed, tau0, tau_rate,
    variance, two_var, depth, flat, expo,
):  # fmt: skip
    """Windows ``first..last-1`` (rows ``(r0, r1, c0, c1, x, y, vx, vy, den, h, s0, s1,
    radius)``): the exponent ``-min_t E`` of each cell with the reference's operations
    (:func:`socialnav.world.meeting_layer.meeting_costs`), visiting per row only the columns
    within ``radius`` of the window's lane points ``samples[s0:s1]`` (the others are below
    the cutoff); cells with ``E <= depth`` go to ``flat``/``expo``. Returns their count (-1
    if the buffers would overflow)."""
    m = 0
    for k in range(first, last):
        r0, r1 = int(windows[k, 0]), int(windows[k, 1])
        c0, c1 = int(windows[k, 2]), int(windows[k, 3])
        x, y, vx, vy = windows[k, 4], windows[k, 5], windows[k, 6], windows[k, 7]
        den, h = windows[k, 8], windows[k, 9]
        s0, s1, radius = int(windows[k, 10]), int(windows[k, 11]), windows[k, 12]
        r2 = radius * radius
        for r in range(r0, r1):
            yc = oy + (r + 0.5) * res
            dy = yc - y
            lo, hi = np.inf, -np.inf
            for i in range(s0, s1):
                gy = yc - samples[i, 1]
                if gy * gy <= r2:
                    half = np.sqrt(r2 - gy * gy)
                    lo = min(lo, samples[i, 0] - half)
                    hi = max(hi, samples[i, 0] + half)
            if lo > hi:
                continue
            q0 = max(int(np.floor((lo - ox) / res - 0.5)) - 1, c0)
            q1 = min(int(np.ceil((hi - ox) / res - 0.5)) + 2, c1)
            for q in range(q0, q1):
                xc = ox + (q + 0.5) * res
                dx = xc - x
                arrive = math.hypot(xc - sx, yc - sy) / speed
                w = tau0 + tau_rate * arrive
                inv_tau2 = 1.0 / (w * w)
                t = ((dx * vx + dy * vy) / variance + arrive * inv_tau2) / (den + inv_tau2)
                t = min(max(t, 0.0), h)
                ex = dx - t * vx
                ey = dy - t * vy
                lag = arrive - t
                e = (ex * ex + ey * ey) / two_var + 0.5 * lag * lag * inv_tau2
                if e <= depth:
                    if m >= flat.shape[0]:
                        return -1
                    flat[m] = r * cols_n + q
                    expo[m] = -e
                    m += 1
    return m


def meeting_costs(
    geometry: GridGeometry,
    positions: NDArray[np.float64],
    velocities: NDArray[np.float64],
    start_xy: NDArray[np.float64],
    speed: float,
    amplitude: float = 250.0,
    variance: float = 0.64,
    cutoff: float = 5.0,
    horizon: float = 10.0,
    tau0: float = 1.0,
    tau_rate: float = 0.25,
    lane_step: float = 0.25,
) -> NDArray[np.uint8]:
    """:func:`socialnav.world.meeting_layer.meeting_costs`, the same uint8 layer (same
    errors): one compiled pass per batch of walker windows computes the exponents without
    temporaries; NumPy's ``exp`` (the reference's) runs only on the cells above the cutoff."""
    start, windows, samples = meeting_layer.meeting_windows(
        geometry, positions, velocities, start_xy, speed, amplitude, variance, cutoff,
        horizon, tau0, tau_rate, lane_step,
    )  # fmt: skip
    out = np.zeros(geometry.shape, dtype=np.uint8)
    if not windows:
        return out
    table = np.array(windows, dtype=np.float64)  # (K, 13)
    cells = ((table[:, 1] - table[:, 0]) * (table[:, 3] - table[:, 2])).astype(np.int64)
    depth = float(np.log(amplitude / cutoff))
    samples = np.ascontiguousarray(samples, dtype=np.float64)
    ox, oy = geometry.origin
    flat_out = out.reshape(-1)
    flat, expo, spans = _batches(cells)
    for first, last in spans:
        m = _meeting_exponents(
            table, samples, first, last, float(ox), float(oy), float(geometry.resolution),
            int(geometry.shape[1]), float(start[0]), float(start[1]), float(speed),
            float(tau0), float(tau_rate), float(variance), 2.0 * variance, depth, flat, expo,
        )  # fmt: skip
        if m < 0:  # pragma: no cover - a window's cells fit the buffer by construction
            return meeting_layer.meeting_costs(
                geometry, positions, velocities, start_xy, speed, amplitude, variance, cutoff,
                horizon, tau0, tau_rate, lane_step,
            )  # fmt: skip
        e = np.exp(expo[:m], out=expo[:m])  # NumPy's exp, the reference's
        _scatter_cost(flat, e, m, float(amplitude), float(cutoff), flat_out)
    return out


# ---- BFS map grids ---------------------------------------------------------------------------


@_jit
def _bfs_state_kernel(passable, r0, r1, c0, c1, state):  # type: ignore[no-untyped-def]
    # Padded state: 0 blocked or pad (never entered), 1 passable, 2 passable inside the settle
    # box. Returns how many cells are 2.
    rows, cols = passable.shape
    w = cols + 2
    count = 0
    for r in range(rows):
        base = (r + 1) * w + 1
        inside_r = r0 <= r < r1
        for c in range(cols):
            if passable[r, c]:
                if inside_r and c0 <= c < c1:
                    state[base + c] = 2
                    count += 1
                else:
                    state[base + c] = 1
    return count


@_jit
def _bfs_flood_kernel(state, count, seeds, w, dist):  # type: ignore[no-untyped-def]
    # Level-synchronous BFS on the padded flat grid (no bounds checks, no division). A cell is
    # entered once (its state drops to 0), so blocked cells are never reached — the reference
    # reaches them without expanding and resets them to inf: same values; seeds expand whatever
    # their cost. Every cell gets its final level when first entered, so the flood stops as soon
    # as every passable cell of the settle box has one (``count`` left to enter).
    n = state.size
    queue = np.empty(n, dtype=np.int32)
    tail = 0
    remaining = count
    for k in range(seeds.shape[0]):
        u = (seeds[k, 0] + 1) * w + seeds[k, 1] + 1
        if dist[u] != 0.0:
            dist[u] = 0.0
            if state[u] == 2:
                remaining -= 1
            state[u] = 0
            queue[tail] = u
            tail += 1
    head = 0
    level = np.float32(0.0)
    while head < tail and remaining > 0:
        stop = tail
        level = level + np.float32(1.0)
        while head < stop:
            u = queue[head]
            head += 1
            for v in (u - w, u - 1, u + 1, u + w):
                sv = state[v]
                if sv != 0:
                    if sv == 2:
                        remaining -= 1
                    state[v] = 0
                    dist[v] = level
                    queue[tail] = v
                    tail += 1
            if remaining == 0:
                break


def bfs_distance(
    passable: NDArray[np.bool_],
    seeds: NDArray[np.intp],
    settle: tuple[slice, slice] | None = None,
    state: tuple[NDArray[np.uint8], int] | None = None,
) -> NDArray[np.float32]:
    """4-connected BFS step counts ``(rows, cols)`` float32 from in-grid ``seeds (K, 2)``
    (row, col): :func:`socialnav.planner.critics.map_grid.bfs_distance` semantics (seeds 0
    whatever their cost, blocked cells never expand and read ``inf``; exact inside ``settle``,
    elsewhere exact or ``inf``; exact everywhere without ``settle``). ``state`` is a
    :func:`bfs_state` of the same mask and ``settle`` (shared by several floods)."""
    rows, cols = passable.shape
    if state is None:
        state = bfs_state(passable, settle)
    dist = np.full((rows + 2) * (cols + 2), np.inf, dtype=np.float32)
    seeds = np.ascontiguousarray(seeds, dtype=np.int64).reshape(-1, 2)
    if seeds.shape[0]:
        _bfs_flood_kernel(state[0].copy(), state[1], seeds, cols + 2, dist)
    return dist.reshape(rows + 2, cols + 2)[1:-1, 1:-1]


def bfs_state(
    passable: NDArray[np.bool_], settle: tuple[slice, slice] | None = None
) -> tuple[NDArray[np.uint8], int]:
    """The padded flood state of ``passable (rows, cols)`` and the number of passable cells in
    ``settle`` (the whole grid without it) for :func:`bfs_distance`."""
    rows, cols = passable.shape
    if settle is None:
        box = (0, rows, 0, cols)
    else:
        rs, cs = settle
        box = (*rs.indices(rows)[:2], *cs.indices(cols)[:2])
    state = np.zeros((rows + 2) * (cols + 2), dtype=np.uint8)
    count = _bfs_state_kernel(np.ascontiguousarray(passable, dtype=np.bool_), *box, state)
    return state, int(count)


# ---- plan densification and plan cells ------------------------------------------------------


@_jit
def _densify_kernel(path, spacing):  # type: ignore[no-untyped-def]
    # densify_path's reference step by step: arc length by np.linalg.norm (sqrt(dx² + dy²)) and
    # a sequential cumsum, the query points of np.arange (i * spacing, ceil(stop / spacing) of
    # them) plus the end, and np.interp's formula (slope · (q − s[j]) + fp[j], s[j] ≤ q < s[j+1],
    # q == s[j] → fp[j], the end → fp[-1], its NaN fallbacks).
    m = path.shape[0]
    s = np.empty(m)
    s[0] = 0.0
    acc = 0.0
    for i in range(1, m):
        dx = path[i, 0] - path[i - 1, 0]
        dy = path[i, 1] - path[i - 1, 1]
        acc += np.sqrt(dx * dx + dy * dy)
        s[i] = acc
    stop = s[m - 1]
    n = int(np.ceil(stop / spacing))
    out = np.empty((n + 1, 2))
    j = 0
    for i in range(n + 1):
        q = i * spacing if i < n else stop
        if q >= stop:
            out[i, 0] = path[m - 1, 0]
            out[i, 1] = path[m - 1, 1]
            continue
        while s[j + 1] <= q:
            j += 1
        for a in range(2):
            if s[j] == q:
                out[i, a] = path[j, a]
                continue
            slope = (path[j + 1, a] - path[j, a]) / (s[j + 1] - s[j])
            v = slope * (q - s[j]) + path[j, a]
            if np.isnan(v):
                v = slope * (q - s[j + 1]) + path[j + 1, a]
                if np.isnan(v) and path[j, a] == path[j + 1, a]:
                    v = path[j, a]
            out[i, a] = v
    return out


def densify_path(path: NDArray[np.float64], spacing: float) -> NDArray[np.float64]:
    """:func:`socialnav.planner.critics.map_grid.densify_path` for a finite ``(P, 2)`` path of
    positive length and ``P >= 2``, bit for bit."""
    return _densify_kernel(np.ascontiguousarray(path, dtype=np.float64), float(spacing))


@_jit
def _arc_lengths_kernel(dense, out):  # type: ignore[no-untyped-def]
    out[0] = 0.0
    for k in range(1, dense.shape[0]):
        dx = dense[k, 0] - dense[k - 1, 0]
        dy = dense[k, 1] - dense[k - 1, 1]
        out[k] = out[k - 1] + np.sqrt(dx * dx + dy * dy)  # 0.0 + x is x: cumsum's first term


def arc_lengths(dense: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(P,)`` arc length (m) at each vertex of a ``(P, 2)`` polyline, P >= 1: the values of
    ``concatenate([[0], cumsum(norm(diff(dense), axis=1))])`` in one pass."""
    out = np.empty(dense.shape[0])
    _arc_lengths_kernel(np.ascontiguousarray(dense, dtype=np.float64), out)
    return out


@_jit
def _plan_cells_kernel(dense, ox, oy, res, costs, unknown):  # type: ignore[no-untyped-def]
    # local_plan_cells' reference: world_to_cell per point, then the first contiguous run of
    # in-grid cells that are not UNKNOWN.
    rows, cols = costs.shape
    m = dense.shape[0]
    rc = np.empty((m, 2), dtype=np.intp)
    first = -1
    last = m
    for i in range(m):
        c = int(np.floor((dense[i, 0] - ox) / res))
        r = int(np.floor((dense[i, 1] - oy) / res))
        rc[i, 0] = r
        rc[i, 1] = c
        ok = 0 <= r < rows and 0 <= c < cols and costs[r, c] != unknown
        if first < 0:
            if ok:
                first = i
        elif not ok:
            last = i
            break
    if first < 0:
        return rc[:0].copy()
    return rc[first:last].copy()


def plan_cells(
    geom: GridGeometry, costs: NDArray[np.uint8], dense: NDArray[np.float64], unknown: int
) -> NDArray[np.intp]:
    """:func:`socialnav.planner.critics.map_grid.local_plan_cells` of a finite densified plan
    ``dense (P, 2)`` (m), bit for bit: ``(K, 2)`` (row, col)."""
    return _plan_cells_kernel(
        np.ascontiguousarray(dense, dtype=np.float64),
        float(geom.origin[0]),
        float(geom.origin[1]),
        float(geom.resolution),
        np.ascontiguousarray(costs),
        unknown,
    )


# ---- occupancy clearance (exact Euclidean distance transform) --------------------------------


@_jit
def _clearance_kernel(free, cap, i0, j0, out):  # type: ignore[no-untyped-def]
    # Exact squared Euclidean distance to the nearest False cell of ``free`` (Felzenszwalb &
    # Huttenlocher: per column the 1-D distance, then per row the lower envelope of parabolas
    # over the columns that have a False cell; integer arithmetic, the intersections compared
    # as doubles, which separates distinct rationals of this size). Then
    # ``floor(min(sqrt(d), cap) * 16)`` for the box ``out`` at (i0, j0): scipy's
    # distance_transform_edt gives sqrt of the same integer (its feature transform is exact).
    h, w = free.shape
    big = h + w + 1
    g = np.empty((h, w), dtype=np.int64)
    for c in range(w):
        last = -big
        for r in range(h):
            if not free[r, c]:
                last = r
            g[r, c] = r - last if last > -big else -1
        last = -big
        for r in range(h - 1, -1, -1):
            if not free[r, c]:
                last = r
            if last > -big and (g[r, c] < 0 or last - r < g[r, c]):
                g[r, c] = last - r
    oh, ow = out.shape
    v = np.empty(w, dtype=np.int64)
    z = np.empty(w + 1)
    fv = np.empty(w, dtype=np.int64)
    for r in range(i0, i0 + oh):
        k = -1
        for q in range(w):
            gq = g[r, q]
            if gq < 0:
                continue
            fq = gq * gq
            if k < 0:
                k = 0
                v[0] = q
                fv[0] = fq
                z[0] = -np.inf
                z[1] = np.inf
                continue
            while True:  # z[0] = -inf: never pops the first parabola
                p = v[k]
                sq = ((fq + q * q) - (fv[k] + p * p)) / (2.0 * (q - p))
                if sq > z[k]:
                    break
                k -= 1
            k += 1
            v[k] = q
            fv[k] = fq
            z[k] = sq
            z[k + 1] = np.inf
        k = 0
        for c in range(j0, j0 + ow):
            while z[k + 1] < c:
                k += 1
            d = (c - v[k]) * (c - v[k]) + fv[k]
            x = min(np.sqrt(np.float64(d)), cap)
            out[r - i0, c - j0] = np.uint16(np.floor(x * 16.0))


def clearance_levels(
    free: NDArray[np.bool_], cap: float, i0: int, j0: int, out: NDArray[np.uint16]
) -> None:
    """Fill ``out (h, w)`` with ``floor(min(edt(free), cap) * 16)`` of the box of ``free`` at
    ``(i0, j0)``, where ``edt`` is :func:`scipy.ndimage.distance_transform_edt` (cells to the
    nearest False cell; ``free`` must have one), bit for bit."""
    _clearance_kernel(np.ascontiguousarray(free, dtype=np.bool_), float(cap), i0, j0, out)


# ---- footprint cells -----------------------------------------------------------------------


@_jit
def _footprint_kernel(poly, px, py, ox, oy, res, mask):  # type: ignore[no-untyped-def]
    # footprint_cells' reference: the polygon's cell box (world_to_cell of its min and max,
    # clipped), points_in_polygon at cell_to_world centres (the same IEEE operations per cell
    # and edge), then the centre cell.
    rows, cols = mask.shape
    nv = poly.shape[0]
    xmin, ymin, xmax, ymax = poly[0, 0], poly[0, 1], poly[0, 0], poly[0, 1]
    for i in range(1, nv):
        xmin = min(xmin, poly[i, 0])
        xmax = max(xmax, poly[i, 0])
        ymin = min(ymin, poly[i, 1])
        ymax = max(ymax, poly[i, 1])
    r0 = max(int(np.floor((ymin - oy) / res)), 0)
    r1 = min(int(np.floor((ymax - oy) / res)) + 1, rows)
    c0 = max(int(np.floor((xmin - ox) / res)), 0)
    c1 = min(int(np.floor((xmax - ox) / res)) + 1, cols)
    for r in range(r0, r1):
        y = oy + (np.float64(r) + 0.5) * res
        for c in range(c0, c1):
            x = ox + (np.float64(c) + 0.5) * res
            count = 0
            for i in range(nv):
                j = i + 1 if i + 1 < nv else 0
                x0, y0 = poly[i, 0], poly[i, 1]
                x1, y1 = poly[j, 0], poly[j, 1]
                if (y0 > y) != (y1 > y):
                    dy = y1 - y0 if y1 != y0 else 1.0
                    if x < x0 + (y - y0) * (x1 - x0) / dy:
                        count += 1
            mask[r, c] = count % 2 == 1
    r = int(np.floor((py - oy) / res))
    c = int(np.floor((px - ox) / res))
    if 0 <= r < rows and 0 <= c < cols:
        mask[r, c] = True


def footprint_mask(
    geom: GridGeometry, polygon: NDArray[np.float64], centre: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """``(rows, cols)`` mask of the cells whose centre lies inside the world polygon ``(V, 2)``
    (m), plus the cell of ``centre (2,)`` (m): bit for bit
    :func:`socialnav.planner.critics.map_grid.footprint_cells`' reference (finite input)."""
    mask = np.zeros(geom.shape, dtype=np.bool_)
    _footprint_kernel(
        np.ascontiguousarray(polygon, dtype=np.float64),
        float(centre[0]),
        float(centre[1]),
        float(geom.origin[0]),
        float(geom.origin[1]),
        float(geom.resolution),
        mask,
    )
    return mask


# ---- timed passing: one lattice period -------------------------------------------------------


@_jit
def _lattice_period_kernel(  # type: ignore[no-untyped-def]
    states, commands, acc, step, times, people, vel, need, low_in, s_out, poses, alive, low
):
    """The operations of :func:`socialnav.planner.passing.lattice_period_reference` per
    (state, command) row ``i * C + j``, in its order; a row stops at its first sample nearer
    than ``need`` to someone (it is dropped: its other outputs are left unset)."""
    n, nc, steps, k_people = states.shape[0], commands.shape[0], times.shape[0] - 1, people.shape[0]
    for i in range(n):
        for j in range(nc):
            r = i * nc + j
            x, y, th = states[i, 0], states[i, 1], states[i, 2]
            vx, vy, w = states[i, 3], states[i, 4], states[i, 5]
            lo = low_in[i]
            ok = True
            poses[r, 0, 0] = x
            poses[r, 0, 1] = y
            poses[r, 0, 2] = th
            for k in range(steps):
                vx += min(max(commands[j, 0] - vx, -acc[0]), acc[0])
                vy += min(max(commands[j, 1] - vy, -acc[1]), acc[1])
                w += min(max(commands[j, 2] - w, -acc[2]), acc[2])
                c = np.cos(th)
                sn = np.sin(th)
                x += (c * vx - sn * vy) * step
                y += (sn * vx + c * vy) * step
                th += w * step
                poses[r, k + 1, 0] = x
                poses[r, k + 1, 1] = y
                poses[r, k + 1, 2] = th
                tk = times[k + 1]
                for q in range(k_people):
                    d = math.hypot(
                        people[q, 0] + tk * vel[q, 0] - x, people[q, 1] + tk * vel[q, 1] - y
                    )
                    if d < need[q]:
                        ok = False
                    if d < lo:
                        lo = d
                if not ok:
                    break
            alive[r] = ok
            low[r] = lo
            s_out[r, 0] = x
            s_out[r, 1] = y
            s_out[r, 2] = th
            s_out[r, 3] = vx
            s_out[r, 4] = vy
            s_out[r, 5] = w


def lattice_period(
    states: NDArray[np.float64],
    commands: NDArray[np.float64],
    acc: NDArray[np.float64],
    step: float,
    times: NDArray[np.float64],
    people: NDArray[np.float64],
    vel: NDArray[np.float64],
    need: NDArray[np.float64],
    low_in: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], NDArray[np.float64]]:
    """:func:`socialnav.planner.passing.lattice_period_reference` compiled: the same values on
    every row that stays alive (a dropped row's state, poses and distance are unset)."""
    rows = states.shape[0] * commands.shape[0]
    s_out = np.empty((rows, 6))
    poses = np.empty((rows, times.shape[0], 3))
    alive = np.empty(rows, dtype=np.bool_)
    low = np.empty(rows)
    f64 = np.float64
    _lattice_period_kernel(
        np.ascontiguousarray(states, dtype=f64),
        np.ascontiguousarray(commands, dtype=f64),
        np.ascontiguousarray(acc, dtype=f64),
        float(step),
        np.ascontiguousarray(times, dtype=f64),
        np.ascontiguousarray(people, dtype=f64).reshape(-1, 2),
        np.ascontiguousarray(vel, dtype=f64).reshape(-1, 2),
        np.ascontiguousarray(need, dtype=f64),
        np.ascontiguousarray(low_in, dtype=f64),
        s_out,
        poses,
        alive,
        low,
    )
    return s_out, poses, alive, low


# ---- warm-up -------------------------------------------------------------------------------


def warmup() -> float:
    """Compile (or load from the cache) every kernel for the planner's argument types; returns
    and records in :data:`compile_seconds` the seconds spent. Idempotent and cheap after the
    first call of a process."""
    global compile_seconds, _warm
    if _warm or not _AVAILABLE:
        return 0.0
    start = time.perf_counter()
    pose = np.zeros(3)
    twists = np.array([[0.1, 0.0, 0.1], [0.2, 0.1, -0.1]])
    t = np.linspace(0.0, 1.0, 4)
    poses = rollout_poses(pose, twists, t, 1.0 / 3.0)
    costs = np.zeros((4, 4), np.uint8)
    outline = np.array([[0.1, 0.0], [0.0, 0.1]])
    codes = np.zeros(64, np.uint8)
    sizes = np.array([1, 2], dtype=np.intp)
    clear = (np.zeros((4, 4), np.uint16), np.array([2, 1], dtype=np.intp))
    for data, clr, circ in (
        ((outline, codes, 2, 8), clear, None),
        ((outline, codes, 2, 8), None, 200),
        (None, None, None),
    ):
        occupancy_scan(poses, 1, costs, (0.0, 0.0), 0.25, data, clr, circ, sizes, 8)
    out = np.full((2, 1), np.inf)
    min_squared_distances(poses, np.zeros((4, 1, 2)), np.array([0], np.intp), out)
    people = np.array([0], np.intp)
    min_squared_distances_culled(poses, np.zeros((4, 1, 2)), people, np.ones(1), out)
    walk = np.zeros((1, 2))
    flags = np.ones(1, dtype=np.bool_)
    person_distances(out, people, poses[:, -1, :2], walk, walk, flags, np.ones(1), flags)
    approaches(poses, t, np.zeros((4, 1, 2)), out, people, np.ones(1), 0.02)
    signed_distance_to_polygon(np.zeros((2, 2)), outline)
    bfs_distance(np.ones((3, 3), dtype=bool), np.array([[1, 1]], dtype=np.intp))
    footprint_mask(GridGeometry((4, 4), 0.25), outline, pose)
    dense = densify_path(np.array([[0.0, 0.0], [1.0, 0.5]]), 0.1)
    arc_lengths(dense)
    plan_cells(GridGeometry((4, 4), 0.25), costs, dense, 255)
    clearance_levels(costs != 0, 3.0, 0, 0, np.zeros((4, 4), np.uint16)[1:3, 1:3])
    time_box(poses)
    nearest_vertex(poses[:, -1], np.zeros((2, 2)))
    one = np.ones(1)
    lattice_period(np.zeros((1, 6)), twists, np.ones(3), 0.1, t, walk, walk, one, one)
    end_point_costs(poses, (0.0, 0.0), 0.25, np.zeros((4, 4), np.float32), costs == 0)
    hit_codes(costs, 253, 2, 2)
    grid_weights(costs, costs == 0, np.array([[0, 1]]), np.array([0.25]), 50.0, 3.0)
    proxemic_costs(GridGeometry((4, 4), 0.25), np.ones((1, 2)), np.ones((1, 2)), passing=True)
    meeting_costs(GridGeometry((4, 4), 0.25), np.ones((1, 2)), np.ones((1, 2)), np.zeros(2), 0.5)
    from socialnav.world.raster import rasterize

    rasterize(GridGeometry((4, 4), 0.25), discs=np.array([[0.5, 0.5, 0.3]]))
    for goal in (15, -1):
        for reuse in (False, True):
            astar(costs, costs == 0, 0, goal, np.ones(8), 50.0, 3.0, 0.1, reuse)
    for dtype in (np.int64, np.int32):  # ours and SciPy's predecessors
        predecessor_chain(np.array([-1, 0], dtype=dtype), 0, 1)
    min_squared_distances(poses[:, -1:], np.zeros((1, 1, 2)), np.array([0], np.intp), out)
    from socialnav.world.costmap import _disc_costs, _disc_finish

    box = np.array([[0, 2, 0, 2]], dtype=np.int64)
    _disc_costs(costs == 0, box, 1, np.zeros(3, np.uint8), np.zeros((4, 4), np.uint8))
    _disc_finish(costs == 0, costs, np.zeros((4, 4), np.uint8))
    from socialnav.moo.paccet import warmup as paccet_warmup

    paccet_warmup()
    compile_seconds = time.perf_counter() - start
    _warm = True
    return compile_seconds

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

import time

import numpy as np
from numpy.typing import NDArray

from socialnav.core.jit import AVAILABLE as _AVAILABLE
from socialnav.core.jit import KernelSwitch, njit

#: Seconds the last :func:`warmup` spent compiling or loading cached kernels (0 if never run).
compile_seconds = 0.0
_warm = False
_SWITCH = KernelSwitch(lambda: warmup())


def enabled() -> bool:
    """Whether the compiled kernels are used (module docstring)."""
    return _SWITCH.on


def set_enabled(value: bool) -> bool:
    """Switch between the compiled kernels (``True``, needs numba) and the NumPy reference;
    returns the previous setting. Raises ``RuntimeError`` asking for numba when unavailable."""
    return _SWITCH.set(value, "the compiled kernels")


_jit = njit


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
def _rollout_kernel(x0, y0, th0, twists, t, dt, two_pi, pi, out):  # type: ignore[no-untyped-def]
    """``out (N, T, 3)``: the operations of :func:`socialnav.planner.rollout.rollout` in its
    order (heading ``th0 + w t``, Euler step with the previous heading, sequential cumulative
    sum, then the start added, yaw wrapped to ``[-pi, pi)``)."""
    n, steps = twists.shape[0], t.shape[0]
    for i in range(n):
        vx = twists[i, 0]
        vy = twists[i, 1]
        w = twists[i, 2]
        out[i, 0, 0] = x0
        out[i, 0, 1] = y0
        sx = 0.0
        sy = 0.0
        th = th0 + w * t[0]
        out[i, 0, 2] = _wrap(th, two_pi, pi)
        for k in range(1, steps):
            ck = np.cos(th)
            sk = np.sin(th)
            sx += (vx * ck - vy * sk) * dt
            sy += (vx * sk + vy * ck) * dt
            out[i, k, 0] = sx + x0
            out[i, k, 1] = sy + y0
            th = th0 + w * t[k]
            out[i, k, 2] = _wrap(th, two_pi, pi)


def rollout_poses(
    pose: NDArray[np.float64], twists: NDArray[np.float64], t: NDArray[np.float64], dt: float
) -> NDArray[np.float64]:
    """float64 poses ``(N, T, 3)`` of constant ``twists (N, 3)`` from ``pose (3,)`` on the time
    grid ``t (T,)`` s with step ``dt`` s; bit-identical to the NumPy rollout (module doc)."""
    twists = np.ascontiguousarray(twists, dtype=np.float64)
    out = np.empty((twists.shape[0], t.size, 3))
    _rollout_kernel(
        float(pose[0]),
        float(pose[1]),
        float(pose[2]),
        twists,
        np.ascontiguousarray(t, dtype=np.float64),
        float(dt),
        2.0 * np.pi,
        np.pi,
        out,
    )
    return out


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
        for k in range(steps):
            cx = np.floor((poses[i, first + k, 0] - ox) * inv)
            cy = np.floor((poses[i, first + k, 1] - oy) * inv)
            v = 255
            if 0.0 <= cy < rows and 0.0 <= cx < cols:
                v = costs[int(cy), int(cx)]
            if v == 255:
                unk = True
            elif v >= 253:
                col_hit = True
            elif v > w:
                w = v
        worst[i] = w
        if footprint and not unk and not col_hit:
            # Outline points per pose (the NumPy reference's need, rounded up to its groups);
            # after a LETHAL hit the current chunk still finishes, as in the reference.
            stop = steps
            for k in range(steps):
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


# ---- people --------------------------------------------------------------------------------


@_jit
def _d2min_kernel(xy, forecast, out):  # type: ignore[no-untyped-def]
    """``out (N, J)`` = min over ``t`` of the squared distance of ``xy[i, t]`` to
    ``forecast[t, j]`` (``forecast (T, J, 2)`` gathered, contiguous); NaN sticks as in
    ``np.min``."""
    n, t = xy.shape[0], xy.shape[1]
    m = forecast.shape[1]
    for i in range(n):
        for j in range(m):
            out[i, j] = np.inf
        for k in range(t):
            x = xy[i, k, 0]
            y = xy[i, k, 1]
            for j in range(m):
                dx = x - forecast[k, j, 0]
                dy = y - forecast[k, j, 1]
                d = dx * dx + dy * dy
                if d < out[i, j] or d != d:
                    out[i, j] = d


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
    _d2min_kernel(
        np.ascontiguousarray(xy, dtype=np.float64),
        np.ascontiguousarray(np.asarray(forecast, dtype=np.float64)[:, people]),
        block,
    )
    out[:, people] = block


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
    xy = np.ascontiguousarray(xy, dtype=np.float64)
    lo = np.empty((xy.shape[1], 2))
    hi = np.empty((xy.shape[1], 2))
    if xy.shape[0] == 0:  # NumPy raises on an empty reduction: keep that behaviour
        return xy[..., :2].min(axis=0), xy[..., :2].max(axis=0)
    _time_box_kernel(xy, lo, hi)
    return lo, hi


@_jit
def _nearest_vertex_kernel(points, vertices, out):  # type: ignore[no-untyped-def]
    for i in range(points.shape[0]):
        px, py = points[i, 0], points[i, 1]
        best = np.inf
        arg = 0
        for v in range(vertices.shape[0]):
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


# ---- BFS map grids ---------------------------------------------------------------------------


@_jit
def _bfs_kernel(passable, seeds, dist):  # type: ignore[no-untyped-def]
    rows, cols = passable.shape
    queue = np.empty(rows * cols, dtype=np.int64)
    head = 0
    tail = 0
    for k in range(seeds.shape[0]):
        r, c = seeds[k, 0], seeds[k, 1]
        if dist[r, c] != 0.0:
            dist[r, c] = 0.0
            queue[tail] = r * cols + c
            tail += 1
    while head < tail:
        u = queue[head]
        head += 1
        r = u // cols
        c = u - r * cols
        d = dist[r, c]
        if d != 0.0 and not passable[r, c]:
            continue  # reached but blocked: never expands (seeds expand whatever their cost)
        d1 = d + np.float32(1.0)
        if r > 0 and dist[r - 1, c] == np.inf:
            dist[r - 1, c] = d1
            queue[tail] = u - cols
            tail += 1
        if c > 0 and dist[r, c - 1] == np.inf:
            dist[r, c - 1] = d1
            queue[tail] = u - 1
            tail += 1
        if c + 1 < cols and dist[r, c + 1] == np.inf:
            dist[r, c + 1] = d1
            queue[tail] = u + 1
            tail += 1
        if r + 1 < rows and dist[r + 1, c] == np.inf:
            dist[r + 1, c] = d1
            queue[tail] = u + cols
            tail += 1
    for r in range(rows):
        for c in range(cols):
            if not passable[r, c]:
                dist[r, c] = np.inf
    for k in range(seeds.shape[0]):
        dist[seeds[k, 0], seeds[k, 1]] = 0.0


def bfs_distance(passable: NDArray[np.bool_], seeds: NDArray[np.intp]) -> NDArray[np.float32]:
    """4-connected BFS step counts ``(rows, cols)`` float32 from in-grid ``seeds (K, 2)``
    (row, col), exact everywhere: :func:`socialnav.planner.critics.map_grid.bfs_distance`
    semantics (seeds 0 whatever their cost, blocked cells never expand and read ``inf``)."""
    dist = np.full(passable.shape, np.inf, dtype=np.float32)
    seeds = np.ascontiguousarray(seeds, dtype=np.int64).reshape(-1, 2)
    if seeds.shape[0]:
        _bfs_kernel(np.ascontiguousarray(passable, dtype=np.bool_), seeds, dist)
    return dist


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
    bfs_distance(np.ones((3, 3), dtype=bool), np.array([[1, 1]], dtype=np.intp))
    time_box(poses)
    nearest_vertex(poses[:, -1], np.zeros((2, 2)))
    grid_weights(costs, costs == 0, np.array([[0, 1]]), np.array([0.25]), 50.0, 3.0)
    min_squared_distances(poses[:, -1:], np.zeros((1, 1, 2)), np.array([0], np.intp), out)
    compile_seconds = time.perf_counter() - start
    _warm = True
    return compile_seconds

"""Compiled (numba) GCFF solve of one component, with :mod:`.fformations` as the reference.

One connected component of standing people (a handful of them) is solved by ~10 small NumPy
calls per outer iteration in the reference; each costs microseconds of interpreter overhead
that dwarf the arithmetic. This kernel runs the same steps in the same order — votes, local
means, anisotropic costs with the attended gaze and the occlusion term, the add/drop/swap
facility-location search, canonical relabelling, least-squares centres — in one compiled call;
:func:`merge_wide` likewise runs the wide-circle merge (step 4 of :mod:`.fformations`).
Sums may be taken in a different order than NumPy's pairwise sums and the 2×2 centre solve is
written out, so centres can differ in the last bits; labels then differ only where joining
a group and standing alone cost the same to ~1e-9. The parity tests in
``tests/social/test_gcff_kernel.py`` check equal labels on random scenes; on the exact,
symmetric layouts of the Synth data 1 frame of 100 differs (a person on the MDL boundary).

Selection: the shared switch of :mod:`socialnav.core.compiled` (compiled when numba is
importable and ``SOCIALNAV_KERNELS`` is not ``reference``); :func:`set_enabled` switches at
run time. :func:`warmup` compiles (or loads from the on-disk cache) before the first cycle.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from socialnav.core import compiled

_warm = False
_jit = compiled.jit


def enabled() -> bool:
    """Whether the compiled solve is used: the shared switch of :mod:`socialnav.core.compiled`."""
    return compiled.enabled()


def set_enabled(value: bool) -> bool:
    """Set the shared switch of :mod:`socialnav.core.compiled` (the compiled kernels below the
    planner, this one included; ``True`` needs numba) and compile this kernel; returns the
    previous setting. Raises ``RuntimeError`` asking for numba when it is unavailable."""
    if value and not compiled.AVAILABLE:
        raise RuntimeError("the compiled GCFF solve needs numba (pip install numba)")
    previous = compiled.enabled()
    compiled.set_flag(value)
    if value:
        warmup()
    return previous


@_jit
def _gaze(px, py, yaw, cx, cy, tol):  # type: ignore[no-untyped-def]
    """Unit gaze of a person at ``(px, py)`` heading ``yaw`` attending to ``(cx, cy)``."""
    if tol <= 0.0:
        return np.cos(yaw), np.sin(yaw)
    off = np.arctan2(cy - py, cx - px) - yaw
    off = np.arctan2(np.sin(off), np.cos(off))
    if off > tol:
        off = tol
    elif off < -tol:
        off = -tol
    th = yaw + off
    return np.cos(th), np.sin(th)


@_jit
def _costs(pos, yaw, centers, p, out):  # type: ignore[no-untyped-def]
    """``out (K, G)``: :func:`socialnav.social.perception.fformations.assignment_costs`."""
    stride, sigma, sigma_along, mdl, occ_cost, occ_radius, tol = (
        p[0],
        p[1],
        p[2],
        p[3],
        p[4],
        p[5],
        p[6],
    )
    k = pos.shape[0]
    g = centers.shape[0]
    for i in range(k):
        for j in range(g):
            ux, uy = _gaze(pos[i, 0], pos[i, 1], yaw[i], centers[j, 0], centers[j, 1], tol)
            rx = centers[j, 0] - pos[i, 0] - stride * ux
            ry = centers[j, 1] - pos[i, 1] - stride * uy
            along = rx * ux + ry * uy
            across2 = max(rx * rx + ry * ry - along * along, 0.0)
            d2 = across2 / sigma**2 + along * along / sigma_along**2
            if k >= 3 and d2 <= mdl:
                ax, ay = pos[i, 0], pos[i, 1]
                bx, by = centers[j, 0] - ax, centers[j, 1] - ay
                length2 = max(bx * bx + by * by, 1e-12)
                for m in range(k):
                    if m == i:
                        continue
                    t = ((pos[m, 0] - ax) * bx + (pos[m, 1] - ay) * by) / length2
                    tc = min(max(t, 0.0), 1.0)
                    dx = pos[m, 0] - (ax + tc * bx)
                    dy = pos[m, 1] - (ay + tc * by)
                    if np.sqrt(dx * dx + dy * dy) < occ_radius and t > 0.05:
                        d2 += occ_cost
                        break
            out[i, j] = d2


@_jit
def _facility_location(costs, opening, max_moves):  # type: ignore[no-untyped-def]
    """Labels ``(K,)``: :func:`socialnav.social.perception.fformations.facility_location`."""
    k, g = costs.shape
    open_ = np.zeros(g, dtype=np.bool_)
    first = np.argmin(costs.sum(axis=0))
    open_[first] = True
    cur = costs[:, first].copy()
    while True:  # add
        best_j = -1
        best_gain = -np.inf
        for j in range(g):
            if open_[j]:
                continue
            gain = -opening
            for i in range(k):
                gain += max(cur[i] - costs[i, j], 0.0)
            if gain > best_gain:
                best_gain, best_j = gain, j
        if best_j < 0 or best_gain <= 1e-12:
            break
        open_[best_j] = True
        for i in range(k):
            cur[i] = min(cur[i], costs[i, best_j])
    total = cur.sum() + opening * open_.sum()
    base = np.empty(k)
    for _ in range(max_moves):  # drop / swap
        best_total = total
        drop, add = -1, -1
        for o in range(g):
            if not open_[o]:
                continue
            n_rest = 0
            for i in range(k):
                base[i] = np.inf
            for j in range(g):
                if open_[j] and j != o:
                    n_rest += 1
                    for i in range(k):
                        base[i] = min(base[i], costs[i, j])
            if n_rest > 0:
                t_drop = base.sum() + opening * n_rest
                if t_drop < best_total - 1e-9:
                    best_total, drop, add = t_drop, o, -1
            sw_best, sw_j = np.inf, -1
            for j in range(g):
                if open_[j]:
                    continue
                s = 0.0
                for i in range(k):
                    s += min(base[i], costs[i, j]) if n_rest > 0 else costs[i, j]
                s += opening * (n_rest + 1)
                if s < sw_best:
                    sw_best, sw_j = s, j
            if sw_j >= 0 and sw_best < best_total - 1e-9:
                best_total, drop, add = sw_best, o, sw_j
        if drop < 0:
            break
        open_[drop] = False
        if add >= 0:
            open_[add] = True
        total = best_total
    labels = np.empty(k, dtype=np.int64)
    for i in range(k):
        best, lab = np.inf, -1
        for j in range(g):
            if open_[j] and costs[i, j] < best:
                best, lab = costs[i, j], j
        labels[i] = lab
    return labels


@_jit
def _centre(pos, yaw, members, p):  # type: ignore[no-untyped-def]
    """:func:`socialnav.social.perception.fformations._centre` of ``pos[members]``."""
    stride, sigma, sigma_along, tol = p[0], p[1], p[2], p[6]
    n = members.size
    cx = 0.0
    cy = 0.0
    for m in members:
        cx += pos[m, 0] + stride * np.cos(yaw[m])
        cy += pos[m, 1] + stride * np.sin(yaw[m])
    cx /= n
    cy /= n
    for _ in range(1 if tol <= 0.0 else 4):
        a00 = a01 = a11 = b0 = b1 = 0.0
        for m in members:
            ux, uy = _gaze(pos[m, 0], pos[m, 1], yaw[m], cx, cy, tol)
            vx = pos[m, 0] + stride * ux
            vy = pos[m, 1] + stride * uy
            w_across = 1.0 / sigma**2
            w_along = 1.0 / sigma_along**2
            m00 = (1.0 - ux * ux) * w_across + ux * ux * w_along
            m01 = -ux * uy * w_across + ux * uy * w_along
            m11 = (1.0 - uy * uy) * w_across + uy * uy * w_along
            a00 += m00
            a01 += m01
            a11 += m11
            b0 += m00 * vx + m01 * vy
            b1 += m01 * vx + m11 * vy
        det = a00 * a11 - a01 * a01
        cx = (a11 * b0 - a01 * b1) / det
        cy = (a00 * b1 - a01 * b0) / det
    return cx, cy


@_jit
def _solve(pos, yaw, p, iterations, max_moves):  # type: ignore[no-untyped-def]
    """Labels ``(K,)`` of one component: the loop of ``fformations._gcff``."""
    k = pos.shape[0]
    stride, sigma, sigma_along, mdl = p[0], p[1], p[2], p[3]
    vote = np.empty((k, 2))
    for i in range(k):
        vote[i, 0] = pos[i, 0] + stride * np.cos(yaw[i])
        vote[i, 1] = pos[i, 1] + stride * np.sin(yaw[i])
    reach = max(sigma, sigma_along) * np.sqrt(mdl)
    centers = np.empty((2 * k, 2))
    for i in range(k):
        centers[i] = vote[i]
        sx = sy = 0.0
        n = 0
        for j in range(k):
            dx = vote[i, 0] - vote[j, 0]
            dy = vote[i, 1] - vote[j, 1]
            if np.sqrt(dx * dx + dy * dy) <= reach:
                sx += vote[j, 0]
                sy += vote[j, 1]
                n += 1
        centers[k + i, 0] = sx / n
        centers[k + i, 1] = sy / n
    labels = np.arange(k)
    for _ in range(max(1, iterations)):
        costs = np.empty((k, centers.shape[0]))
        _costs(pos, yaw, centers, p, costs)
        raw = _facility_location(costs, mdl, max_moves)
        # canonical labels numbered by first member, centres in that order, then the votes
        new = np.full(k, -1, dtype=np.int64)
        n_used = 0
        for i in range(k):
            if new[i] < 0:
                for j in range(i, k):
                    if raw[j] == raw[i]:
                        new[j] = n_used
                n_used += 1
        nxt = np.empty((n_used + k, 2))
        for u in range(n_used):
            cx, cy = _centre(pos, yaw, np.flatnonzero(new == u), p)
            nxt[u, 0] = cx
            nxt[u, 1] = cy
        nxt[n_used:] = vote
        centers = nxt
        same = True
        for i in range(k):
            if new[i] != labels[i]:
                same = False
                break
        if same:
            break
        labels = new
    return labels


@_jit
def _fitted_stride(pos, yaw, members, p):  # type: ignore[no-untyped-def]
    """:func:`socialnav.social.perception.fformations.fitted_stride` of ``pos[members]``."""
    stride, sigma, sigma_along, tol, max_stride = p[0], p[1], p[2], p[6], p[7]
    cx, cy = _centre(pos, yaw, members, p)
    d = stride
    w_across = 1.0 / sigma**2
    w_along = 1.0 / sigma_along**2
    for _ in range(1 if tol <= 0.0 else 4):
        m = np.zeros((3, 3))
        b = np.zeros(3)
        for k in members:
            ux, uy = _gaze(pos[k, 0], pos[k, 1], yaw[k], cx, cy, tol)
            a00 = (1.0 - ux * ux) * w_across + ux * ux * w_along
            a01 = -ux * uy * w_across + ux * uy * w_along
            a11 = (1.0 - uy * uy) * w_across + uy * uy * w_along
            au0 = a00 * ux + a01 * uy
            au1 = a01 * ux + a11 * uy
            ap0 = a00 * pos[k, 0] + a01 * pos[k, 1]
            ap1 = a01 * pos[k, 0] + a11 * pos[k, 1]
            m[0, 0] += a00
            m[0, 1] += a01
            m[1, 0] += a01
            m[1, 1] += a11
            m[0, 2] -= au0
            m[1, 2] -= au1
            m[2, 2] += au0 * ux + au1 * uy
            b[0] += ap0
            b[1] += ap1
            b[2] -= ap0 * ux + ap1 * uy
        m[2, 0] = m[0, 2]
        m[2, 1] = m[1, 2]
        if abs(np.linalg.det(m)) < 1e-12:
            break
        x = np.linalg.solve(m, b)
        d = min(max(x[2], stride), max(max_stride, stride))
        if d == x[2]:
            cx, cy = x[0], x[1]
        else:
            q = p.copy()
            q[0] = d
            cx, cy = _centre(pos, yaw, members, q)
    return cx, cy, d


@_jit
def _label_energy(pos, yaw, members, p):  # type: ignore[no-untyped-def]
    """(energy, centre x, centre y, stride) of one label with its fitted stride."""
    if members.size < 2:
        return p[3], np.nan, np.nan, p[0]
    cx, cy, d = _fitted_stride(pos, yaw, members, p)
    q = p.copy()
    q[0] = d
    center = np.empty((1, 2))
    center[0, 0] = cx
    center[0, 1] = cy
    costs = np.empty((pos.shape[0], 1))
    _costs(pos, yaw, center, q, costs)
    total = 0.0
    for k in members:
        total += costs[k, 0]
    return total + p[3], cx, cy, d


@_jit
def _merge_wide(pos, yaw, labels, p):  # type: ignore[no-untyped-def]
    """:func:`socialnav.social.perception.fformations.merge_wide`: labels and the fitted
    stride of every label (NaN where not merged)."""
    stride, tol, facing_max = p[0], p[6], p[8]
    labels = labels.copy()
    k = labels.size
    strides = np.full(k + 1, np.nan)
    if p[7] <= stride:
        return labels, strides
    while True:
        used = np.unique(labels)
        n = used.size
        if n < 2:
            return labels, strides
        alone = np.empty(n)
        for i in range(n):
            alone[i] = _label_energy(pos, yaw, np.flatnonzero(labels == used[i]), p)[0]
        best_saving, best_a, best_b, best_d = 0.0, -1, -1, 0.0
        for i in range(n):
            for j in range(i + 1, n):
                union = np.flatnonzero((labels == used[i]) | (labels == used[j]))
                if union.size < 3:
                    continue
                energy, cx, cy, d = _label_energy(pos, yaw, union, p)
                saving = alone[i] + alone[j] - energy
                if d <= stride * (1 + 1e-9) or saving <= 1e-9:
                    continue
                if best_a >= 0 and saving <= best_saving:
                    continue
                ok = True
                angles = np.empty(union.size)
                for t in range(union.size):
                    m = union[t]
                    a = np.arctan2(cy - pos[m, 1], cx - pos[m, 0])
                    off = a - yaw[m]
                    if abs(np.arctan2(np.sin(off), np.cos(off))) > facing_max:
                        ok = False
                        break
                    angles[t] = np.arctan2(pos[m, 1] - cy, pos[m, 0] - cx)
                if not ok:
                    continue
                angles.sort()
                gap = angles[0] + 2 * np.pi - angles[-1]
                for t in range(1, union.size):
                    gap = max(gap, angles[t] - angles[t - 1])
                if gap <= np.pi + tol:
                    best_saving, best_a, best_b, best_d = saving, used[i], used[j], d
        if best_a < 0:
            return labels, strides
        for t in range(k):
            if labels[t] == best_b:
                labels[t] = best_a
        strides[best_b] = np.nan
        strides[best_a] = best_d


def merge_wide(
    positions: NDArray[np.float64],
    yaws: NDArray[np.float64],
    labels: NDArray[np.int64],
    params: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Labels ``(K,)`` (values in ``0..K-1``) after the wide-circle merge and the fitted stride
    (m) of every label value ``(K + 1,)``, NaN where a label was not merged; ``params`` as in
    :func:`solve_component` followed by ``max_stride`` and ``merge_facing``."""
    return _merge_wide(
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(yaws, dtype=np.float64),
        np.ascontiguousarray(labels, dtype=np.int64),
        np.ascontiguousarray(params, dtype=np.float64),
    )


def solve_component(
    positions: NDArray[np.float64],
    yaws: NDArray[np.float64],
    params: NDArray[np.float64],
    iterations: int,
    max_moves: int = 50,
) -> NDArray[np.int64]:
    """Labels ``(K,)`` of one component (positions ``(K, 2)`` m, yaws ``(K,)`` rad);
    ``params``: stride, σ, sigma_along, mdl, occlusion cost, occlusion radius, heading
    tolerance (the fields of ``FFormationParams``; further entries are ignored)."""
    return _solve(
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(yaws, dtype=np.float64),
        np.ascontiguousarray(params, dtype=np.float64),
        int(iterations),
        int(max_moves),
    )


@_jit
def _geometry(pos, yaw, p):  # type: ignore[no-untyped-def]
    """Centre of all rows and each row's cost of joining it (occlusion among the rows)."""
    cx, cy = _centre(pos, yaw, np.arange(pos.shape[0]), p)
    center = np.empty((1, 2))
    center[0, 0] = cx
    center[0, 1] = cy
    costs = np.empty((pos.shape[0], 1))
    _costs(pos, yaw, center, p, costs)
    return center[0], costs[:, 0]


def centre_and_costs(
    positions: NDArray[np.float64], yaws: NDArray[np.float64], params: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A group's o-space centre ``(2,)`` (m) and its members' costs ``(K,)`` of joining it:
    ``fformations._centre`` and ``assignment_costs`` of the members alone."""
    return _geometry(
        np.ascontiguousarray(positions, dtype=np.float64),
        np.ascontiguousarray(yaws, dtype=np.float64),
        np.ascontiguousarray(params, dtype=np.float64),
    )


def warmup() -> None:
    """Compile (or load from cache) the solve for the argument types the detector passes."""
    global _warm
    if _warm or not compiled.enabled():
        return
    a = 2 * np.pi * np.arange(3) / 3
    pos = 0.7 * np.column_stack([np.cos(a), np.sin(a)])
    params = np.array([0.4, 0.1, 0.3, 25.0, 25.0, 0.25, 0.26, 2.0, 0.35])
    labels = solve_component(pos, a + np.pi, params, 10)
    merge_wide(pos, a + np.pi, labels, params)
    centre_and_costs(pos, a + np.pi, params)
    _warm = True

"""Standing conversational groups (F-formations, pairs included) by o-space voting and a
minimum-description-length assignment — GCFF.

Method: F. Setti, C. Russell, C. Bassetti, M. Cristani, "F-formation detection: individuating
free-standing conversational groups in images", PLoS One 10(5), 2015 (GCFF, "graph-cuts for
F-formations"); the o-space is Kendon's (Conducting Interaction, 1990).

1. Every standing person ``i`` votes for an o-space centre ``c_i = p_i + D·(cos θ_i, sin θ_i)``,
   ``D`` the *stride* (distance from a person to the centre of the conversation they face).
2. Candidate centres ``o_g``: every vote and, for each vote, the mean of the votes within
   ``max(σ, sigma_along)·√mdl`` (one mean-shift step). Assigning person ``i`` to ``g`` costs
   ``|c_i − o_g|² / σ²`` in GCFF; here an anisotropic version, σ across the gaze and
   ``sigma_along`` along it (GCFF is ``sigma_along = σ``), since members of larger circles stand
   farther from the centre than the stride. The gaze is the heading turned towards ``o_g`` by
   at most ``heading_tolerance``: a person attends equally to everything within their
   transactional segment (Kendon 1990), and a body orientation is a coarse cue (people turn
   their heads; trackers and head-pose classifiers err by tens of degrees). GCFF is
   ``heading_tolerance = 0``. Add ``occlusion_cost`` when another person stands
   between ``p_i`` and ``o_g`` or in the o-space itself (GCFF's visibility term: one cannot
   converse through someone). Each group in use costs ``mdl`` (the minimum-description-length
   label cost), so a person joins a group only when that is cheaper than standing alone.
3. The labelling minimises the sum. GCFF's energy has no pairwise terms, so it is an
   uncapacitated facility-location problem; GCFF solves it by α-expansion with label costs
   (Delong et al. 2012); here the classic add/drop/swap local search for facility location
   (:func:`facility_location`), fast enough for every control cycle. Centres are re-estimated
   from their members (the weighted least-squares point of the anisotropic costs) and steps
   2–3 repeat until the labelling is stable (GCFF's outer loop), at most ``iterations`` times.
4. **Wide circles** (:func:`merge_wide`). A fixed stride makes every member's vote land ``D``
   ahead of them, so a circle much wider than ``D`` (five or more people on a 1.2–1.5 m circle)
   is cheaper as two groups, each with its centre nearer its members. Kendon's o-space grows
   with the group (its members keep their spacing), so this step re-prices the labelling with
   each group's *own* stride: the centre and stride ``D ∈ [stride, max_stride]`` minimising
   the members' costs (a 3-unknown weighted least squares). Two labels (groups or people
   alone) are merged, best saving first, while the union with its fitted stride costs less
   (members' costs, occlusion by the rest of the component, one ``mdl``) than the two apart,
   each priced with its own fitted stride too. A union is considered only when it has three or
   more members, its fitted stride exceeds ``stride`` (otherwise GCFF's own solve already
   priced it), its members surround the centre (no angular gap between neighbours, seen from
   it, wider than π + ``heading_tolerance``: the o-space is enclosed by the p-space) and every
   member faces it within ``merge_facing``. ``max_stride <= stride`` turns the step off
   (GCFF as published). Two people alone are never merged into a pair here.
5. **Wide pairs** (:func:`facing_pairs`, in :class:`FFormationDetector`). Two people GCFF
   leaves alone (more than ~2.3 m apart) who face each other within ``pair_facing`` (20°, as
   ``merge_facing``), at most ``pair_max_distance`` (3 m: the widest pair of the project's
   group scenarios, radius 1.5 m; inside Hall's 1.2–3.6 m social-consultative distance) apart,
   with nobody between them, form a pair (Kendon's vis-à-vis arrangement). A triple whose
   members are all left alone stays undetected. ``pair_max_distance = 0`` turns it off.
6. **Facing the o-space** (:func:`~socialnav.social.perception.base.faces_ospace`): a group
   is kept only when more than half of its members have its centre in front of them. The
   anisotropic cost lets a centre lie a metre along the gaze *behind* a person as cheaply as
   ahead of them, so two people standing back to back 0.3–0.7 m apart made a "group"
   (confidence 0.6–0.7). No parameter: on Synth F1 at T = 2/3 rose 0.952 → 0.970 and at
   T = 1 0.894 → 0.912 (only false groups removed); CoffeeBreak's single frames are unchanged.

Parameters (metres, radians; defaults fitted on the Cristani et al. *Synth* data only, see
``benchmarks/bench_context.py --fit``): ``stride`` D, ``sigma`` σ, ``sigma_along``, ``mdl``,
``occlusion_cost``, ``occlusion_radius`` (a body's radius), ``heading_tolerance``. The fit is a
grid search maximising the mean of F1 at T = 2/3 and T = 1 on Synth, among
``sigma_along >= 3σ`` (so that circles of 0.6–1.2 m radius, the project's group scenarios, are
not split); ``heading_tolerance`` (15°) was fitted last, the others held at their earlier fit.
A person joins a centre whose vote lies within ``σ·√mdl`` (0.5 m) across or
``sigma_along·√mdl`` (1.5 m) along the gaze. The dataset's own settings give a 0.6 m stride
for the original method. ``max_stride`` (2 m) is the widest circle the project's group
scenarios use (radius 0.5–2 m, :mod:`socialnav.social.plausibility` admits up to 2.5 m);
``merge_facing`` (20°) is two standard deviations of the 10° heading noise of the simulator's
default perception model (:class:`socialnav.sim.perception.PerceptionNoise`), set a priori:
Synth scores the same for any value from 15° to 30° (it has no circle wider than the stride),
and on generated circles 25° joins one more of 105 (``bench_context.py``). ``reuse_distance``
and ``reuse_angle``: see :class:`FFormationDetector` (incremental solving across control
cycles).

Coarse headings. The defaults assume headings accurate to about 10° (the simulator's
perception model). A source whose headings are quantised more coarsely needs its own set,
fitted the same way on Synth with its headings quantised to that step: for four directions
(90°, CoffeeBreak's head-pose classes) that is ``stride`` 0.4, ``sigma`` 0.15,
``sigma_along`` 0.15, ``mdl`` 25, ``heading_tolerance`` 40° (``bench_context.py``, with
``sigma_along`` from σ and the tolerance up to half the step; the defaults' grid keeps
``sigma_along >= 3σ`` and leaves CoffeeBreak where it was). Widening σ and ``merge_facing``
by the quantisation error instead, without refitting, does worse on both data sets. The fit
protocol of ``bench_context.py`` (``protocol_grid``: every combination of ``stride``
0.3–0.8 m, ``sigma`` 0.10–0.25 m, ``sigma_along`` 1–4 σ, ``mdl`` 9–36 and a tolerance of 0,
a quarter or half the step; fixed before its held-out result was seen) gives ``stride`` 0.4,
``sigma`` 0.15, ``sigma_along`` 0.15, ``mdl`` 25, ``heading_tolerance`` 45° for a 90° step
(0.5, 0.1, 0.2, 25, 22.5° before step 6 below, which changes which set scores best). With it,
the estimator over the CoffeeBreak sequence (``EstimatorParams(velocity_source="positions",
detector_params={"fformation": {...}})``: its tracks have no velocities) scores F1 0.82–0.84
at T = 2/3 for any frame spacing from 0.1 to 2 s; single frames 0.75.

Output: groups of at least two members with o-space centre (the fitted centre), radius (the mean
member distance to it) and a score ``1 − mean cost / mdl`` in [0, 1]: the margin by which
joining beats standing alone (1: every vote on the centre; 0: no better than alone).

An alternative detector of the same candidates, dominant sets with headings as soft evidence
(Hung & Kröse 2011), is :mod:`socialnav.social.perception.dominant_sets` (``dominant_sets``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy.sparse import csr_array
from scipy.sparse.csgraph import connected_components

from socialnav.core.geometry import FloatArray
from socialnav.social.perception import gcff_kernel
from socialnav.social.perception.base import (
    DETECTORS,
    STANDING_SPEED,
    Candidate,
    MapKnowledge,
    ParamDetector,
    TrackFrame,
    faces_ospace,
    unclaimed,
)


@dataclass(frozen=True)
class FFormationParams:
    """GCFF parameters (module docstring); lengths in metres."""

    stride: float = 0.4
    sigma: float = 0.1
    sigma_along: float = 0.3
    mdl: float = 25.0
    occlusion_cost: float = 25.0
    occlusion_radius: float = 0.25
    heading_tolerance: float = float(np.radians(15.0))
    iterations: int = 10
    max_stride: float = 2.0
    merge_facing: float = float(np.radians(20.0))
    standing_speed: float = STANDING_SPEED
    reuse_distance: float = 0.02
    reuse_angle: float = float(np.radians(3.0))
    pair_max_distance: float = 3.0
    pair_facing: float = float(np.radians(20.0))


def votes(positions: FloatArray, yaws: FloatArray, stride: float) -> FloatArray:
    """O-space votes ``(K, 2)``: each person's point ``stride`` m ahead of them."""
    return positions + stride * np.column_stack([np.cos(yaws), np.sin(yaws)])


def attended_gaze(
    positions: FloatArray, yaws: FloatArray, centers: FloatArray, tolerance: float
) -> FloatArray:
    """Unit gaze ``(K, G, 2)`` of person ``k`` towards centre ``g``: the heading turned towards
    the centre by at most ``tolerance`` (rad), the half-width of the transactional segment
    (Kendon 1990) within which a centre costs nothing in angle."""
    if tolerance <= 0.0:
        g = np.column_stack([np.cos(yaws), np.sin(yaws)])
        return np.broadcast_to(g[:, None, :], (yaws.size, centers.shape[0], 2))
    rel = centers[None, :, :] - positions[:, None, :]
    off = np.arctan2(rel[..., 1], rel[..., 0]) - yaws[:, None]
    off = np.arctan2(np.sin(off), np.cos(off))  # wrapped to (-π, π]
    th = yaws[:, None] + np.clip(off, -tolerance, tolerance)
    return np.stack([np.cos(th), np.sin(th)], axis=-1)


def assignment_costs(
    positions: FloatArray, yaws: FloatArray, centers: FloatArray, p: FFormationParams
) -> FloatArray:
    """Cost ``(K, G)`` of person ``k`` joining centre ``g``: the squared distance from the
    centre to the person's vote along their attended gaze (:func:`attended_gaze`), scaled by
    ``sigma`` across the gaze and ``sigma_along`` along it, plus the occlusion cost when
    someone else stands between the person and the centre."""
    u = attended_gaze(positions, yaws, centers, p.heading_tolerance)  # (K, G, 2)
    rel = centers[None, :, :] - positions[:, None, :] - p.stride * u  # vote → centre
    along = (rel * u).sum(-1)
    across2 = np.maximum((rel**2).sum(-1) - along**2, 0.0)
    d2 = across2 / p.sigma**2 + along**2 / p.sigma_along**2
    k = positions.shape[0]
    if k < 3:
        return d2
    # occluder j of (i, g): within the radius of the segment p_i → o_g, past its start. Only
    # pairs cheaper than standing alone can change the labelling, so only those are tested.
    ii, gg = np.nonzero(d2 <= p.mdl)
    a = positions[ii]  # (M, 2)
    ab = centers[gg] - a  # (M, 2)
    length2 = np.maximum((ab**2).sum(-1), 1e-12)
    rel = positions[None, :, :] - a[:, None, :]  # (M, J, 2)
    t = (rel * ab[:, None, :]).sum(-1) / length2[:, None]  # (M, J)
    closest = a[:, None, :] + np.clip(t, 0, 1)[..., None] * ab[:, None, :]
    dist = np.linalg.norm(positions[None, :, :] - closest, axis=-1)
    # someone on the segment, or standing in the o-space itself (Kendon: it is kept empty)
    occluded = (dist < p.occlusion_radius) & (t > 0.05)
    occluded[np.arange(ii.size), ii] = False
    out = d2.copy()
    out[ii, gg] += p.occlusion_cost * occluded.any(axis=1)
    return out


def facility_location(costs: FloatArray, opening: float, max_moves: int = 50) -> np.ndarray:
    """Labelling ``(K,)`` (a column of ``costs (K, G)`` per row) that minimises
    ``Σ costs[k, label_k] + opening · #labels used`` (uncapacitated facility location).

    The classic local search: the greedy *add* heuristic of Kuehn & Hamburger ("A heuristic
    program for locating warehouses", Management Science 1963), then *drop* and *swap* moves
    (Teitz & Bart, "Heuristic methods for estimating the generalized vertex median of a
    weighted graph", Operations Research 1968) while one lowers the total, at most
    ``max_moves`` of them. Not guaranteed optimal, but never worse than everyone alone or
    everyone in one group (both are reachable by the moves).
    """
    k, g = costs.shape
    if k == 0 or g == 0:
        return np.zeros(k, dtype=int)
    open_ = np.zeros(g, dtype=bool)
    first = int(np.argmin(costs.sum(axis=0)))
    open_[first] = True
    cur = costs[:, first].copy()
    while True:  # add
        gain = np.maximum(cur[:, None] - costs, 0.0).sum(axis=0) - opening
        gain[open_] = -np.inf
        j = int(np.argmax(gain))
        if gain[j] <= 1e-12:
            break
        open_[j] = True
        cur = np.minimum(cur, costs[:, j])
    total = cur.sum() + opening * open_.sum()
    for _ in range(max_moves):  # drop / swap
        best_total = total
        best_move: tuple[int, int | None] | None = None
        opened = np.flatnonzero(open_)
        for i in opened:
            rest = open_.copy()
            rest[i] = False
            base = np.where(rest[None, :], costs, np.inf).min(axis=1) if rest.any() else None
            n_rest = int(rest.sum())
            if base is not None:
                t_drop = base.sum() + opening * n_rest
                if t_drop < best_total - 1e-9:
                    best_total, best_move = t_drop, (int(i), None)
                swapped = np.minimum(base[:, None], costs).sum(axis=0)
            else:
                swapped = costs.sum(axis=0)
            swapped = swapped + opening * (n_rest + 1)
            swapped[open_] = np.inf
            j = int(np.argmin(swapped))
            if swapped[j] < best_total - 1e-9:
                best_total, best_move = float(swapped[j]), (int(i), j)
        if best_move is None:
            break
        drop, add = best_move
        open_[drop] = False
        if add is not None:
            open_[add] = True
        total = best_total
    return np.argmin(np.where(open_[None, :], costs, np.inf), axis=1)


def _centre(positions: FloatArray, yaws: FloatArray, p: FFormationParams) -> FloatArray:
    """The point minimising the members' anisotropic vote costs: a weighted least-squares
    solve (the mean of the votes when ``sigma_along == sigma``), repeated with the gazes
    attended towards the last solution when ``heading_tolerance > 0``."""
    center = votes(positions, yaws, p.stride).mean(axis=0)
    for _ in range(1 if p.heading_tolerance <= 0.0 else 4):
        u = attended_gaze(positions, yaws, center[None], p.heading_tolerance)[:, 0, :]
        vote = positions + p.stride * u
        outer = u[:, :, None] * u[:, None, :]
        a = (np.eye(2) - outer) / p.sigma**2 + outer / p.sigma_along**2  # (K, 2, 2)
        center = np.linalg.solve(a.sum(0), np.einsum("kij,kj->i", a, vote))
    return center


def _local_means(vote: FloatArray, reach: float) -> FloatArray:
    """One mean-shift step: for every vote, the mean of the votes within ``reach`` (m) — extra
    centre hypotheses near the middle of a ring of votes, which the votes alone lack."""
    near = np.linalg.norm(vote[:, None] - vote[None], axis=-1) <= reach
    return (near[:, :, None] * vote[None]).sum(1) / near.sum(1, keepdims=True)


def components(positions: FloatArray, params: FFormationParams) -> np.ndarray:
    """Component label ``(K,)`` of each person: people farther apart than
    ``2 (stride + max(σ, sigma_along)·√mdl)`` (chained) cannot share a centre (the label cost
    alone exceeds standing alone), nor occlude each other's centre, so each connected
    component of the closer pairs is solved alone."""
    k = positions.shape[0]
    if k < 2:
        return np.zeros(k, dtype=int)
    reach = max(params.sigma, params.sigma_along) * np.sqrt(params.mdl)
    link = np.linalg.norm(positions[:, None] - positions[None], axis=-1) <= 2 * (
        params.stride + reach
    )
    return connected_components(csr_array(link.astype(np.int8)), directed=False)[1]


def gcff(positions: FloatArray, yaws: FloatArray, params: FFormationParams) -> list[np.ndarray]:
    """Groups (index arrays into ``positions (K, 2)``, two or more members) by GCFF, each
    connected component (:func:`components`) solved separately."""
    if positions.shape[0] < 2:
        return []
    comp = components(positions, params)
    out = []
    for c in np.unique(comp):
        idx = np.flatnonzero(comp == c)
        if idx.size >= 2:
            out += [idx[g] for g, _ in _gcff(positions[idx], yaws[idx], params)]
    return sorted(out, key=lambda g: int(g[0]))


def _gcff(
    positions: FloatArray, yaws: FloatArray, params: FFormationParams
) -> list[tuple[np.ndarray, float]]:
    """Groups of one component with their strides (m): the compiled solve
    (:mod:`.gcff_kernel`) or the reference, then :func:`merge_wide`."""
    if gcff_kernel.enabled():
        kp = kernel_params(params)
        labels = gcff_kernel.solve_component(positions, yaws, kp, params.iterations)
        labels, fitted = gcff_kernel.merge_wide(positions, yaws, labels, kp)
        strides = {int(u): float(d) for u, d in enumerate(fitted) if np.isfinite(d)}
    else:
        labels = _labels_reference(positions, yaws, params)
        labels, strides = merge_wide(positions, yaws, labels, params)
    out = []
    for u in np.unique(labels):
        g = np.flatnonzero(labels == u)
        if g.size < 2:
            continue
        stride = strides.get(int(u), params.stride)
        p = params if stride == params.stride else replace(params, stride=stride)
        if faces_ospace(positions[g], yaws[g], _group_centre(positions[g], yaws[g], p)):
            out.append((g, stride))
    return out


def _group_centre(positions: FloatArray, yaws: FloatArray, p: FFormationParams) -> FloatArray:
    """The o-space centre ``(2,)`` of one group: the compiled :func:`_centre` or the reference."""
    if gcff_kernel.enabled():
        return gcff_kernel.centre_and_costs(positions, yaws, kernel_params(p))[0]
    return _centre(positions, yaws, p)


def fitted_stride(
    positions: FloatArray, yaws: FloatArray, params: FFormationParams
) -> tuple[FloatArray, float]:
    """O-space centre ``(2,)`` and stride ``D`` (m) of one group ``(K, 2)``, ``K >= 2``: the
    weighted least-squares point of :func:`_centre` with ``D`` a third unknown, clipped to
    ``[stride, max_stride]`` (the centre then solved again with ``D`` fixed); the gazes are
    attended towards the last solution, as in :func:`_centre`."""
    p = params
    center = _centre(positions, yaws, p)
    stride = p.stride
    eye = np.eye(2)
    for _ in range(1 if p.heading_tolerance <= 0.0 else 4):
        u = attended_gaze(positions, yaws, center[None], p.heading_tolerance)[:, 0, :]
        outer = u[:, :, None] * u[:, None, :]
        a = (eye - outer) / p.sigma**2 + outer / p.sigma_along**2  # (K, 2, 2)
        # residual c − p_k − D u_k, linear in (c, D): normal equations of the 3 unknowns
        au = np.einsum("kij,kj->ki", a, u)  # (K, 2)
        m = np.zeros((3, 3))
        m[:2, :2] = a.sum(0)
        m[:2, 2] = m[2, :2] = -au.sum(0)
        m[2, 2] = (au * u).sum()
        ap = np.einsum("kij,kj->ki", a, positions)
        b = np.concatenate([ap.sum(0), [-(ap * u).sum()]])
        if abs(np.linalg.det(m)) < 1e-12:  # parallel gazes: no common centre
            break
        x = np.linalg.solve(m, b)
        stride = float(np.clip(x[2], p.stride, max(p.max_stride, p.stride)))
        # a clipped stride: the centre solved again with that stride fixed
        fixed = replace(p, stride=stride)
        center = x[:2] if stride == x[2] else _centre(positions, yaws, fixed)
    return center, stride


def _encloses(positions: FloatArray, center: FloatArray, slack: float) -> bool:
    """Whether the people ``(K, 2)`` surround ``center``: no angular gap between neighbours,
    seen from it, wider than π + ``slack`` (rad)."""
    rel = positions - center
    a = np.sort(np.arctan2(rel[:, 1], rel[:, 0]))
    return bool(np.diff(np.append(a, a[0] + 2 * np.pi)).max() <= np.pi + slack)


def _label_energy(
    positions: FloatArray, yaws: FloatArray, members: np.ndarray, params: FFormationParams
) -> tuple[float, FloatArray | None, float]:
    """(energy, centre, stride) of one label with its fitted stride: ``mdl`` alone; else the
    members' costs of joining the fitted centre (occlusion by everyone in ``positions``) plus
    ``mdl``."""
    if members.size < 2:
        return params.mdl, None, params.stride
    center, stride = fitted_stride(positions[members], yaws[members], params)
    costs = assignment_costs(positions, yaws, center[None], replace(params, stride=stride))
    return float(costs[members, 0].sum()) + params.mdl, center, stride


def merge_wide(
    positions: FloatArray, yaws: FloatArray, labels: np.ndarray, params: FFormationParams
) -> tuple[np.ndarray, dict[int, float]]:
    """Step 4 of the module docstring on one component: labels ``(K,)`` with wide circles
    merged (each merged label keeps its smallest original number), and the fitted stride (m)
    of every merged label. Unchanged when ``max_stride <= stride``."""
    p = params
    labels = np.asarray(labels).copy()
    strides: dict[int, float] = {}
    if p.max_stride <= p.stride:
        return labels, strides
    while True:
        used = [int(u) for u in np.unique(labels)]
        if len(used) < 2:
            return labels, strides
        members = {u: np.flatnonzero(labels == u) for u in used}
        alone = {u: _label_energy(positions, yaws, members[u], p)[0] for u in used}
        best: tuple[float, int, int, float] | None = None
        for i, a in enumerate(used):
            for b in used[i + 1 :]:
                union = np.union1d(members[a], members[b])
                if union.size < 3:
                    continue
                energy, center, stride = _label_energy(positions, yaws, union, p)
                saving = alone[a] + alone[b] - energy
                if center is None or stride <= p.stride * (1 + 1e-9) or saving <= 1e-9:
                    continue
                if best is not None and saving <= best[0]:
                    continue
                rel = center - positions[union]
                off = np.arctan2(rel[:, 1], rel[:, 0]) - yaws[union]
                facing = np.abs(np.arctan2(np.sin(off), np.cos(off))).max() <= p.merge_facing
                if facing and _encloses(positions[union], center, p.heading_tolerance):
                    best = (saving, a, b, stride)
        if best is None:
            return labels, strides
        _, a, b, stride = best
        labels[labels == b] = a
        strides.pop(b, None)
        strides[a] = stride


def kernel_params(p: FFormationParams) -> FloatArray:
    """The parameter vector of :func:`.gcff_kernel.solve_component`."""
    return np.array(
        [
            p.stride,
            p.sigma,
            p.sigma_along,
            p.mdl,
            p.occlusion_cost,
            p.occlusion_radius,
            p.heading_tolerance,
            p.max_stride,
            p.merge_facing,
        ]
    )


def _labels_reference(
    positions: FloatArray, yaws: FloatArray, params: FFormationParams
) -> np.ndarray:
    """Labels ``(K,)`` of one component by the NumPy steps of the module docstring."""
    k = positions.shape[0]
    vote = votes(positions, yaws, params.stride)
    reach = max(params.sigma, params.sigma_along) * np.sqrt(params.mdl)
    centers = np.concatenate([vote, _local_means(vote, reach)])
    labels = np.arange(k)
    for _ in range(max(1, params.iterations)):
        costs = assignment_costs(positions, yaws, centers, params)
        new = facility_location(costs, params.mdl)
        used, first = np.unique(new, return_index=True)
        centers = np.array([_centre(positions[new == u], yaws[new == u], params) for u in used])
        # canonical labels (numbered by first member) so a stable partition compares equal
        rank = np.empty(used.size, dtype=int)
        rank[np.argsort(first)] = np.arange(used.size)
        new = rank[np.searchsorted(used, new)]
        centers = centers[np.argsort(rank)]
        # GCFF keeps every person's own vote as a hypothesis, so a singleton can always split off
        centers = np.concatenate([centers, vote])
        if np.array_equal(new, labels):
            break
        labels = new
    return labels


def facing_pairs(
    ids: np.ndarray,
    positions: FloatArray,
    yaws: FloatArray,
    everyone: FloatArray,
    params: FFormationParams,
) -> list[Candidate]:
    """Step 5 of the module docstring: wide face-to-face pairs among people GCFF left alone.

    ``ids (K,)``, ``positions (K, 2)``, ``yaws (K,)``: the standing people in no group;
    ``everyone (N, 2)``: all tracked positions (occluders). Two of them form a pair when they
    are at most ``pair_max_distance`` (m) apart, each faces the other within ``pair_facing``
    (rad) and nobody else stands within ``occlusion_radius`` of the segment between them;
    the best-facing pairs are taken first, each person in one pair at most. Centre: the
    midpoint; score ``1 − worst facing error / pair_facing``.
    """
    p = params
    k = positions.shape[0]
    found: list[tuple[float, int, int]] = []
    for a in range(k):
        for b in range(a + 1, k):
            d = positions[b] - positions[a]
            dist = float(np.hypot(*d))
            if not 1e-6 < dist <= p.pair_max_distance:
                continue
            bearing = np.arctan2(d[1], d[0])
            off = np.array([bearing - yaws[a], bearing + np.pi - yaws[b]])
            err = float(np.abs(np.arctan2(np.sin(off), np.cos(off))).max())
            if err > p.pair_facing:
                continue
            rel = everyone - positions[a]
            t = np.clip(rel @ d / dist**2, 0.0, 1.0)
            gap = np.hypot(*(rel - t[:, None] * d).T)
            ends = (np.hypot(*rel.T) <= 1e-6) | (np.hypot(*(everyone - positions[b]).T) <= 1e-6)
            if np.any((gap < p.occlusion_radius) & ~ends):
                continue
            found.append((err, a, b))
    out: list[Candidate] = []
    used: set[int] = set()
    for err, a, b in sorted(found):
        if a in used or b in used:
            continue
        used |= {a, b}
        center = 0.5 * (positions[a] + positions[b])
        radius = 0.5 * float(np.hypot(*(positions[b] - positions[a])))
        members = tuple(sorted((int(ids[a]), int(ids[b]))))
        out.append(
            Candidate(
                "fformation",
                members,
                float(1.0 - err / p.pair_facing),
                geometry={"ospace_center": center, "ospace_radius": radius},
            )
        )
    return out


@dataclass
class _Solved:
    """One component's last solve: the inputs it was solved on and its candidates."""

    positions: FloatArray
    yaws: FloatArray
    candidates: list[Candidate]


class FFormationDetector(ParamDetector[FFormationParams]):
    """Registered as ``fformation``: GCFF over the standing people not yet claimed.

    Incremental across cycles: a component (:func:`components`) with the same members as in
    an earlier cycle, every member within ``reuse_distance`` (m) and ``reuse_angle`` (rad) of
    the positions and headings it was last solved on, keeps that solve's candidates instead of
    being solved again. The comparison is with the inputs of the solve, not of the previous
    cycle, so slow drift cannot accumulate past the tolerances. Standing conversations change
    little between control cycles, so most of a crowd is reused; ``reuse_distance=0`` turns
    reuse off (every cycle solved from scratch).
    """

    params_type = FFormationParams
    positive = frozenset({"sigma", "sigma_along", "mdl", "iterations"})

    def __init__(self, params: FFormationParams | None = None, **overrides: Any) -> None:
        super().__init__(params, **overrides)
        gcff_kernel.warmup()  # compile before the first control cycle, not in it
        self.reset()

    def reset(self) -> None:
        """Forget the solves of earlier cycles."""
        self._solved: dict[tuple[int, ...], _Solved] = {}

    def __call__(
        self, frame: TrackFrame, knowledge: MapKnowledge, claimed: frozenset[int]
    ) -> list[Candidate]:
        """Candidates of one frame (see :data:`~socialnav.social.perception.base.Detector`)."""
        del knowledge
        p = self.params
        idx = unclaimed(frame, claimed, frame.standing(p.standing_speed))
        idx = idx[np.argsort(frame.ids[idx], kind="stable")]  # members in id order
        pos, yaw, ids = frame.positions[idx], frame.yaws[idx], frame.ids[idx]
        comp = components(pos, p)
        solved: dict[tuple[int, ...], _Solved] = {}
        out: list[Candidate] = []
        for c in np.unique(comp):
            sel = np.flatnonzero(comp == c)
            if sel.size < 2:
                continue
            key = tuple(int(i) for i in ids[sel])
            last = self._solved.get(key)
            if last is None or not self._reusable(last, pos[sel], yaw[sel]):
                cands = self._solve(ids[sel], pos[sel], yaw[sel])
                last = _Solved(pos[sel].copy(), yaw[sel].copy(), cands)
            solved[key] = last
            out.extend(last.candidates)
        self._solved = solved  # components gone this cycle are forgotten
        taken = {i for c in out for i in c.members}
        alone = np.array([k for k, i in enumerate(ids) if int(i) not in taken], dtype=int)
        out.extend(facing_pairs(ids[alone], pos[alone], yaw[alone], frame.positions, p))
        return out

    def _reusable(self, last: _Solved, pos: FloatArray, yaw: FloatArray) -> bool:
        p = self.params
        if p.reuse_distance <= 0.0:
            return False
        moved = np.max(np.hypot(*(pos - last.positions).T))
        turn = np.max(np.abs(np.angle(np.exp(1j * (yaw - last.yaws)))))
        return bool(moved <= p.reuse_distance and turn <= p.reuse_angle)

    def _solve(self, ids: np.ndarray, pos: FloatArray, yaw: FloatArray) -> list[Candidate]:
        out = []
        for g, stride in _gcff(pos, yaw, self.params):
            # a merged wide circle is scored with its own stride (step 4), others with GCFF's
            p = self.params if stride == self.params.stride else replace(self.params, stride=stride)
            if gcff_kernel.enabled():
                center, cost = gcff_kernel.centre_and_costs(pos[g], yaw[g], kernel_params(p))
            else:
                center = _centre(pos[g], yaw[g], p)
                cost = assignment_costs(pos[g], yaw[g], center[None], p)[:, 0]
            radius = float(np.linalg.norm(pos[g] - center, axis=1).mean())
            out.append(
                Candidate(
                    "fformation",
                    tuple(int(i) for i in ids[g]),
                    float(np.clip(1.0 - cost.mean() / self.params.mdl, 0.0, 1.0)),
                    geometry={"ospace_center": center, "ospace_radius": radius},
                )
            )
        return out


DETECTORS.add("fformation", FFormationDetector)

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
   farther from the centre than the stride. Add ``occlusion_cost`` when another person stands
   between ``p_i`` and ``o_g`` or in the o-space itself (GCFF's visibility term: one cannot
   converse through someone). Each group in use costs ``mdl`` (the minimum-description-length
   label cost), so a person joins a group only when that is cheaper than standing alone.
3. The labelling minimises the sum. GCFF's energy has no pairwise terms, so it is an
   uncapacitated facility-location problem; GCFF solves it by α-expansion with label costs
   (Delong et al. 2012); here the classic add/drop/swap local search for facility location
   (:func:`facility_location`), fast enough for every control cycle. Centres are re-estimated
   from their members (the weighted least-squares point of the anisotropic costs) and steps
   2–3 repeat until the labelling is stable (GCFF's outer loop), at most ``iterations`` times.

Parameters (metres; defaults fitted on the Cristani et al. *Synth* data only, see
``benchmarks/bench_context.py --fit``): ``stride`` D, ``sigma`` σ, ``sigma_along``, ``mdl``,
``occlusion_cost``, ``occlusion_radius`` (a body's radius). The fit is a grid search maximising
the mean of F1 at T = 2/3 and T = 1 on Synth, among ``sigma_along >= 3σ`` (so that circles of
0.6–1.2 m radius, the project's group scenarios, are not split). A person joins a centre whose
vote lies within ``σ·√mdl`` (0.5 m) across or ``sigma_along·√mdl`` (1.5 m) along the gaze. The
dataset's own settings give a 0.6 m stride for the original method.

Output: groups of at least two members with o-space centre (the fitted centre), radius (the mean
member distance to it) and a score ``1 − mean cost / mdl`` in [0, 1]: the margin by which
joining beats standing alone (1: every vote on the centre; 0: no better than alone).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_array
from scipy.sparse.csgraph import connected_components

from socialnav.core.geometry import FloatArray
from socialnav.social.perception.base import (
    DETECTORS,
    STANDING_SPEED,
    Candidate,
    MapKnowledge,
    ParamDetector,
    TrackFrame,
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
    iterations: int = 10
    standing_speed: float = STANDING_SPEED


def votes(positions: FloatArray, yaws: FloatArray, stride: float) -> FloatArray:
    """O-space votes ``(K, 2)``: each person's point ``stride`` m ahead of them."""
    return positions + stride * np.column_stack([np.cos(yaws), np.sin(yaws)])


def assignment_costs(
    positions: FloatArray, vote: FloatArray, centers: FloatArray, p: FFormationParams
) -> FloatArray:
    """Cost ``(K, G)`` of person ``k`` joining centre ``g``: the squared vote distance,
    scaled by ``sigma`` across the gaze and ``sigma_along`` along it, plus the occlusion cost
    when someone else stands between the person and the centre."""
    gaze = vote - positions
    u = gaze / np.maximum(np.linalg.norm(gaze, axis=1, keepdims=True), 1e-12)
    rel = centers[None, :, :] - vote[:, None, :]  # (K, G, 2)
    along = (rel * u[:, None, :]).sum(-1)
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


def _centre(vote: FloatArray, positions: FloatArray, p: FFormationParams) -> FloatArray:
    """The point minimising the members' anisotropic vote costs (a weighted least-squares
    solve; the mean of the votes when ``sigma_along == sigma``)."""
    gaze = vote - positions
    u = gaze / np.maximum(np.linalg.norm(gaze, axis=1, keepdims=True), 1e-12)
    outer = u[:, :, None] * u[:, None, :]
    a = (np.eye(2) - outer) / p.sigma**2 + outer / p.sigma_along**2  # (K, 2, 2)
    return np.linalg.solve(a.sum(0), np.einsum("kij,kj->i", a, vote))


def _local_means(vote: FloatArray, reach: float) -> FloatArray:
    """One mean-shift step: for every vote, the mean of the votes within ``reach`` (m) — extra
    centre hypotheses near the middle of a ring of votes, which the votes alone lack."""
    near = np.linalg.norm(vote[:, None] - vote[None], axis=-1) <= reach
    return (near[:, :, None] * vote[None]).sum(1) / near.sum(1, keepdims=True)


def gcff(positions: FloatArray, yaws: FloatArray, params: FFormationParams) -> list[np.ndarray]:
    """Groups (index arrays into ``positions (K, 2)``, two or more members) by GCFF.

    People farther apart than ``2 (stride + max(σ, sigma_along)·√mdl)``
    cannot share a centre (the label cost alone exceeds standing alone), nor occlude each
    other's centre: the connected components of the closer pairs are solved separately.
    """
    k = positions.shape[0]
    if k < 2:
        return []
    reach = max(params.sigma, params.sigma_along) * np.sqrt(params.mdl)
    link = np.linalg.norm(positions[:, None] - positions[None], axis=-1) <= 2 * (
        params.stride + reach
    )
    n, comp = connected_components(csr_array(link.astype(np.int8)), directed=False)
    if n > 1:
        out = []
        for c in range(n):
            idx = np.flatnonzero(comp == c)
            if idx.size >= 2:
                out += [idx[g] for g in _gcff(positions[idx], yaws[idx], params)]
        return sorted(out, key=lambda g: int(g[0]))
    return _gcff(positions, yaws, params)


def _gcff(positions: FloatArray, yaws: FloatArray, params: FFormationParams) -> list[np.ndarray]:
    k = positions.shape[0]
    vote = votes(positions, yaws, params.stride)
    reach = max(params.sigma, params.sigma_along) * np.sqrt(params.mdl)
    centers = np.concatenate([vote, _local_means(vote, reach)])
    labels = np.arange(k)
    for _ in range(max(1, params.iterations)):
        costs = assignment_costs(positions, vote, centers, params)
        new = facility_location(costs, params.mdl)
        used, first = np.unique(new, return_index=True)
        centers = np.array([_centre(vote[new == u], positions[new == u], params) for u in used])
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
    groups = [np.flatnonzero(labels == u) for u in np.unique(labels)]
    return [g for g in groups if g.size >= 2]


class FFormationDetector(ParamDetector[FFormationParams]):
    """Registered as ``fformation``: GCFF over the standing people not yet claimed."""

    params_type = FFormationParams

    def __call__(
        self, frame: TrackFrame, knowledge: MapKnowledge, claimed: frozenset[int]
    ) -> list[Candidate]:
        """Candidates of one frame (see :data:`~socialnav.social.perception.base.Detector`)."""
        del knowledge
        idx = unclaimed(frame, claimed, frame.standing(self.params.standing_speed))
        pos, yaw = frame.positions[idx], frame.yaws[idx]
        out = []
        vote = votes(pos, yaw, self.params.stride)
        for g in gcff(pos, yaw, self.params):
            center = _centre(vote[g], pos[g], self.params)
            cost = assignment_costs(pos[g], vote[g], center[None], self.params)[:, 0]
            radius = float(np.linalg.norm(pos[g] - center, axis=1).mean())
            out.append(
                Candidate(
                    "fformation",
                    tuple(int(i) for i in frame.ids[idx[g]]),
                    float(np.clip(1.0 - cost.mean() / self.params.mdl, 0.0, 1.0)),
                    geometry={"ospace_center": center, "ospace_radius": radius},
                )
            )
        return out


DETECTORS.add("fformation", FFormationDetector)

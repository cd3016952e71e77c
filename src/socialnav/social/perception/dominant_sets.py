"""Standing conversational groups (F-formations, pairs included) as dominant sets of an
affinity graph, with headings as soft evidence.

Method: H. Hung, B. Kröse, "Detecting F-formations as dominant sets", ICMI 2011; dominant sets
and their replicator-dynamics extraction: M. Pavan, M. Pelillo, "Dominant sets and pairwise
clustering", IEEE TPAMI 29(1), 2007. Registered as ``dominant_sets``; it returns the same
``fformation`` candidates as the GCFF detector (:mod:`.fformations`, registered as
``fformation``), so either can stand in the estimator's pipeline.

1. **Affinity** ``A (K, K)`` between standing people, zero diagonal::

       A_ij = exp(−d_ij² / 2σ_d²) · ((1 − ρ) + ρ · exp(−|c_i − c_j|² / 2σ_o²))

   ``d_ij`` the distance between ``i`` and ``j`` (``A_ij = 0`` beyond ``max_distance``),
   ``c_i = p_i + D·(cos θ_i, sin θ_i)`` person ``i``'s o-space vote (as GCFF's, ``D`` the
   ``stride``): two people facing a common o-space have nearby votes (Kendon 1990).
   Hung & Kröse gate the proximity by whether the two can see each other, so a wrong heading
   cuts a link outright; here the heading is soft evidence weighted by its *reliability*
   ``ρ ∈ [0, 1]``: ``ρ = 0`` is proximity alone, ``ρ = 1`` makes the vote agreement a factor.
   With coarse or often wrong headings (a head-pose classifier's four classes) proximity
   keeps most of the weight.
2. **Dominant sets** (Pavan & Pelillo 2007). A dominant set is a maximally cohesive subset:
   a local maximiser ``x`` on the simplex of ``f(x) = xᵀ A x``; its support
   ``{i : x_i > support}`` is the set. The replicator dynamics
   ``x_i ← x_i (A x)_i / xᵀ A x`` from the barycentre converge to one
   (``iterations``, ``tolerance``). Each component of the ``max_distance`` graph is peeled: the
   dominant set is extracted, removed, and the rest solved again, while the set has two or
   more members and its *cohesion* reaches ``min_cohesion`` (Hung & Kröse stop the same way).
   Cohesion is ``Σ_{i≠j} x_i x_j A_ij / Σ_{i≠j} x_i x_j``, the ``x``-weighted mean affinity
   within the set, in [0, 1]: for ``k`` members with equal affinity ``a`` it is ``a`` whatever
   ``k`` (``xᵀ A x`` itself would be ``a (k − 1) / k``, favouring large sets).

Parameters (metres; defaults fitted on the Cristani et al. *Synth* data with its headings
quantised to 90°, CoffeeBreak's detected heading step, by the protocol of
``benchmarks/bench_context.py`` (:func:`dominant_sets_grid`), never on CoffeeBreak):
``sigma_distance`` σ_d, ``reliability`` ρ, ``stride`` D, ``sigma_vote`` σ_o,
``min_cohesion``: σ_d 1.0 m, ρ 1, D 0.4 m, σ_o 0.6 m, minimum cohesion 0.1 (mean F1 of
T = 2/3 and T = 1 on quantised Synth 0.944; ρ and the cohesion at the edge of the grid). ρ = 1
keeps the heading as a factor, not a gate: with σ_o 0.6 m a member whose vote lies 1 m from
the others' still keeps ``exp(−1/0.72) ≈ 0.25`` of the proximity affinity. A priori:
``max_distance`` 3 m (the widest pair of the project's group scenarios, as
:class:`~socialnav.social.perception.fformations.FFormationParams` ``pair_max_distance``),
``support`` 1e-4, ``iterations`` 1000, ``tolerance`` 1e-9.

Output: groups of at least two members, more than half of whom have the o-space centre in
front of them (:func:`~socialnav.social.perception.base.faces_ospace`: proximity alone made
two people standing back to back a set); o-space centre the members' mean position (the
centre of a circle of evenly spread members, the midpoint of a pair), radius the mean member
distance to it; score 0.6 at the minimum cohesion, rising linearly to 1 at cohesion 1 (the
tracker's hysteresis confirms a candidate above 0.5).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_array
from scipy.sparse.csgraph import connected_components

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.geometry import FloatArray
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
class DominantSetsParams:
    """Dominant-sets parameters (module docstring); lengths in metres. Raises
    :class:`~socialnav.core.errors.ConfigurationError` for a value out of range."""

    sigma_distance: float = 1.0
    reliability: float = 1.0
    stride: float = 0.4
    sigma_vote: float = 0.6
    min_cohesion: float = 0.1
    max_distance: float = 3.0
    support: float = 1e-4
    iterations: int = 1000
    tolerance: float = 1e-9
    standing_speed: float = STANDING_SPEED

    def __post_init__(self) -> None:
        checks = {
            "sigma_distance": self.sigma_distance > 0,
            "reliability": 0.0 <= self.reliability <= 1.0,
            "stride": self.stride >= 0,
            "sigma_vote": self.sigma_vote > 0,
            "min_cohesion": 0.0 <= self.min_cohesion <= 1.0,
            "max_distance": self.max_distance > 0,
            "support": 0.0 < self.support < 0.5,
            "iterations": self.iterations >= 1,
            "tolerance": self.tolerance > 0,
        }
        for name, ok in checks.items():
            value = getattr(self, name)
            if not ok or not np.isfinite(value):
                raise ConfigurationError(f"DominantSetsParams.{name} out of range: {value}")


def affinity(positions: FloatArray, yaws: FloatArray, params: DominantSetsParams) -> FloatArray:
    """Affinity ``(K, K)`` in [0, 1] of people at ``positions (K, 2)`` (m) with headings
    ``yaws (K,)`` (rad, CCW from +x), step 1 of the module docstring; zero diagonal. Raises
    :class:`~socialnav.core.errors.InvalidInputError` for mismatched shapes or non-finite
    values."""
    pos = np.asarray(positions, dtype=float)
    yaw = np.asarray(yaws, dtype=float)
    if pos.ndim != 2 or pos.shape[1] != 2 or yaw.shape != (pos.shape[0],):
        raise InvalidInputError(
            f"positions must be (K, 2) and yaws (K,): got {pos.shape} and {yaw.shape}"
        )
    if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(yaw))):
        raise InvalidInputError("positions or yaws contain NaN or infinite values")
    p = params
    d2 = ((pos[:, None, :] - pos[None, :, :]) ** 2).sum(-1)
    a = np.exp(-d2 / (2 * p.sigma_distance**2))
    if p.reliability > 0:
        vote = pos + p.stride * np.column_stack([np.cos(yaw), np.sin(yaw)])
        v2 = ((vote[:, None, :] - vote[None, :, :]) ** 2).sum(-1)
        a *= (1 - p.reliability) + p.reliability * np.exp(-v2 / (2 * p.sigma_vote**2))
    a[d2 > p.max_distance**2] = 0.0
    np.fill_diagonal(a, 0.0)
    return a


def _check_affinity(a: FloatArray) -> FloatArray:
    a = np.asarray(a, dtype=float)
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise InvalidInputError(f"affinity must be a square (K, K) matrix: got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError("affinity contains NaN or infinite values")
    if np.any(a < 0):
        raise InvalidInputError("affinity must be non-negative")
    if not np.allclose(a, a.T, atol=1e-12):
        raise InvalidInputError("affinity must be symmetric")
    return a


def replicator(a: FloatArray, iterations: int = 1000, tolerance: float = 1e-9) -> FloatArray:
    """The replicator dynamics ``x_i ← x_i (A x)_i / xᵀ A x`` on ``a (K, K)`` (symmetric,
    non-negative, zero diagonal) from the barycentre: a local maximiser ``x (K,)`` of
    ``xᵀ A x`` on the simplex (Pavan & Pelillo 2007), after at most ``iterations`` steps or
    when no weight moves by more than ``tolerance``. A graph without edges returns the
    barycentre."""
    k = a.shape[0]
    x = np.full(k, 1.0 / k)
    for _ in range(iterations):
        ax = a @ x
        f = float(x @ ax)
        if f <= 0.0:
            break
        new = x * ax / f
        done = float(np.abs(new - x).max()) <= tolerance
        x = new
        if done:
            break
    return x


def cohesion(a: FloatArray, x: FloatArray) -> float:
    """``Σ_{i≠j} x_i x_j A_ij / Σ_{i≠j} x_i x_j`` (zero diagonal): the ``x``-weighted mean
    affinity, in [0, 1] for affinities in [0, 1]; 0 when ``x`` has a single member."""
    off = 1.0 - float(x @ x)
    return float(x @ a @ x) / off if off > 1e-12 else 0.0


def peel(a: FloatArray, params: DominantSetsParams) -> list[tuple[np.ndarray, float]]:
    """Dominant sets of one affinity ``a (K, K)``, best first, each with its cohesion: step 2
    of the module docstring (extract, remove, repeat while a set of two or more reaches
    ``min_cohesion``). Raises :class:`~socialnav.core.errors.InvalidInputError` for an
    affinity that is not square, symmetric, finite and non-negative."""
    a = _check_affinity(a).copy()
    np.fill_diagonal(a, 0.0)
    left = np.arange(a.shape[0])
    out: list[tuple[np.ndarray, float]] = []
    while left.size >= 2:
        sub = a[np.ix_(left, left)]
        x = replicator(sub, params.iterations, params.tolerance)
        members = np.flatnonzero(x > params.support)
        if members.size < 2:
            break
        c = cohesion(sub[np.ix_(members, members)], x[members] / x[members].sum())
        if c < params.min_cohesion:
            break
        out.append((left[members], c))
        left = np.delete(left, members)
    return out


def dominant_sets(
    positions: FloatArray, yaws: FloatArray, params: DominantSetsParams
) -> list[tuple[np.ndarray, float]]:
    """Groups (index arrays into ``positions (K, 2)``, two or more members, sorted by first
    index) with their cohesion, each connected component of the ``max_distance`` graph
    peeled alone (:func:`peel`)."""
    a = affinity(positions, yaws, params)
    if a.shape[0] < 2:
        return []
    comp = connected_components(csr_array((a > 0).astype(np.int8)), directed=False)[1]
    out = []
    for c in np.unique(comp):
        idx = np.flatnonzero(comp == c)
        if idx.size >= 2:
            for g, s in peel(a[np.ix_(idx, idx)], params):
                g = np.sort(idx[g])
                # the o-space the members' votes point at (the mean position is beside a pair
                # standing side by side, facing one way)
                votes = positions[g] + params.stride * np.column_stack(
                    [np.cos(yaws[g]), np.sin(yaws[g])]
                )
                if faces_ospace(positions[g], yaws[g], votes.mean(axis=0)):
                    out.append((g, s))
    return sorted(out, key=lambda gs: int(gs[0][0]))


class DominantSetsDetector(ParamDetector[DominantSetsParams]):
    """Registered as ``dominant_sets``: dominant sets (module docstring) over the standing
    people not yet claimed; ``fformation`` candidates, as the GCFF detector's."""

    params_type = DominantSetsParams

    def __call__(
        self, frame: TrackFrame, knowledge: MapKnowledge, claimed: frozenset[int]
    ) -> list[Candidate]:
        """Candidates of one frame (see :data:`~socialnav.social.perception.base.Detector`)."""
        del knowledge
        p = self.params
        idx = unclaimed(frame, claimed, frame.standing(p.standing_speed))
        idx = idx[np.argsort(frame.ids[idx], kind="stable")]  # members in id order
        pos, ids = frame.positions[idx], frame.ids[idx]
        out = []
        for g, cohesion in dominant_sets(pos, frame.yaws[idx], p):
            center = pos[g].mean(axis=0)
            radius = float(np.linalg.norm(pos[g] - center, axis=1).mean())
            # A set the peeling accepted (cohesion >= min_cohesion) is evidence of a group:
            # 0.6 at the acceptance threshold, rising to 1 with cohesion, so the tracker's
            # hysteresis (on = 0.5) confirms it as it does GCFF's; the raw cohesion of a
            # group of 1.3-1.8 m gaps is about 0.2 and would never be confirmed.
            c0 = min(p.min_cohesion, 1.0 - 1e-9)
            score = 0.6 + 0.4 * (float(cohesion) - c0) / (1.0 - c0)
            out.append(
                Candidate(
                    "fformation",
                    tuple(int(i) for i in ids[g]),
                    float(np.clip(score, 0.0, 1.0)),
                    geometry={"ospace_center": center, "ospace_radius": radius},
                )
            )
        return out


DETECTORS.add("dominant_sets", DominantSetsDetector)

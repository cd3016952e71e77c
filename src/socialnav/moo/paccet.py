"""PaCcET: Pareto Concavity Elimination Transformation (closed form and reference parity).

Yliniemi & Tumer, "PaCcET: An Objective Space Transformation to Shape the Pareto Front and
Eliminate Concavity" (SEAL 2014); used for trajectory selection by Banisetty et al.,
"Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach".

All objectives are minimized; lower fitness is better. For a candidate ``f`` with normalized
``x = (f - u) / (n - u)`` (utopia ``u = min_A - delta``, nadir ``n = max_A`` over the archive A):

    s*(x) = min_{s in N(A)} max_j s_j / x_j,        T(f) = x / (s*(x) * sum_j x_j)

so the archive's attainment surface maps onto the simplex ``sum(T) = 1``.

Deviations from the reference code (each an option of :class:`PaccetOptions`; the reference
behaviour is ``PaccetOptions.reference()``):
- ``method="closed_form"`` (default) evaluates ``s*`` exactly as one chunked n×P×m reduction;
  the reference bisects ``v_B`` and ``v_hp`` on ``[0, 2*sqrt(m) + 0.1]`` (``method="parity"``
  reproduces that quantization and clipping, vectorized over all candidates);
- ``delta_mode="relative"`` (default): ``delta_j = delta * range_j`` so the selection is
  invariant under positive affine rescaling of an objective (reference: absolute 0.001);
- ``drop_constant_objectives`` (default on): objectives with zero range over the archive carry
  no information and make every candidate's ``s* = 1``; they are removed before transforming
  (their ``T`` column is 0);
- ``rank_weakly_dominated`` (default on): candidates not in the archive (weakly dominated,
  later exact duplicates included) rank below all archive members (secondary key), closing the
  weak-dominance blind spot where e.g. (30, 0) next to (25, 0) also gets ``s* = 1``;
- ``sentinel`` (default 1e9, the navigation code's "touching a person" value): values
  ``>= sentinel`` are capped, per objective, to ``hi + span`` where ``hi``/``span`` are the
  max/range of the regular (``< sentinel``) values of that objective over candidates and
  archive (``hi + max(|hi|, 1)`` if span is 0; the sentinel itself if no regular value). They
  stay the worst value of their objective and tie among themselves, but no longer squash the
  normalization of the regular values;
- ``indifference`` (default off): per-objective thresholds ``q`` (raw units; the name of
  outranking methods' indifference thresholds, Roy's ELECTRE): each objective's nonzero
  normalizing range over the archive is raised to at least its ``q``, so a difference
  ``delta`` moves a normalized coordinate by at most ``delta / q``. Without it a difference of
  1e-6 in an objective whose archive range is 1e-6 spans the whole normalized range: beside a
  person standing still, a robot chose a command 0.15 worse in navigation for a 1e-6 lower
  interpersonal cost, every cycle. It is a floor, not a dead zone: near the utopia the
  transformation compares coordinates by their ratios, and the utopia offset is relative
  (``delta_mode``), so a difference of about ``0.001 * q`` can still decide between two
  archive members (the example above needs ``q >= 0.003``). It changes the choice only under
  a scalarization that tells archive members apart (``L1Target``, ``Weighted``):
  ``EqualWeight`` scores every member 1. Removing the archive members that another beats by
  more than ``q`` (epsilon-dominance) was tried and not kept: a two-member archive is left
  more often, and an L1 target then picks the extreme best in the social objectives however
  small its lead (a robot stopped 1.5 m from a person it could pass);
- fitness values within a relative 1e-12 are ties (``sum(T)`` of simplex points differs from 1
  by rounding only); ties go to the lowest candidate index.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from socialnav.core import compiled
from socialnav.moo.archive import ParetoArchive
from socialnav.moo.nondominated import nondominated_mask, validate_objectives
from socialnav.moo.scalarize import EqualWeight, Scalarization

__all__ = [
    "PaccetOptions",
    "PaccetRanking",
    "PaccetTransform",
    "best_index",
    "cap_sentinels",
    "normalize",
    "paccet_select",
    "paccet_transform",
]

# Fitness values closer than this (relative) are ties, broken by the lowest index.
TIE_RTOL = 1e-12
# Elements of the (chunk x P) work matrix of the closed form (~0.5 MB of float64: cache sized).
_CHUNK_ELEMS = 1 << 16


@dataclass(frozen=True)
class PaccetOptions:
    """Options of the PaCcET transformation; defaults are the sensible remedies ON.

    Attributes
    ----------
    delta: utopia offset below the archive minimum (raw units if absolute, fraction of the
        archive range if relative). Reference 0.001 absolute.
    delta_mode: ``"relative"`` (default) or ``"absolute"`` (reference).
    method: ``"closed_form"`` (default) or ``"parity"`` (reference bisections).
    parity_vb_tol: bisection tolerance on ``v_B`` (navigation code 1e-2; author's header 1e-4).
    parity_hp_tol: bisection tolerance on ``v_hp`` (1e-4 in both reference codes).
    drop_constant_objectives: drop objectives with zero range over the archive (default on).
    rank_weakly_dominated: rank non-archive candidates below archive members (default on).
    sentinel: values ``>= sentinel`` are capped (see module docstring); ``None`` disables.
    indifference: per-objective indifference thresholds ``(m,)`` in the objectives' raw units
        (a floor on each normalizing range; module docstring), or ``None`` (reference). A
        list or array is stored as a tuple.
    """

    delta: float = 0.001
    delta_mode: Literal["absolute", "relative"] = "relative"
    method: Literal["closed_form", "parity"] = "closed_form"
    parity_vb_tol: float = 1e-2
    parity_hp_tol: float = 1e-4
    drop_constant_objectives: bool = True
    rank_weakly_dominated: bool = True
    sentinel: float | None = 1e9
    indifference: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        for name in ("delta", "parity_vb_tol", "parity_hp_tol"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive finite number, got {value}")
        if self.delta_mode not in ("absolute", "relative"):
            raise ValueError(f"delta_mode must be 'absolute' or 'relative', got {self.delta_mode}")
        if self.method not in ("closed_form", "parity"):
            raise ValueError(f"method must be 'closed_form' or 'parity', got {self.method!r}")
        if self.sentinel is not None and not math.isfinite(self.sentinel):
            raise ValueError(f"sentinel must be finite or None, got {self.sentinel}")
        if self.indifference is not None:
            try:
                values = tuple(float(q) for q in self.indifference)
            except (TypeError, ValueError) as exc:
                raise ValueError(
                    f"indifference must be a sequence of thresholds, got {self.indifference!r}"
                ) from exc
            if not all(math.isfinite(q) and q >= 0 for q in values):
                raise ValueError(f"indifference must be finite and >= 0, got {values}")
            object.__setattr__(self, "indifference", values)  # hashable, like every field

    def thresholds(self, m: int) -> np.ndarray:
        """``(m,)`` indifference thresholds (zeros when off); ``ValueError`` on a length other
        than ``m``."""
        if self.indifference is None:
            return np.zeros(m)
        if len(self.indifference) != m:
            raise ValueError(
                f"indifference has {len(self.indifference)} thresholds for {m} objectives"
            )
        return np.asarray(self.indifference, dtype=np.float64)

    @classmethod
    def reference(cls, parity_vb_tol: float = 1e-2) -> PaccetOptions:
        """Reference behaviour: absolute delta 0.001, parity bisections, every remedy off."""
        return cls(
            delta=0.001,
            delta_mode="absolute",
            method="parity",
            parity_vb_tol=parity_vb_tol,
            parity_hp_tol=1e-4,
            drop_constant_objectives=False,
            rank_weakly_dominated=False,
            sentinel=None,
        )


@dataclass(frozen=True)
class PaccetRanking:
    """Outcome of :func:`paccet_select` for ``n`` candidates and ``m`` objectives.

    ``transformed`` (n, m) PaCcET coordinates (0 in dropped columns); ``fitness`` (n,) scalarized
    (lower is better); ``best_index`` selected candidate; ``nondominated`` (n,) archive
    membership; ``kept_objectives`` (m,) columns used by the transformation.
    """

    transformed: np.ndarray
    fitness: np.ndarray
    best_index: int
    nondominated: np.ndarray
    kept_objectives: np.ndarray
    rank_weakly_dominated: bool = field(default=True, repr=False)

    def order(self) -> np.ndarray:
        """``(n,)`` candidate indices best first: (dominated?, fitness, index) lexicographic."""
        idx = np.arange(self.fitness.size)
        fit = np.where(np.isnan(self.fitness), np.inf, self.fitness)
        if self.rank_weakly_dominated:
            return np.lexsort((idx, fit, ~self.nondominated))
        return np.lexsort((idx, fit))


# ---------------------------------------------------------------------------- preprocessing
def cap_sentinels(F: np.ndarray, sentinel: float | None, *others: np.ndarray) -> list[np.ndarray]:
    """Cap values ``>= sentinel`` per column of ``F`` and each of ``others`` (same m).

    The cap is computed over all given arrays together (see module docstring), so the arrays
    stay comparable. Returns the arrays (copies only when something was capped).
    """
    arrays = [F, *others]
    if sentinel is None or not any((a >= sentinel).any() for a in arrays):
        return arrays
    both = np.concatenate(arrays)
    regular = both < sentinel
    has_regular = regular.any(axis=0)
    hi = np.where(regular, both, -np.inf).max(axis=0)
    lo = np.where(regular, both, np.inf).min(axis=0)
    span = hi - lo
    with np.errstate(invalid="ignore"):
        cap = np.where(span > 0, hi + span, hi + np.maximum(np.abs(hi), 1.0))
    cap = np.where(has_regular, cap, sentinel)
    return [np.where(a >= sentinel, cap, a) for a in arrays]


def _bounds(
    F: np.ndarray, A: np.ndarray, options: PaccetOptions
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """lo, hi (archive min/max), per-objective delta d, kept mask; all (m,)."""
    lo, hi = _column_range(A)
    rng = hi - lo
    kept = rng > 0 if options.drop_constant_objectives else np.ones(rng.size, dtype=bool)
    if not kept.any():  # single-point archive: every objective is constant, keep them all
        kept = np.ones(rng.size, dtype=bool)
    if options.indifference is not None:  # a range below q is raised to q (module docstring)
        q = options.thresholds(rng.size)
        hi = np.where((rng > 0) & (rng < q), lo + q, hi)
        rng = hi - lo
    if options.delta_mode == "absolute":
        d = np.full(rng.size, options.delta)
    else:
        # Zero archive range: fall back to the spread of all given points (scale invariant),
        # then to the absolute delta (everything equal, so the scale is irrelevant).
        f_lo, f_hi = _column_range(F)
        spread = np.maximum(f_hi, hi) - np.minimum(f_lo, lo)
        base = np.where(rng > 0, rng, np.where(spread > 0, spread, 1.0))
        d = options.delta * base
    return lo, hi, d, kept


def normalize(
    F: np.ndarray, archive_points: np.ndarray, options: PaccetOptions | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Normalize ``F`` (n, m) by the archive (P, m): ``(x (n, m), utopia (m,), nadir (m,))``.

    ``x = (F - utopia) / (nadir - utopia)``; archive members land in ``(0, 1]^m``. Sentinel
    capping applies; constant objectives are *not* dropped here (see ``kept_objectives``).
    """
    options = options or PaccetOptions()
    F = validate_objectives(F)
    A = validate_objectives(archive_points, "archive_points", ncols=F.shape[1])
    F, A = cap_sentinels(F, options.sentinel, A)
    lo, hi, d, _ = _bounds(F, A, options)
    return _normalized(F, lo, hi, d), lo - d, hi


def _normalized(F: np.ndarray, lo: np.ndarray, hi: np.ndarray, d: np.ndarray) -> np.ndarray:
    # Written as (f - lo + d) / (hi - lo + d): exact for power-of-two rescaling and shifts of
    # integer data, so invariance tests compare bit-identical values.
    return (F - lo + d) / (hi - lo + d)


# ---------------------------------------------------------------------------- transformation
def _s_star(x: np.ndarray, S: np.ndarray, members: np.ndarray | None = None) -> np.ndarray:
    """``(n,)`` ``min_p max_j S[p, j] / x[:, j]`` (+inf terms where ``x_j <= 0``).

    ``S`` (P, k) must be mutually non-dominated and unique (an archive). ``members`` (n,)
    marks rows of ``x`` known to equal an archive member: their ``s*`` is exactly 1 (their own
    ratio is 1, every other member exceeds it in some objective), so they are skipped.
    """
    n, k = x.shape
    out = np.ones(n)
    rows = np.arange(n) if members is None else np.flatnonzero(~members)
    if rows.size == 0:
        return out
    xr = x[rows]
    inv = np.full_like(xr, np.inf)
    np.divide(1.0, xr, out=inv, where=xr > 0)
    # The staircase search only pays off beyond a few dozen members (sort + gather overhead).
    out[rows] = _s_star_2d(inv, S) if k == 2 and S.shape[0] > 32 else _s_star_dense(inv, S)
    return out


@compiled.jit
def _s_star_kernel(inv_t, S, out):  # type: ignore[no-untyped-def]
    """``out[i] = min_p max_j inv_t[j, i] * S[p, j]`` (``inv_t (k, n)``: ``inv`` transposed):
    the dense path's products, maxima over ``j`` and minima over ``p`` in its order (NaN
    propagating as in ``np.maximum`` and ``min``), so the same values. Each step is one
    element-wise pass over the candidates, which the compiler vectorizes."""
    k, n = inv_t.shape
    m = np.empty(n)
    for i in range(n):
        out[i] = np.inf
    for p in range(S.shape[0]):
        s0 = S[p, 0]
        for i in range(n):
            m[i] = inv_t[0, i] * s0
        for j in range(1, k):
            sj = S[p, j]
            for i in range(n):
                t = inv_t[j, i] * sj
                mi = m[i]
                m[i] = t if (t > mi) | (t != t) else mi
        for i in range(n):
            mi = m[i]
            b = out[i]
            out[i] = mi if (mi < b) | (mi != mi) else b


@compiled.jit
def _column_range_kernel(X, lo, hi):  # type: ignore[no-untyped-def]
    """``lo``/``hi (m,)`` = ``X.min(axis=0)``/``X.max(axis=0)`` of ``X (n, m)``, n > 0 (exact;
    NaN propagating as in ``np.min``)."""
    n, m = X.shape
    for j in range(m):
        lo[j] = X[0, j]
        hi[j] = X[0, j]
    for i in range(1, n):
        for j in range(m):
            v = X[i, j]
            if v < lo[j] or v != v:
                lo[j] = v
            if v > hi[j] or v != v:
                hi[j] = v


def _column_range(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Column minima and maxima ``(m,)`` of a non-empty ``X (n, m)`` (one compiled pass)."""
    if compiled.enabled() and X.shape[0] > 0:
        lo = np.empty(X.shape[1])
        hi = np.empty(X.shape[1])
        _column_range_kernel(np.ascontiguousarray(X, dtype=np.float64), lo, hi)
        return lo, hi
    return X.min(axis=0), X.max(axis=0)


def warmup() -> None:
    """Compile (or load) the compiled kernels of PaCcET (see ``socialnav.core.compiled``)."""
    from socialnav.moo import nondominated

    nondominated.warmup()
    if compiled.AVAILABLE:
        _s_star_kernel(np.ones((3, 2)), np.ones((2, 3)), np.empty(2))
        _column_range(np.ones((2, 3)))


def _s_star_dense(inv: np.ndarray, S: np.ndarray) -> np.ndarray:
    """All pairs, one objective at a time, chunked so the (chunk, P) work matrix stays in cache
    (compiled: one pass, the same values)."""
    if compiled.enabled() and S.shape[0] > 0 and inv.shape[1] > 0:
        out = np.empty(inv.shape[0])
        _s_star_kernel(
            np.ascontiguousarray(inv.T, dtype=np.float64),
            np.ascontiguousarray(S, dtype=np.float64),
            out,
        )
        return out
    n, k = inv.shape
    P = S.shape[0]
    out = np.empty(n)
    chunk = max(1, _CHUNK_ELEMS // P)
    ST = np.ascontiguousarray(S.T)  # (k, P): contiguous rows for the broadcasts below
    acc = np.empty((min(chunk, n), P))
    tmp = np.empty_like(acc)
    for s in range(0, n, chunk):
        iv = inv[s : s + chunk]
        c = iv.shape[0]
        a, t = acc[:c], tmp[:c]
        np.multiply(iv[:, 0:1], ST[0], out=a)
        for j in range(1, k):
            np.multiply(iv[:, j : j + 1], ST[j], out=t)
            np.maximum(a, t, out=a)
        a.min(axis=1, out=out[s : s + c])
    return out


def _s_star_2d(inv: np.ndarray, S: np.ndarray) -> np.ndarray:
    """m = 2 in O((n + P) log P): on the archive staircase (S0 up, S1 down) the first ratio
    S_p0/x0 increases and the second S_p1/x1 decreases with p, so the min of their max sits
    where ``S_p0/S_p1`` crosses ``x0/x1``; the neighbours of that crossing are evaluated with
    the same products as the dense path (bit-identical result)."""
    S = S[np.argsort(S[:, 0], kind="stable")]
    if not (np.all(np.diff(S[:, 0]) > 0) and np.all(np.diff(S[:, 1]) < 0)):
        # Not a staircase (caller-supplied archive with dominated rows or duplicates):
        # dominated rows never attain the minimum, so filtering them is exact.
        S = S[nondominated_mask(S)]
        S = S[np.argsort(S[:, 0], kind="stable")]
    P = S.shape[0]
    with np.errstate(invalid="ignore", divide="ignore"):
        key = S[:, 0] / S[:, 1]  # strictly increasing (S > 0, staircase)
        xk = inv[:, 1] / inv[:, 0]  # = x0 / x1; NaN/inf rows have s* = inf anyway
    k = np.searchsorted(key, np.where(np.isnan(xk), np.inf, xk))
    near = np.clip(k[:, None] + np.arange(-2, 2), 0, P - 1)  # (n, 4) around the crossing
    f = np.maximum(inv[:, 0:1] * S[near, 0], inv[:, 1:2] * S[near, 1])
    return f.min(axis=1)


def _bisect_steps(upper: float, tol: float) -> int:
    """Iterations of the reference loop ``while (hi - lo) > tol`` starting from ``[0, upper]``."""
    lo, hi, steps = 0.0, upper, 0
    while hi - lo > tol:
        hi = (lo + hi) / 2  # the margin sequence does not depend on which side moves
        steps += 1
    return steps


def _parity_scale(x: np.ndarray, s_star: np.ndarray, options: PaccetOptions) -> np.ndarray:
    """Reference bisections, all candidates at once: returns ``v_hp / v_B`` per row ``(n,)``.

    Along the unit direction ``x/|x|`` the archive dominates the point at distance ``c`` iff
    ``c >= |x| * s*`` (the reference tests every archive member per step; this is the same
    predicate up to rounding), and ``c * sum(x)/|x| <= 1`` iff ``c <= |x| / sum(x)``.
    """
    k = x.shape[1]
    upper = 2.0 * math.sqrt(k) + 0.1
    r = np.sqrt(np.einsum("ij,ij->i", x, x))
    sx = x.sum(axis=1)
    c_b = r * s_star  # +inf when never dominated along the ray
    with np.errstate(divide="ignore", invalid="ignore"):
        c_hp = np.where(sx > 0, r / sx, np.inf)
    v_b = _bisect(c_b, upper, options.parity_vb_tol, hit_moves_upper=True)
    v_hp = _bisect(c_hp, upper, options.parity_hp_tol, hit_moves_upper=False)
    return v_hp / v_b


def _bisect(crossing: np.ndarray, upper: float, tol: float, *, hit_moves_upper: bool) -> np.ndarray:
    lo = np.zeros_like(crossing)
    hi = np.full_like(crossing, upper)
    for _ in range(_bisect_steps(upper, tol)):
        mid = 0.5 * (lo + hi)
        if hit_moves_upper:  # v_B: dominated (mid >= crossing) -> upper = mid
            hit = mid >= crossing
            hi = np.where(hit, mid, hi)
            lo = np.where(hit, lo, mid)
        else:  # v_hp: below the hyperplane (mid <= crossing) -> lower = mid
            hit = mid <= crossing
            lo = np.where(hit, mid, lo)
            hi = np.where(hit, hi, mid)
    return 0.5 * (lo + hi)


def _transform_core(
    F: np.ndarray, A: np.ndarray, options: PaccetOptions, members: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Validated, sentinel-capped F (n, m) and A (P, m) -> (T (n, m), kept (m,)).

    ``members`` (n,) optionally marks rows of F that are (unique) rows of A.
    """
    lo, hi, d, kept = _bounds(F, A, options)
    cols = np.flatnonzero(kept)
    if cols.size < kept.size:
        lo, hi, d = lo[cols], hi[cols], d[cols]
        Fk, Ak = F[:, cols], A[:, cols]
    else:
        Fk, Ak = F, A
    x = _normalized(Fk, lo, hi, d)
    S = _normalized(Ak, lo, hi, d)
    # Dropped columns are constant over the archive, so members stay unique and mutually
    # non-dominated in the reduced space and ``members`` remains valid.
    s_star = _s_star(x, S, members)
    if options.method == "parity":
        scale = _parity_scale(x, s_star, options)
        Tk = x * scale[:, None]
        Tk[~(np.abs(x).sum(axis=1) > 0)] = 0.0  # x == 0 (the utopia itself): no direction
    else:
        finite = np.isfinite(s_star)
        denom = np.where(finite, s_star * x.sum(axis=1), 1.0)
        Tk = np.where(finite[:, None], x / denom[:, None], 0.0)
    if cols.size == kept.size:
        return Tk, kept
    T = np.zeros(F.shape)
    T[:, cols] = Tk
    return T, kept


def paccet_transform(
    F: np.ndarray, archive_points: np.ndarray, options: PaccetOptions | None = None
) -> np.ndarray:
    """PaCcET coordinates ``T`` ``(n, m)`` of candidates ``F`` ``(n, m)`` for an archive ``(P, m)``.

    The archive should be mutually non-dominated (as :class:`ParetoArchive` keeps it); its
    members map onto ``sum(T) = 1``. Points beyond the utopia in every objective never become
    dominated along their ray (``s* = inf``) and map to ``T = 0`` in closed form.
    Raises ``ValueError`` on invalid or mismatched inputs or an empty archive.
    """
    options = options or PaccetOptions()
    F = validate_objectives(F)
    A = validate_objectives(archive_points, "archive_points", ncols=F.shape[1])
    F, A = cap_sentinels(F, options.sentinel, A)
    return _transform_core(F, A, options)[0]


# ---------------------------------------------------------------------------- selection
def best_index(fitness: np.ndarray, eligible: np.ndarray | None = None) -> int:
    """Lowest fitness among ``eligible`` rows (all if None); ties (TIE_RTOL) -> lowest index.

    NaN counts as +inf. ``eligible`` must select at least one row.
    """
    f = np.where(np.isnan(fitness), np.inf, fitness)
    if eligible is not None:
        f = np.where(eligible, f, np.inf)
    fmin = f.min()
    if not np.isfinite(fmin):
        return int(np.argmin(f)) if eligible is None else int(np.flatnonzero(eligible)[0])
    tie = f <= fmin + TIE_RTOL * max(1.0, abs(fmin))
    return int(np.argmax(tie))


def _score(scalarization: Scalarization, T: np.ndarray) -> np.ndarray:
    fitness = np.asarray(scalarization(T), dtype=np.float64)
    if fitness.shape != (T.shape[0],):
        raise ValueError(f"scalarization returned shape {fitness.shape}, want ({T.shape[0]},)")
    return fitness


def paccet_select(
    F: np.ndarray,
    scalarization: Scalarization | None = None,
    options: PaccetOptions | None = None,
) -> PaccetRanking:
    """Stateless PaCcET selection over candidates ``F`` ``(n, m)`` (the planner's use).

    A fresh archive is built from the non-dominated rows of (sentinel-capped) ``F``; every
    candidate is transformed and scalarized (default :class:`EqualWeight`, which scores every
    archive member 1, so the lowest-index member wins). The best index has the lowest fitness,
    ties to the lowest index; with ``rank_weakly_dominated`` only archive members are eligible
    (there is always at least one). Raises ``ValueError`` on an invalid ``F`` or on
    ``options.indifference`` of another length than ``m``.
    """
    scalarization = scalarization if scalarization is not None else EqualWeight()
    options = options or PaccetOptions()
    F = validate_objectives(F)
    (F,) = cap_sentinels(F, options.sentinel)
    nd = nondominated_mask(F)
    T, kept = _transform_core(F, F[nd], options, members=nd)
    fitness = _score(scalarization, T)
    best = best_index(fitness, nd if options.rank_weakly_dominated else None)
    return PaccetRanking(T, fitness, best, nd, kept, options.rank_weakly_dominated)


class PaccetTransform:
    """Stateful PaCcET with a persistent archive (elitist memory of an optimizer).

    ``tell(F)`` offers rows to the archive; ``transform``/``fitness``/``order`` evaluate
    candidates against the current archive. ``threshold``/``buffer``/``seed`` configure the
    archive's random thinning (:class:`ParetoArchive`).
    """

    def __init__(
        self,
        options: PaccetOptions | None = None,
        *,
        threshold: int | None = None,
        buffer: int = 1,
        seed: int | None = 0,
    ):
        self.options = options or PaccetOptions()
        self._archive = ParetoArchive(threshold=threshold, buffer=buffer, seed=seed)

    @property
    def archive(self) -> ParetoArchive:
        """The persistent :class:`ParetoArchive` (objective vectors offered with ``tell``)."""
        return self._archive

    def reset(self) -> None:
        """Empty the archive (and re-seed its thinning generator)."""
        self._archive.reset()

    def tell(self, F: np.ndarray) -> None:
        """Offer the rows of ``F`` ``(n, m)`` to the archive, in order."""
        self._archive.extend(F)

    def _members(self) -> np.ndarray:
        if len(self._archive) == 0:
            raise ValueError("the PaCcET archive is empty: call tell() first")
        return self._archive.points

    def transform(self, F: np.ndarray) -> np.ndarray:
        """``(n, m)`` PaCcET coordinates of ``F`` against the current archive."""
        return paccet_transform(F, self._members(), self.options)

    def fitness(self, F: np.ndarray, scalarization: Scalarization | None = None) -> np.ndarray:
        """``(n,)`` scalarized fitness (default equal weight) of ``F``; lower is better."""
        scalarization = scalarization if scalarization is not None else EqualWeight()
        return _score(scalarization, self.transform(F))

    def order(self, F: np.ndarray, scalarization: Scalarization | None = None) -> np.ndarray:
        """``(n,)`` row indices of ``F`` best first.

        Key: (weakly dominated by a member without being one, if ``rank_weakly_dominated``),
        fitness, index.
        """
        F = validate_objectives(F)
        fit = self.fitness(F, scalarization)
        fit = np.where(np.isnan(fit), np.inf, fit)
        idx = np.arange(F.shape[0])
        if not self.options.rank_weakly_dominated:
            return np.lexsort((idx, fit))
        return np.lexsort((idx, fit, self.dominated_by_archive(F)))

    def dominated_by_archive(self, F: np.ndarray) -> np.ndarray:
        """``(n,)`` rows weakly dominated by some archive member without being equal to one."""
        F = validate_objectives(F)
        A = self._members()
        if A.shape[1] != F.shape[1]:
            raise ValueError(f"F has {F.shape[1]} objectives, the archive {A.shape[1]}")
        out = np.empty(F.shape[0], dtype=bool)
        chunk = max(1, _CHUNK_ELEMS // A.shape[0])
        for s in range(0, F.shape[0], chunk):
            rows = F[s : s + chunk]
            le = np.ones((rows.shape[0], A.shape[0]), dtype=bool)
            eq = np.ones_like(le)
            for j in range(F.shape[1]):
                le &= A[None, :, j] <= rows[:, j : j + 1]
                eq &= A[None, :, j] == rows[:, j : j + 1]
            out[s : s + chunk] = le.any(axis=1) & ~eq.any(axis=1)
        return out

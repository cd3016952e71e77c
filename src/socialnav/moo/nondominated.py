"""Non-dominated filtering under weak Pareto dominance (all objectives minimized).

Semantics match :class:`socialnav.moo.archive.ParetoArchive` (and the PaCcET reference
``Pareto_Check``): ``a`` dominates ``b`` when ``a_j <= b_j`` for every objective ``j``
(equality counts). An exact duplicate of an earlier row is therefore dominated by that earlier
row: among identical rows only the **lowest-index copy** is reported as non-dominated. As a set,
``F[nondominated_mask(F)]`` equals the non-dominated set of the unique rows of ``F``.

Algorithms: m = 1 first argmin; m = 2 lexicographic sort + running minimum, O(n log n);
m >= 3 a compiled presort-and-front filter (``socialnav.core.compiled``; with
``SOCIALNAV_KERNELS=reference`` moocore's ``is_nondominated``, Kung et al. dimension sweep, C),
with a pure-NumPy fallback (lexicographic presort + blocked filter, bounded memory) selectable
via ``method``.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from socialnav.core import compiled

__all__ = ["dominates", "nondominated_mask", "validate_objectives"]

Method = Literal["auto", "moocore", "numpy"]

# Block size of the NumPy fallback: the (|front| x block) comparison matrix stays a few MB.
_BLOCK = 256


def validate_objectives(F: object, name: str = "F", *, ncols: int | None = None) -> np.ndarray:
    """Return ``F`` as a C-contiguous float64 ``(n, m)`` array or raise ``ValueError``.

    Rejects: non-numeric data, ``ndim != 2``, ``n == 0`` or ``m == 0``, NaN or ±inf entries,
    and (when ``ncols`` is given) a column count different from ``ncols``.
    """
    try:
        arr = np.asarray(F, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a numeric (n, m) array: {exc}") from exc
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D (n, m) array, got ndim={arr.ndim}")
    n, m = arr.shape
    if n == 0 or m == 0:
        raise ValueError(f"{name} must be non-empty, got shape {arr.shape}")
    if ncols is not None and m != ncols:
        raise ValueError(f"{name} must have {ncols} objective columns, got {m}")
    if not np.isfinite(arr).all():
        bad = np.argwhere(~np.isfinite(arr))[0]
        raise ValueError(
            f"{name} must be finite; found {arr[tuple(bad)]} at row {bad[0]}, column {bad[1]}"
        )
    return np.ascontiguousarray(arr)


def dominates(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Weak dominance ``all(a <= b)`` along the last axis (broadcasting; shapes ``(..., m)``)."""
    return np.all(np.asarray(a) <= np.asarray(b), axis=-1)


def nondominated_mask(F: np.ndarray, *, method: Method = "auto") -> np.ndarray:
    """Boolean ``(n,)`` mask of the non-dominated rows of ``F`` ``(n, m)``, minimization.

    Weak dominance; among exact duplicates only the lowest-index copy is ``True``.
    ``method``: ``"auto"`` (sweep for m <= 2, moocore for m >= 3), ``"moocore"`` or
    ``"numpy"`` (pure-NumPy fallback for every m). Raises ``ValueError`` on invalid ``F``.
    """
    F = validate_objectives(F)
    if method not in ("auto", "moocore", "numpy"):
        raise ValueError(f"unknown method {method!r}")
    m = F.shape[1]
    if m == 1:
        mask = np.zeros(F.shape[0], dtype=bool)
        mask[int(np.argmin(F[:, 0]))] = True  # argmin returns the first copy
        return mask
    if method == "auto" and m >= 3 and compiled.enabled():
        return _compiled_filter(F)
    if method == "moocore" or (method == "auto" and m >= 3):
        import moocore  # local import: keeps `import socialnav.moo` light

        # keep_weakly=False reports only the first copy of duplicates, i.e. our semantics.
        return np.asarray(moocore.is_nondominated(F, keep_weakly=False), dtype=bool)
    if m == 2:
        return _sweep_2d(F)
    return _blocked_numpy(F)


@compiled.jit
def _front_kernel(F, order, keep):  # type: ignore[no-untyped-def]
    """Rows of ``F`` visited in ``order`` (ascending row sums: a weak dominator's sum is never
    larger, summed in the same order; ties in index order): a row is kept unless a kept row
    weakly dominates it, and a kept row it dominates (an equal-sum tie) is dropped again."""
    n, m = F.shape
    front = np.empty(n, dtype=np.int64)
    size = 0
    for o in range(n):
        i = order[o]
        dead = False
        for q in range(size):
            f = front[q]
            le = True
            for j in range(m):
                if F[f, j] > F[i, j]:
                    le = False
                    break
            if le:
                dead = True
                break
        keep[i] = not dead
        if dead:
            continue
        w = 0
        for q in range(size):  # drop the kept rows that row i dominates (not its equals)
            f = front[q]
            ge = True
            for j in range(m):
                if F[i, j] > F[f, j]:
                    ge = False
                    break
            if ge:
                keep[f] = False
            else:
                front[w] = f
                w += 1
        size = w
        front[size] = i
        size += 1


def _compiled_filter(F: np.ndarray) -> np.ndarray:
    """An exact filter in one compiled pass (the mask is defined by the semantics above, so
    every exact filter returns the same one)."""
    order = np.argsort(F.sum(axis=1), kind="stable")
    keep = np.empty(F.shape[0], dtype=bool)
    _front_kernel(F, order, keep)
    return keep


def warmup() -> None:
    """Compile (or load) this module's compiled kernel (``socialnav.core.compiled``)."""
    if compiled.AVAILABLE:
        _front_kernel(np.ones((2, 3)), np.arange(2), np.empty(2, dtype=bool))


def _sweep_2d(F: np.ndarray) -> np.ndarray:
    # Stable lexicographic sort by (f0, f1, index): every potential dominator of a row comes
    # before it, so a row survives iff its f1 is strictly below all earlier f1 values.
    order = np.lexsort((F[:, 1], F[:, 0]))
    f1 = F[order, 1]
    prev_min = np.empty_like(f1)
    prev_min[0] = np.inf
    np.minimum.accumulate(f1[:-1], out=prev_min[1:])
    mask = np.empty(F.shape[0], dtype=bool)
    mask[order] = f1 < prev_min
    return mask


def _blocked_numpy(F: np.ndarray) -> np.ndarray:
    """Pure-NumPy filter for any m: presort, then compare blocks against the front so far.

    After a stable lexicographic sort a row can only be weakly dominated by rows before it
    (a dominator is lexicographically <=; ties of identical rows keep index order). Each block
    is tested against the front found in earlier blocks and against earlier rows of its own
    block; dominance is transitive, so earlier dominated rows need not be kept. Memory is
    O(|front| * block), compared one objective at a time (no (n, n, m) temporaries).
    """
    n, m = F.shape
    order = np.lexsort(F.T[::-1])
    S = F[order]
    keep = np.zeros(n, dtype=bool)
    front = np.empty((0, m))
    tri = np.tril(np.ones((_BLOCK, _BLOCK), dtype=bool), k=-1)  # [i, k]: k earlier than i
    for start in range(0, n, _BLOCK):
        B = S[start : start + _BLOCK]
        b = B.shape[0]
        # within block: dom[i, k] = row k (earlier) weakly dominates row i
        dom = tri[:b, :b].copy()
        for j in range(m):
            dom &= B[None, :, j] <= B[:, None, j]
        dead = dom.any(axis=1)
        if front.shape[0]:
            acc = np.ones((b, front.shape[0]), dtype=bool)
            for j in range(m):
                acc &= front[None, :, j] <= B[:, None, j]
            dead |= acc.any(axis=1)
        keep[start : start + b] = ~dead
        front = np.concatenate((front, B[~dead]))
    mask = np.empty(n, dtype=bool)
    mask[order] = keep
    return mask

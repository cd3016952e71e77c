"""PaCcET's Pareto archive: the non-dominated raw objective vectors seen so far.

Yliniemi & Tumer, "PaCcET: An Objective Space Transformation to Shape the Pareto Front and
Eliminate Concavity" (SEAL 2014); behaviour of the author's ``Pareto_Check`` / ``rand_thresh``.

Deviations from the reference code:
- thinning draws the members to remove with a seeded ``numpy.random.Generator`` (the reference
  calls C ``rand()``); the removed set is uniformly random as in the reference;
- the reference's anchor re-insertion after thinning (``anchor_readd``) is not reproduced;
- ``extend`` is a vectorized bulk insert; it equals sequential ``pareto_check`` calls exactly
  (it falls back to them from the first point at which thinning could trigger).
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from socialnav.moo.nondominated import nondominated_mask, validate_objectives

__all__ = ["ParetoArchive"]


class ParetoArchive:
    """Set of mutually non-dominated objective vectors (minimization, weak dominance).

    Parameters
    ----------
    threshold:
        Thinning threshold; ``None`` disables thinning. When the size reaches
        ``threshold + buffer`` uniformly random members are removed until ``threshold - 1``
        remain (reference values: 250/1 in the author's header, 50/10 in the navigation code).
    buffer:
        See ``threshold`` (>= 1).
    seed:
        Seed of the generator that chooses the members removed by thinning.
    """

    def __init__(self, threshold: int | None = None, buffer: int = 1, seed: int | None = 0):
        if threshold is not None and int(threshold) < 2:
            raise ValueError(f"threshold must be >= 2 or None, got {threshold}")
        if int(buffer) < 1:
            raise ValueError(f"buffer must be >= 1, got {buffer}")
        self.threshold = None if threshold is None else int(threshold)
        self.buffer = int(buffer)
        self.seed = seed
        self._rng = np.random.default_rng(seed)
        self._points: np.ndarray | None = None  # (P, m), None until the first insertion

    # ------------------------------------------------------------------ state
    def reset(self) -> None:
        """Empty the archive and re-seed the thinning generator."""
        self._points = None
        self._rng = np.random.default_rng(self.seed)

    def __len__(self) -> int:
        return 0 if self._points is None else self._points.shape[0]

    @property
    def n_objectives(self) -> int | None:
        """m, fixed by the first insertion (``None`` while empty and never filled)."""
        return None if self._points is None else self._points.shape[1]

    @property
    def points(self) -> np.ndarray:
        """Read-only ``(P, m)`` view of the members in insertion order (``(0, 0)`` if unset)."""
        out = np.empty((0, 0)) if self._points is None else self._points.view()
        out.flags.writeable = False
        return out

    # ------------------------------------------------------------------ updates
    def pareto_check(self, f: np.ndarray) -> bool:
        """Offer one vector ``f`` ``(m,)``; return ``True`` if it entered the archive.

        Rejected (no change) if a member weakly dominates it, an exact duplicate included;
        otherwise members it weakly dominates are removed, ``f`` is appended, then thinning runs.
        """
        row = validate_objectives(np.atleast_2d(f), "f", ncols=self.n_objectives)
        if row.shape[0] != 1:
            raise ValueError(f"pareto_check takes one vector, got shape {np.shape(f)}")
        return self._check(row[0])

    def _check(self, f: np.ndarray) -> bool:
        A = self._points
        if A is None or A.shape[0] == 0:
            self._points = f[None, :].copy()
            return True
        if np.any(np.all(f >= A, axis=1)):
            return False
        survivors = ~np.all(f <= A, axis=1)
        self._points = np.concatenate((A[survivors], f[None, :]))
        self._thin()
        return True

    def extend(self, F: np.ndarray) -> None:
        """Offer every row of ``F`` ``(n, m)`` in order.

        Equals sequential :meth:`pareto_check` calls in content, member order and random
        stream. Without thinning this is one vectorized non-dominated filter of
        ``[members; F]`` (members first, so a new exact duplicate of a member is the later,
        rejected copy); from the first row at which thinning could trigger it falls back to
        sequential checks, because thinning depends on the intermediate sizes.
        """
        F = validate_objectives(F, ncols=self.n_objectives)
        n = F.shape[0]
        i = 0
        while i < n:
            # Sizes stay <= len + k while k rows are offered, so thinning cannot trigger
            # within the next `room` rows: insert those in bulk, then re-evaluate.
            room = n - i
            if self.threshold is not None:
                room = min(room, self.threshold + self.buffer - 1 - len(self))
            if room >= 8 or (room > 0 and room == n - i):
                self._bulk(F[i : i + room])
                i += room
            else:
                self._check(F[i])
                i += 1

    def _bulk(self, F: np.ndarray) -> None:
        A = self._points if self._points is not None else np.empty((0, F.shape[1]))
        combined = np.concatenate((A, F))
        self._points = combined[nondominated_mask(combined)]

    def _thin(self) -> None:
        if self.threshold is None or self._points is None:
            return
        size = self._points.shape[0]
        if size < self.threshold + self.buffer:
            return
        remove = self._rng.choice(size, size=size - (self.threshold - 1), replace=False)
        keep = np.ones(size, dtype=bool)
        keep[remove] = False
        self._points = self._points[keep]

    # ------------------------------------------------------------------ bounds
    def utopia(
        self, delta: float = 0.001, mode: Literal["absolute", "relative"] = "absolute"
    ) -> np.ndarray:
        """``(m,)`` utopia ``min_a a_j - delta_j``; relative mode: ``delta_j = delta * range_j``
        (range over the archive; absolute ``delta`` where that range is zero)."""
        A = self._require()
        lo = A.min(axis=0)
        return lo - _delta_vector(A, delta, mode)

    @property
    def nadir(self) -> np.ndarray:
        """``(m,)`` per-objective maximum over the archive."""
        return self._require().max(axis=0)

    def _require(self) -> np.ndarray:
        if self._points is None or self._points.shape[0] == 0:
            raise ValueError("the archive is empty")
        return self._points

    def __repr__(self) -> str:
        return (
            f"ParetoArchive(size={len(self)}, threshold={self.threshold}, "
            f"buffer={self.buffer}, seed={self.seed})"
        )


def _delta_vector(A: np.ndarray, delta: float, mode: str) -> np.ndarray:
    if mode == "absolute":
        return np.full(A.shape[1], float(delta))
    if mode == "relative":
        rng = A.max(axis=0) - A.min(axis=0)
        return np.where(rng > 0, delta * rng, float(delta))
    raise ValueError(f"unknown delta mode {mode!r}")

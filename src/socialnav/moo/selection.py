"""Planner-facing selection strategies: pick one candidate trajectory from its objective matrix.

The local planner scores N candidates on m objectives (``F`` (N, m), lower is better) and marks
the legal ones; a strategy returns the chosen index (``None`` when nothing is legal) and a
per-candidate fitness. ``WeightedSum`` is the traditional ROS scoring; ``PaccetSelection`` is the
PaCcET selection of Banisetty et al. ("Socially-Aware Navigation: A Non-linear Multi-Objective
Optimization Approach"), with a fresh archive built from the legal candidates every cycle.
Hot path: never raises on well-typed input (finite-or-not float matrix, boolean mask).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Protocol, runtime_checkable

import numpy as np

from socialnav.moo.paccet import PaccetOptions, paccet_select
from socialnav.moo.scalarize import EqualWeight, Scalarization

__all__ = ["PaccetSelection", "Selection", "SelectionStrategy", "WeightedSum"]


@dataclass(frozen=True)
class Selection:
    """``index`` of the chosen row (None if no candidate is legal); ``fitness`` (N,) with
    +inf for illegal rows (lower is better); ``details`` strategy-specific diagnostics."""

    index: int | None
    fitness: np.ndarray
    details: dict[str, Any] = field(default_factory=dict)


@runtime_checkable
class SelectionStrategy(Protocol):
    """Picks one candidate from an objective matrix; stateless between calls.

    ``name``: the strategy's registry-style name. ``select(F, legal)``: ``F (N, m)`` objective
    values (lower is better; any non-finite row counts as illegal), ``legal (N,)`` bool; returns
    a :class:`Selection` (``index`` None when nothing is legal). Ties go to the lowest fitness,
    then the lowest index. Raises ``ValueError`` only on ill-shaped input.
    """

    name: str

    def select(self, F: np.ndarray, legal: np.ndarray) -> Selection:
        """The chosen row of ``F (N, m)`` among ``legal (N,)`` and every row's fitness."""
        ...


def _usable(F: np.ndarray, legal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Float (N, m) matrix and the (N,) rows that are legal and finite (boundary checks)."""
    F = np.asarray(F, dtype=np.float64)
    if F.ndim != 2:
        raise ValueError(f"F must be a 2-D (N, m) array, got ndim={F.ndim}")
    legal = np.asarray(legal, dtype=bool)
    if legal.shape != (F.shape[0],):
        raise ValueError(f"legal must have shape ({F.shape[0]},), got {legal.shape}")
    # A non-finite legal row is treated as illegal rather than raising inside the control loop.
    return F, legal & np.isfinite(F).all(axis=1)


class WeightedSum:
    """Traditional scoring ``F @ w`` over legal rows; argmin with ties to the lowest index."""

    name = "weighted_sum"

    def __init__(self, weights: Sequence[float]):
        w = np.asarray(weights, dtype=np.float64)
        if w.ndim != 1 or w.size == 0 or not np.isfinite(w).all():
            raise ValueError(f"weights must be a non-empty finite 1-D sequence, got {weights}")
        self.weights = w

    def select(self, F: np.ndarray, legal: np.ndarray) -> Selection:
        """The chosen row of ``F (N, m)`` among ``legal (N,)`` (see :class:`SelectionStrategy`)."""
        F, ok = _usable(F, legal)
        if F.shape[1] != self.weights.size:
            raise ValueError(f"{self.weights.size} weights for {F.shape[1]} objectives")
        fitness = np.full(F.shape[0], np.inf)
        if not ok.any():
            return Selection(None, fitness, {"n_legal": 0})
        fitness[ok] = F[ok] @ self.weights
        # Plain argmin (first minimum): exactly the ROS planner's choice for one objective.
        return Selection(int(np.argmin(fitness)), fitness, {"n_legal": int(ok.sum())})


class PaccetSelection:
    """PaCcET selection over the legal rows (fresh archive per call).

    ``scalarization`` defaults to :class:`~socialnav.moo.scalarize.EqualWeight`, which scores
    every archive member 1 (the lowest-index member wins; ``options.indifference`` then never
    changes the choice); the planner presets use an ``L1Target``.

    ``details``: ``transformed`` (N, m) (NaN for excluded rows), ``nondominated`` (N,) bool,
    ``kept_objectives`` (m,) bool, ``n_legal``.
    """

    name = "paccet"

    def __init__(
        self,
        scalarization: Scalarization | None = None,
        options: PaccetOptions | None = None,
    ):
        self.scalarization = scalarization if scalarization is not None else EqualWeight()
        self.options = options or PaccetOptions()

    def with_indifference(self, q: Sequence[float]) -> PaccetSelection:
        """This selection with per-objective indifference thresholds ``q (m,)`` (raw units,
        ``PaccetOptions.indifference``)."""
        options = replace(self.options, indifference=tuple(float(v) for v in q))
        return PaccetSelection(self.scalarization, options)

    def select(self, F: np.ndarray, legal: np.ndarray) -> Selection:
        """The chosen row of ``F (N, m)`` among ``legal (N,)`` (see :class:`SelectionStrategy`)."""
        F, ok = _usable(F, legal)
        n, m = F.shape
        fitness = np.full(n, np.inf)
        if m == 0 or not ok.any():
            return Selection(None, fitness, {"n_legal": 0})
        rows = np.flatnonzero(ok)
        res = paccet_select(F[rows], self.scalarization, self.options)
        fitness[rows] = res.fitness
        transformed = np.full((n, m), np.nan)
        transformed[rows] = res.transformed
        nondominated = np.zeros(n, dtype=bool)
        nondominated[rows] = res.nondominated
        details = {
            "transformed": transformed,
            "nondominated": nondominated,
            "kept_objectives": res.kept_objectives,
            "n_legal": int(rows.size),
        }
        return Selection(int(rows[res.best_index]), fitness, details)

"""Scalarizations applied in PaCcET-transformed space: ``(T (n, m)) -> fitness (n,)``.

Lower fitness is better. Yliniemi & Tumer (PaCcET, SEAL 2014): the equal-weight sum is the
original PaCcET fitness; the L1 distance to a target on the simplex ``sum(y) = 1`` is the
author's later way of steering toward a chosen trade-off (concave parts of the front included).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["EqualWeight", "L1Target", "Scalarization", "Weighted"]


def _as_matrix(T: np.ndarray) -> np.ndarray:
    T = np.asarray(T, dtype=np.float64)
    if T.ndim != 2:
        raise ValueError(f"T must be a 2-D (n, m) array, got ndim={T.ndim}")
    return T


def _as_vector(v: Sequence[float] | np.ndarray, name: str) -> np.ndarray:
    arr = np.asarray(v, dtype=np.float64)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D sequence, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite, got {arr}")
    arr.flags.writeable = False
    return arr


class Scalarization:
    """Base class: callable ``(T (n, m)) -> (n,)``."""

    name: str = "scalarization"

    def __call__(self, T: np.ndarray) -> np.ndarray:  # pragma: no cover - interface
        """Fitness ``(n,)`` of PaCcET coordinates ``T (n, m)``; lower is better."""
        raise NotImplementedError


class EqualWeight(Scalarization):
    """``sum_j T_j`` (= ``1 / s*`` in closed form): every archive member scores 1."""

    name = "equal_weight"

    def __call__(self, T: np.ndarray) -> np.ndarray:
        """Fitness ``(n,)`` of PaCcET coordinates ``T (n, m)``; lower is better."""
        return _as_matrix(T).sum(axis=1)

    def __repr__(self) -> str:
        return "EqualWeight()"


class Weighted(Scalarization):
    """``w · T`` for weights ``w`` ``(m,)`` (finite; any sign, though non-negative is usual)."""

    name = "weighted"

    def __init__(self, weights: Sequence[float] | np.ndarray):
        self.weights = _as_vector(weights, "weights")

    def __call__(self, T: np.ndarray) -> np.ndarray:
        """Fitness ``(n,)`` of PaCcET coordinates ``T (n, m)``; lower is better."""
        T = _as_matrix(T)
        if T.shape[1] != self.weights.size:
            raise ValueError(f"{self.weights.size} weights for {T.shape[1]} objectives")
        return T @ self.weights

    def __repr__(self) -> str:
        return f"Weighted({self.weights.tolist()})"


class L1Target(Scalarization):
    """``sum_j |T_j - g_j|``: L1 distance to a target ``g`` ``(m,)`` (usually on the simplex)."""

    name = "l1_target"

    def __init__(self, target: Sequence[float] | np.ndarray):
        self.target = _as_vector(target, "target")

    def __call__(self, T: np.ndarray) -> np.ndarray:
        """Fitness ``(n,)`` of PaCcET coordinates ``T (n, m)``; lower is better."""
        T = _as_matrix(T)
        if T.shape[1] != self.target.size:
            raise ValueError(f"target has {self.target.size} entries for {T.shape[1]} objectives")
        return np.abs(T - self.target).sum(axis=1)

    def __repr__(self) -> str:
        return f"L1Target({self.target.tolist()})"

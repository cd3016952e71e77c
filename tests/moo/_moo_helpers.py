"""Shared reference implementations and data for the moo tests (brute force, slow, obvious)."""

from __future__ import annotations

import numpy as np


def brute_nondominated(F: np.ndarray) -> np.ndarray:
    """Row i survives iff no other row weakly dominates it (equal rows: the earlier one wins)."""
    F = np.asarray(F, dtype=float)
    n = F.shape[0]
    out = np.ones(n, dtype=bool)
    for i in range(n):
        for k in range(n):
            if k == i:
                continue
            if np.all(F[k] <= F[i]) and (np.any(F[k] < F[i]) or k < i):
                out[i] = False
                break
    return out


EXAMPLE1 = np.array([[1.0, 0.0], [0.8, 0.6], [0.6, 0.8], [0.0, 1.0], [0.9, 0.9]])

_D = np.array([0.6, 0.9, 1.2, 1.6, 2.0])
EXAMPLE2 = np.column_stack(
    [[10.0, 14.0, 18.0, 25.0, 30.0], np.where(_D <= 1.5, np.exp(1.0 / np.minimum(_D, 1.5)), 0.0)]
)

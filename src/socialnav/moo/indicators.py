"""Quality indicators for objective sets (minimization)."""

from __future__ import annotations

import numpy as np

from socialnav.moo.nondominated import validate_objectives

__all__ = ["hypervolume"]


def hypervolume(F: np.ndarray, ref: np.ndarray) -> float:
    """Hypervolume dominated by ``F`` ``(n, m)`` and bounded by the reference point ``ref`` (m,).

    Minimization; points that do not strictly dominate ``ref`` contribute nothing. Computed
    by moocore. Raises ``ValueError`` on invalid input or a reference of the wrong length.
    """
    F = validate_objectives(F)
    r = np.asarray(ref, dtype=np.float64)
    if r.shape != (F.shape[1],) or not np.isfinite(r).all():
        raise ValueError(f"ref must be a finite vector of length {F.shape[1]}, got {ref}")
    import moocore

    return float(moocore.hypervolume(F, ref=r))

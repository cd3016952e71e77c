"""The switch and decorator of the compiled (numba) kernels, shared by every layer.

``SOCIALNAV_KERNELS=reference`` selects the NumPy reference everywhere at import;
:func:`socialnav.planner.kernels.set_enabled` switches at run time (it keeps this flag in
step). Kernels compute the same IEEE operations in the same order as their reference (no
fast-math), cache their machine code (``cache=True``) and run without the GIL.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

try:  # numba is a core dependency; the guard keeps the reference path usable without it.
    import numba as _numba

    AVAILABLE = True
except ImportError:  # pragma: no cover - exercised only without numba installed
    AVAILABLE = False

_ENABLED = AVAILABLE and os.environ.get("SOCIALNAV_KERNELS", "").strip().lower() != "reference"


def enabled() -> bool:
    """Whether the compiled kernels are used."""
    return _ENABLED


def set_flag(value: bool) -> None:
    """Set the switch (use :func:`socialnav.planner.kernels.set_enabled`, which also warms
    the kernels up)."""
    global _ENABLED
    _ENABLED = bool(value) and AVAILABLE


def jit(fn: Callable[..., Any]) -> Callable[..., Any]:
    """``numba.njit(cache=True, nogil=True)`` without fast-math (the plain function without
    numba)."""
    if not AVAILABLE:
        return fn
    return _numba.njit(cache=True, nogil=True, fastmath=False, error_model="numpy")(fn)

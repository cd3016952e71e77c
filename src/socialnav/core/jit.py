"""The switch between compiled (numba) kernels and their NumPy references, shared by every
kernel module (:mod:`socialnav.planner.kernels`, :mod:`socialnav.social.perception.gcff_kernel`).

Compiled kernels are used when numba is importable and the environment variable
``SOCIALNAV_KERNELS`` is not ``reference``; a :class:`KernelSwitch` may be flipped at run time.
Kernels are compiled with ``cache=True`` (machine code beside the module or in
``NUMBA_CACHE_DIR``) and without fast-math, so they compute the IEEE operations they spell out.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

try:  # numba is a core dependency; the guard keeps the reference paths usable without it.
    import numba as _numba

    AVAILABLE = True
except ImportError:  # pragma: no cover - exercised only without numba installed
    AVAILABLE = False


def requested() -> bool:
    """Whether the environment asks for compiled kernels (and numba is there)."""
    return AVAILABLE and os.environ.get("SOCIALNAV_KERNELS", "").strip().lower() != "reference"


def njit(fn: Any) -> Any:
    """``numba.njit`` with the project's options, or ``fn`` itself without numba."""
    if not AVAILABLE:
        return fn
    return _numba.njit(cache=True, nogil=True, fastmath=False, error_model="numpy")(fn)


class KernelSwitch:
    """On/off state of one kernel module; ``warmup`` compiles its kernels when switched on."""

    def __init__(self, warmup: Callable[[], object]) -> None:
        self.on = requested()
        self._warmup = warmup

    def set(self, value: bool, what: str) -> bool:
        """Switch to compiled (``True``) or reference; returns the previous setting. Raises
        ``RuntimeError`` asking for numba when it is unavailable."""
        if value and not AVAILABLE:
            raise RuntimeError(f"{what} need numba (pip install numba)")
        previous, self.on = self.on, bool(value)
        if value:
            self._warmup()
        return previous

"""The compiled kernels of ``socialnav.moo`` against their reference, on random data: the
non-dominated mask (against moocore) and PaCcET's ``s*`` / full selection, bit for bit."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core import compiled
from socialnav.moo import paccet
from socialnav.moo.nondominated import nondominated_mask

pytest.importorskip("numba")


@contextmanager
def flag(value: bool) -> Iterator[None]:
    previous = compiled.enabled()
    compiled.set_flag(value)
    try:
        yield
    finally:
        compiled.set_flag(previous)


@settings(max_examples=80, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(1, 400),
    m=st.integers(3, 6),
    levels=st.sampled_from([1, 2, 5, 0]),
    scale=st.sampled_from([1.0, 1e-17, 3.0]),
)
def test_nondominated_mask_is_moocores(seed, n, m, levels, scale):
    """Duplicates, ties in every column and in the row sums (tiny scales), continuous data."""
    rng = np.random.default_rng(seed)
    F = rng.random((n, m)) if levels == 0 else rng.integers(0, levels + 1, (n, m)) * 1.0
    F = F * scale
    with flag(True):
        fast = nondominated_mask(F)
    assert np.array_equal(fast, nondominated_mask(F, method="moocore"))


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(1, 300),
    p=st.integers(1, 60),
    k=st.integers(1, 5),
    specials=st.booleans(),
)
def test_s_star_identical(seed, n, p, k, specials):
    """``min_p max_j inv S`` with inf (x <= 0), zeros in the archive (inf x 0 = NaN), NaN."""
    rng = np.random.default_rng(seed)
    inv = rng.uniform(0.2, 5.0, (n, k))
    S = rng.uniform(0.05, 1.0, (p, k))
    if specials:
        inv[rng.random(inv.shape) < 0.1] = np.inf
        S[rng.random(S.shape) < 0.1] = 0.0
        inv[rng.random(inv.shape) < 0.02] = np.nan
    with flag(False), np.errstate(invalid="ignore"):
        ref = paccet._s_star_dense(inv, S)
    with flag(True):
        fast = paccet._s_star_dense(inv, S)
    assert np.array_equal(fast, ref, equal_nan=True)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 500), m=st.integers(2, 6))
def test_paccet_selection_identical(seed, n, m):
    rng = np.random.default_rng(seed)
    F = rng.random((n, m)) * rng.uniform(0.1, 100.0, m)
    F[rng.random(n) < 0.2] = F[0]  # duplicates of one row
    with flag(False):
        ref = paccet.paccet_select(F)
    with flag(True):
        fast = paccet.paccet_select(F)
    assert fast.best_index == ref.best_index
    assert np.array_equal(fast.fitness, ref.fitness)
    assert np.array_equal(fast.transformed, ref.transformed)
    assert np.array_equal(fast.nondominated, ref.nondominated)

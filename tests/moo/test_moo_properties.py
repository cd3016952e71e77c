"""Hypothesis properties of the PaCcET selection (remedies on unless stated)."""

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from socialnav.moo import (
    EqualWeight,
    L1Target,
    PaccetOptions,
    Weighted,
    paccet_select,
)
from socialnav.moo.nondominated import dominates


def matrices(max_m: int = 5, max_n: int = 30, lo: int = 0, hi: int = 6):
    # Small integers: many ties, duplicates and weakly dominated rows.
    return st.integers(2, max_m).flatmap(
        lambda m: arrays(
            np.float64,
            st.tuples(st.integers(1, max_n), st.just(m)),
            elements=st.integers(lo, hi).map(float),
        )
    )


@st.composite
def problem(draw, **kw):
    F = draw(matrices(**kw))
    m = F.shape[1]
    kind = draw(st.sampled_from(["equal", "weighted", "l1"]))
    if kind == "equal":
        scal = EqualWeight()
    elif kind == "weighted":
        scal = Weighted(draw(st.lists(st.integers(0, 4).map(float), min_size=m, max_size=m)))
    else:
        g = np.array(draw(st.lists(st.integers(1, 5).map(float), min_size=m, max_size=m)))
        scal = L1Target(g / g.sum())
    return F, scal


@settings(max_examples=200, deadline=None)
@given(pb=problem(), parity=st.booleans())
def test_dominated_candidate_never_beats_its_dominator(pb, parity):
    F, scal = pb
    opts = PaccetOptions(method="parity" if parity else "closed_form")
    res = paccet_select(F, scal, opts)
    # the selected row is not dominated by any other row (nor a later copy of a duplicate)
    b = res.best_index
    others = np.delete(np.arange(F.shape[0]), b)
    dom = dominates(F[others], F[b])
    strict = dom & np.any(F[others] < F[b], axis=1)
    earlier_copy = dom & (others < b)
    assert not np.any(strict | earlier_copy)
    # in the full ranking every dominated row comes after every non-dominated row, and
    # after each row that strictly dominates it when that row is non-dominated
    order = res.order()
    pos = np.empty_like(order)
    pos[order] = np.arange(order.size)
    nd = res.nondominated
    assert pos[nd].max(initial=-1) < pos[~nd].min(initial=order.size)
    if isinstance(scal, EqualWeight) and not parity:
        # equal weight (= 1/s*) is monotone in dominance for every pair
        for a in range(F.shape[0]):
            mask = dominates(F[a], F)
            assert np.all(res.fitness[mask] >= res.fitness[a] * (1 - 1e-12))


@settings(max_examples=150, deadline=None)
@given(pb=problem(), seed=st.integers(0, 2**31), parity=st.booleans())
def test_permuting_candidates_permutes_results(pb, seed, parity):
    F, scal = pb
    opts = PaccetOptions(method="parity" if parity else "closed_form")
    perm = np.random.default_rng(seed).permutation(F.shape[0])
    a = paccet_select(F, scal, opts)
    b = paccet_select(F[perm], scal, opts)
    np.testing.assert_allclose(b.transformed, a.transformed[perm], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(b.fitness, a.fitness[perm], rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(b.kept_objectives, a.kept_objectives)
    # the same set of distinct non-dominated vectors
    assert {tuple(r) for r in F[perm][b.nondominated]} == {tuple(r) for r in F[a.nondominated]}
    # the chosen candidate is the same vector unless fitness ties make another equally good
    assert abs(b.fitness[b.best_index] - a.fitness[a.best_index]) <= 1e-9
    if np.sum(np.abs(a.fitness - a.fitness[a.best_index]) <= 1e-9) == 1:
        np.testing.assert_array_equal(F[perm][b.best_index], F[a.best_index])


@settings(max_examples=200, deadline=None)
@given(
    pb=problem(lo=-8, hi=8),
    column=st.integers(0, 4),
    log2_scale=st.integers(-4, 4),
    shift=st.integers(-20, 20),
    parity=st.booleans(),
)
def test_relative_delta_selection_invariant_under_affine_rescaling(
    pb, column, log2_scale, shift, parity
):
    # Power-of-two scales and integer shifts are exact in floating point, so the invariance
    # must hold bit for bit (no tolerance games with near-ties).
    F, scal = pb
    assume(column < F.shape[1])
    opts = PaccetOptions(sentinel=None, method="parity" if parity else "closed_form")
    G = F.copy()
    G[:, column] = G[:, column] * 2.0**log2_scale + shift
    a = paccet_select(F, scal, opts)
    b = paccet_select(G, scal, opts)
    assert a.best_index == b.best_index
    np.testing.assert_array_equal(a.transformed, b.transformed)


@settings(max_examples=100, deadline=None)
@given(
    F=arrays(
        np.float64,
        st.tuples(st.integers(2, 30), st.integers(2, 5)),
        # a 0.01 grid: distinct values stay distinct after rounding in the affine map
        elements=st.integers(0, 10_000).map(lambda v: v / 100.0),
    ),
    scale=st.floats(1e-3, 1e3),
    shift=st.floats(-1e3, 1e3),
)
def test_relative_delta_transform_invariant_for_general_affine_maps(F, scale, shift):
    opts = PaccetOptions(sentinel=None)
    G = F * scale + shift
    a = paccet_select(F, options=opts)
    b = paccet_select(G, options=opts)
    assume(np.array_equal(a.nondominated, b.nondominated))  # rounding may merge near-equal rows
    assume(np.array_equal(a.kept_objectives, b.kept_objectives))
    np.testing.assert_allclose(a.transformed, b.transformed, rtol=1e-6, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(pb=problem())
def test_reference_options_never_raise_and_stay_finite(pb):
    F, scal = pb
    res = paccet_select(F, scal, PaccetOptions.reference())
    assert np.all(np.isfinite(res.transformed)) and np.all(np.isfinite(res.fitness))
    assert 0 <= res.best_index < F.shape[0]

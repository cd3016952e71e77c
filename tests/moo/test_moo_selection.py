import numpy as np
import pytest
from _moo_helpers import EXAMPLE1
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from socialnav.moo import (
    L1Target,
    PaccetOptions,
    PaccetSelection,
    Selection,
    SelectionStrategy,
    WeightedSum,
    hypervolume,
    paccet_select,
)


def test_strategies_satisfy_protocol():
    assert isinstance(WeightedSum([1.0]), SelectionStrategy)
    assert isinstance(PaccetSelection(), SelectionStrategy)
    assert WeightedSum([1.0]).name == "weighted_sum" and PaccetSelection().name == "paccet"


@settings(max_examples=100, deadline=None)
@given(
    F=arrays(
        np.float64,
        st.tuples(st.integers(1, 50), st.just(1)),
        elements=st.integers(0, 5).map(float),
    ),
    legal_bits=st.lists(st.booleans(), min_size=50, max_size=50),
)
def test_single_objective_weighted_sum_is_exact_argmin(F, legal_bits):
    legal = np.array(legal_bits[: F.shape[0]])
    sel = WeightedSum([1.0]).select(F, legal)
    if not legal.any():
        assert sel.index is None
        return
    masked = np.where(legal, F[:, 0], np.inf)
    assert sel.index == int(np.argmin(masked))  # ROS parity: first minimum among legal rows
    assert np.all(np.isinf(sel.fitness[~legal]))


def test_illegal_rows_are_excluded_before_the_archive():
    # Row 3 would dominate everything, but it is illegal.
    F = np.vstack([EXAMPLE1, [[-5.0, -5.0]]])
    legal = np.array([True, True, True, True, True, False])
    sel = PaccetSelection(L1Target([0.45, 0.55])).select(F, legal)
    assert sel.index == 2
    assert np.isinf(sel.fitness[5])
    np.testing.assert_allclose(
        sel.fitness[:5], paccet_select(EXAMPLE1, L1Target([0.45, 0.55])).fitness
    )
    assert sel.details["n_legal"] == 5 and not sel.details["nondominated"][5]
    assert np.isnan(sel.details["transformed"][5]).all()


def test_indices_map_back_to_full_matrix():
    F = np.vstack([[[9.0, 9.0]], EXAMPLE1])
    legal = np.array([False, True, True, True, True, True])
    assert PaccetSelection(L1Target([0.45, 0.55])).select(F, legal).index == 3


@pytest.mark.parametrize("strategy", [WeightedSum([1.0, 1.0]), PaccetSelection()])
def test_all_illegal_or_non_finite_gives_none(strategy):
    F = np.array([[1.0, 2.0], [np.nan, 1.0], [np.inf, 0.0]])
    sel = strategy.select(F, np.array([False, True, True]))
    assert isinstance(sel, Selection) and sel.index is None
    assert np.all(np.isinf(sel.fitness))
    sel = strategy.select(F, np.array([True, True, True]))  # non-finite legal rows: illegal
    assert sel.index == 0 and np.isinf(sel.fitness[1:]).all()
    empty = strategy.select(np.zeros((0, 2)), np.zeros(0, dtype=bool))
    assert empty.index is None and empty.fitness.shape == (0,)


def test_selection_boundary_checks():
    with pytest.raises(ValueError):
        PaccetSelection().select(np.ones(3), np.ones(3, dtype=bool))
    with pytest.raises(ValueError):
        PaccetSelection().select(np.ones((3, 2)), np.ones(2, dtype=bool))
    with pytest.raises(ValueError):
        WeightedSum([1.0]).select(np.ones((3, 2)), np.ones(3, dtype=bool))
    for bad in ([], [np.nan], [[1.0]]):
        with pytest.raises(ValueError):
            WeightedSum(bad)


def test_paccet_selection_options_pass_through():
    F = np.array([[3.0, 4.0]] * 2)
    sel = PaccetSelection(options=PaccetOptions.reference()).select(F, np.ones(2, dtype=bool))
    assert sel.index == 0


def test_hypervolume_analytic_and_checks():
    F = np.array([[0.0, 1.0], [1.0, 0.0], [0.5, 0.5]])
    assert hypervolume(F, [2.0, 2.0]) == pytest.approx(4.0 - (1.0 - 0.25))
    assert hypervolume(np.array([[1.0, 1.0, 1.0]]), [2.0, 3.0, 4.0]) == pytest.approx(6.0)
    assert hypervolume(np.array([[5.0, 5.0]]), [2.0, 2.0]) == 0.0
    with pytest.raises(ValueError):
        hypervolume(F, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError):
        hypervolume(F, [np.nan, 1.0])

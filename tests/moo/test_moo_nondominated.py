import numpy as np
import pytest
from _moo_helpers import brute_nondominated
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from socialnav.moo.nondominated import dominates, nondominated_mask, validate_objectives

METHODS = ["auto", "moocore", "numpy"]


def small_int_matrices(max_m: int = 6, max_n: int = 40):
    # Small integer ranges produce many ties and exact duplicates: the hard cases.
    return st.integers(1, max_m).flatmap(
        lambda m: arrays(
            np.float64,
            st.tuples(st.integers(1, max_n), st.just(m)),
            elements=st.integers(-3, 3).map(float),
        )
    )


@pytest.mark.parametrize("method", METHODS)
@settings(max_examples=150, deadline=None)
@given(F=small_int_matrices())
def test_matches_brute_force(method, F):
    np.testing.assert_array_equal(nondominated_mask(F, method=method), brute_nondominated(F))


@pytest.mark.parametrize("method", METHODS)
@settings(max_examples=40, deadline=None)
@given(
    F=st.integers(1, 6).flatmap(
        lambda m: arrays(
            np.float64,
            st.tuples(st.integers(1, 60), st.just(m)),
            elements=st.floats(-1e6, 1e6, allow_nan=False, allow_subnormal=False),
        )
    )
)
def test_matches_brute_force_continuous(method, F):
    np.testing.assert_array_equal(nondominated_mask(F, method=method), brute_nondominated(F))


@pytest.mark.parametrize("m", [2, 3, 4, 6])
def test_numpy_fallback_agrees_with_moocore_on_large_sets(m):
    rng = np.random.default_rng(m)
    # Concave-front-like data with duplicates, larger than one block of the fallback.
    F = rng.random((1500, m))
    F /= np.linalg.norm(F, axis=1, keepdims=True)
    F = np.round(F * 20) / 20
    F = np.concatenate([F, F[:100]])
    np.testing.assert_array_equal(
        nondominated_mask(F, method="numpy"), nondominated_mask(F, method="moocore")
    )


def test_duplicates_keep_lowest_index_copy():
    F = np.array([[1.0, 1.0], [0.0, 2.0], [1.0, 1.0], [0.0, 2.0], [2.0, 0.0]])
    for method in METHODS:
        np.testing.assert_array_equal(
            nondominated_mask(F, method=method), [True, True, False, False, True]
        )


def test_single_objective_is_first_argmin():
    F = np.array([[3.0], [1.0], [2.0], [1.0]])
    np.testing.assert_array_equal(nondominated_mask(F), [False, True, False, False])


def test_weakly_dominated_is_removed():
    F = np.array([[25.0, 0.0], [30.0, 0.0], [10.0, 5.0]])
    np.testing.assert_array_equal(nondominated_mask(F), [True, False, True])


def test_dominates_is_weak_and_broadcasts():
    assert dominates(np.array([1.0, 2.0]), np.array([1.0, 2.0]))
    assert dominates(np.array([1.0, 2.0]), np.array([1.0, 3.0]))
    assert not dominates(np.array([1.0, 4.0]), np.array([2.0, 3.0]))
    np.testing.assert_array_equal(
        dominates(np.zeros((3, 2)), np.array([[0.0, 0.0], [-1.0, 0.0], [1.0, 1.0]])),
        [True, False, True],
    )


@pytest.mark.parametrize(
    "bad",
    [
        np.array([[1.0, np.nan]]),
        np.array([[1.0, np.inf]]),
        np.array([[-np.inf, 0.0]]),
        np.zeros((0, 2)),
        np.zeros((3, 0)),
        np.zeros(3),
        np.zeros((2, 2, 2)),
        [["a", "b"]],
    ],
)
def test_bad_input_raises(bad):
    with pytest.raises(ValueError):
        nondominated_mask(bad)
    with pytest.raises(ValueError):
        validate_objectives(bad)


def test_unknown_method_and_wrong_columns_raise():
    with pytest.raises(ValueError, match="method"):
        nondominated_mask(np.zeros((2, 2)), method="tree")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="3 objective columns"):
        validate_objectives(np.zeros((2, 2)), ncols=3)


def test_validate_returns_float_contiguous_copy_of_ints():
    out = validate_objectives([[1, 2], [3, 4]])
    assert out.dtype == np.float64 and out.flags.c_contiguous

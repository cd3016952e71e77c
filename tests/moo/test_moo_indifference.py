"""Indifference thresholds in PaCcET selection (``PaccetOptions.indifference``)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_moo_properties import matrices

from socialnav.moo import L1Target, PaccetOptions, paccet_select
from socialnav.moo.nondominated import nondominated_mask
from socialnav.moo.selection import PaccetSelection

# Generated crowdnav dev seed 34, Pioneer, beside a person standing 1.08 m away: two archive
# members, (navigation, ID). The second turns toward the goal (0.155 better in navigation);
# the first is 1e-6 lower in ID. Normalized by the archive's ID range (1e-6) they were
# extremes of the front and the L1 target (0.7, 0.3) took the first, every cycle.
BESIDE_A_PERSON = np.array(
    [
        [6.92910935, 2.53177214],
        [7.30000000, 2.60000000],  # a dominated row: never chosen
        [6.77405806, 2.53177316],
    ]
)
TARGET = L1Target(np.array([0.7, 0.3]))


def test_a_difference_within_the_threshold_no_longer_outweighs_a_large_one():
    assert paccet_select(BESIDE_A_PERSON, TARGET).best_index == 0  # the bug, without
    options = PaccetOptions(indifference=(0.0, 0.01))
    ranking = paccet_select(BESIDE_A_PERSON, TARGET, options)
    assert ranking.best_index == 2
    assert ranking.nondominated.tolist() == [True, False, True]  # the archive is unchanged


def test_a_difference_beyond_the_threshold_still_counts():
    F = BESIDE_A_PERSON.copy()
    F[0, 1] -= 0.05  # now 0.05 lower in ID: a real trade-off
    options = PaccetOptions(indifference=(0.0, 0.01))
    ranking = paccet_select(F, TARGET, options)
    assert ranking.nondominated.tolist() == [True, False, True]
    assert ranking.best_index == paccet_select(F, TARGET).best_index


def test_a_range_within_the_threshold_does_not_decide_between_three_objectives():
    # The third objective differs by 1e-6 only; the first two trade off 0.1 against 0.1.
    F = np.array([[0.0, 1.0, 5.000001], [1.0, 0.0, 5.0], [0.4, 0.6, 5.0000005]])
    target = L1Target(np.array([0.5, 0.25, 0.25]))
    off = paccet_select(F, target)
    on = paccet_select(F, target, PaccetOptions(indifference=(0.0, 0.0, 0.01)))
    # With the threshold the third column is near 0 for every row: the choice is the first
    # two objectives' (row 2 is nearest their 2:1 share), not the 1e-6 of the third.
    assert on.best_index == 2
    assert np.ptp(on.transformed[:, 2]) < 1e-3 < np.ptp(off.transformed[:, 2])


def test_zero_thresholds_select_as_without():
    rng = np.random.default_rng(3)
    for _ in range(50):
        F = rng.integers(0, 6, size=(12, 3)).astype(float)
        a = paccet_select(F, options=PaccetOptions())
        b = paccet_select(F, options=PaccetOptions(indifference=(0.0, 0.0, 0.0)))
        assert a.best_index == b.best_index
        np.testing.assert_array_equal(a.nondominated, b.nondominated)


def test_thresholds_are_validated():
    with pytest.raises(ValueError, match="indifference"):
        PaccetOptions(indifference=(0.0, -1.0))
    with pytest.raises(ValueError, match="indifference"):
        PaccetOptions(indifference=(float("nan"),))
    with pytest.raises(ValueError, match="2 thresholds for 3 objectives"):
        paccet_select(
            np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 2.0]]),
            options=PaccetOptions(indifference=(0.0, 0.1)),
        )


def test_paccet_selection_with_indifference_keeps_its_scalarization():
    sel = PaccetSelection(TARGET, PaccetOptions())
    q = sel.with_indifference([0.0, 0.01])
    assert q.scalarization is TARGET and q.options.indifference == (0.0, 0.01)
    legal = np.ones(3, dtype=bool)
    assert sel.select(BESIDE_A_PERSON, legal).index == 0
    assert q.select(BESIDE_A_PERSON, legal).index == 2


@settings(max_examples=200, deadline=None)
@given(
    F=matrices(max_m=4, max_n=25, hi=8),
    q=st.floats(0.0, 3.0),
)
def test_thresholds_matter_only_where_an_archive_range_is_below_them(F, q):
    qs = (q,) * F.shape[1]
    with_q = paccet_select(F, options=PaccetOptions(indifference=qs))
    without = paccet_select(F, options=PaccetOptions())
    np.testing.assert_array_equal(with_q.nondominated, without.nondominated)
    assert with_q.nondominated[with_q.best_index]
    assert np.isfinite(with_q.fitness).all()
    A = F[nondominated_mask(F)]
    ranges = A.max(axis=0) - A.min(axis=0)
    if ((ranges == 0) | (ranges >= q)).all():  # no range is floored: the same selection
        np.testing.assert_allclose(with_q.transformed, without.transformed)
        assert with_q.best_index == without.best_index


def test_thresholds_are_stored_as_a_hashable_tuple_and_a_scalar_is_refused():
    options = PaccetOptions(indifference=np.array([0.0, 0.01]))
    assert options.indifference == (0.0, 0.01)
    hash(options)
    with pytest.raises(ValueError, match="sequence of thresholds"):
        PaccetOptions(indifference=0.01)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="sequence of thresholds"):
        PaccetOptions(indifference="ab")  # type: ignore[arg-type]

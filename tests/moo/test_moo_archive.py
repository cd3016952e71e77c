import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from socialnav.moo.archive import ParetoArchive
from socialnav.moo.nondominated import nondominated_mask


def int_matrices(max_m: int = 5, max_n: int = 40):
    return st.integers(1, max_m).flatmap(
        lambda m: arrays(
            np.float64,
            st.tuples(st.integers(1, max_n), st.just(m)),
            elements=st.integers(0, 4).map(float),
        )
    )


def test_pareto_check_rules():
    a = ParetoArchive()
    assert a.pareto_check([1.0, 1.0])
    assert not a.pareto_check([1.0, 1.0])  # exact duplicate rejected
    assert not a.pareto_check([2.0, 1.0])  # weakly dominated rejected
    assert a.pareto_check([0.0, 3.0])
    assert a.pareto_check([0.5, 0.5])  # removes (1, 1)
    np.testing.assert_array_equal(a.points, [[0.0, 3.0], [0.5, 0.5]])
    assert a.pareto_check([0.0, 0.0])  # dominates everything
    np.testing.assert_array_equal(a.points, [[0.0, 0.0]])
    assert len(a) == 1


def test_bounds_and_reset():
    a = ParetoArchive()
    a.extend(np.array([[1.0, 0.0], [0.0, 1.0], [0.5, 0.5]]))
    np.testing.assert_allclose(a.utopia(0.001), [-0.001, -0.001])
    np.testing.assert_allclose(a.utopia(0.01, "relative"), [-0.01, -0.01])
    np.testing.assert_array_equal(a.nadir, [1.0, 1.0])
    a.reset()
    assert len(a) == 0 and a.n_objectives is None
    with pytest.raises(ValueError, match="empty"):
        _ = a.nadir


def test_points_view_is_read_only():
    a = ParetoArchive()
    a.extend(np.eye(2))
    with pytest.raises(ValueError):
        a.points[0, 0] = 5.0


@settings(max_examples=150, deadline=None)
@given(F=int_matrices(), split=st.integers(0, 40))
def test_extend_equals_sequential_equals_nondominated_set(F, split):
    seq = ParetoArchive()
    for f in F:
        seq.pareto_check(f)
    bulk = ParetoArchive()
    if split:  # two bulk calls: an existing archive plus new rows
        bulk.extend(F[:split])
    if split < F.shape[0]:
        bulk.extend(F[split:])
    np.testing.assert_array_equal(bulk.points, seq.points)  # same content and order
    expected = F[nondominated_mask(F)]
    assert {tuple(r) for r in seq.points} == {tuple(r) for r in expected}
    assert len(seq) == len(np.unique(expected, axis=0))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), threshold=st.integers(2, 8), buffer=st.integers(1, 4))
def test_extend_equals_sequential_with_thinning(seed, threshold, buffer):
    # Points on an anti-diagonal are mutually non-dominated: thinning must trigger.
    rng = np.random.default_rng(seed)
    t = rng.permutation(40).astype(float)
    F = np.column_stack([t, 39.0 - t])
    seq = ParetoArchive(threshold, buffer, seed=seed)
    for f in F:
        seq.pareto_check(f)
    bulk = ParetoArchive(threshold, buffer, seed=seed)
    bulk.extend(F)
    np.testing.assert_array_equal(bulk.points, seq.points)
    assert len(seq) < threshold + buffer


def test_thinning_sizes_and_reproducibility():
    t = np.arange(30.0)
    F = np.column_stack([t, 29.0 - t])
    a = ParetoArchive(threshold=10, buffer=1, seed=3)
    sizes = []
    for f in F:
        a.pareto_check(f)
        sizes.append(len(a))
    assert max(sizes) == 10  # reaches threshold + buffer - 1, never threshold + buffer
    assert sizes[10] == 9  # the 11th insert triggers thinning down to threshold - 1
    b = ParetoArchive(threshold=10, buffer=1, seed=3)
    b.extend(F)
    np.testing.assert_array_equal(a.points, b.points)
    c = ParetoArchive(threshold=10, buffer=1, seed=4)
    c.extend(F)
    assert not np.array_equal(np.sort(c.points, axis=0), np.sort(a.points, axis=0))
    a.reset()  # reset re-seeds: the same stream again
    a.extend(F)
    np.testing.assert_array_equal(a.points, b.points)


def test_navigation_code_thinning_values():
    t = np.arange(100.0)
    a = ParetoArchive(threshold=50, buffer=10, seed=0)
    a.extend(np.column_stack([t, 99.0 - t]))
    assert 49 <= len(a) < 60


@pytest.mark.parametrize(
    "kwargs", [{"threshold": 1}, {"threshold": 0}, {"buffer": 0}, {"threshold": 5, "buffer": -1}]
)
def test_bad_configuration_raises(kwargs):
    with pytest.raises(ValueError):
        ParetoArchive(**kwargs)


def test_bad_vectors_raise():
    a = ParetoArchive()
    a.pareto_check([1.0, 2.0])
    with pytest.raises(ValueError, match="2 objective columns"):
        a.pareto_check([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="finite"):
        a.pareto_check([np.nan, 1.0])
    with pytest.raises(ValueError, match="one vector"):
        a.pareto_check(np.zeros((2, 2)))
    with pytest.raises(ValueError):
        a.extend(np.zeros((0, 2)))
    with pytest.raises(ValueError, match="delta mode"):
        a.utopia(0.1, "log")  # type: ignore[arg-type]

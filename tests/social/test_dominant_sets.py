"""F-formations as dominant sets: the replicator dynamics and cohesion on analytic matrices,
groups recovered on analytic layouts (alone and in the estimator's pipeline), robustness to a
wrong heading, permutation equivariance, and bad input."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.scene import Person
from socialnav.social.perception import (
    DETECTORS,
    ContextEstimator,
    EstimatorParams,
    MapKnowledge,
    TrackFrame,
)
from socialnav.social.perception.dominant_sets import (
    DominantSetsDetector,
    DominantSetsParams,
    affinity,
    cohesion,
    dominant_sets,
    peel,
    replicator,
)


def circle(center, radius, k, phase=0.0):
    """Positions ``(k, 2)`` on a circle and headings facing its centre."""
    a = phase + 2 * np.pi * np.arange(k) / k
    pos = np.asarray(center) + radius * np.column_stack([np.cos(a), np.sin(a)])
    return pos, a + np.pi


def two_triples_and_a_singleton():
    p1, y1 = circle((0.0, 0.0), 0.7, 3)
    p2, y2 = circle((6.0, 0.0), 0.7, 3, phase=0.4)
    pos = np.vstack([p1, p2, [[3.0, 4.0]]])
    return pos, np.concatenate([y1, y2, [0.3]])


def test_replicator_finds_the_clique_and_cohesion_is_its_affinity():
    # a 3-clique of affinity 0.9, a fourth vertex linked to it by 0.2
    a = np.full((4, 4), 0.9)
    a[3, :] = a[:, 3] = 0.2
    np.fill_diagonal(a, 0.0)
    x = replicator(a)
    assert np.flatnonzero(x > 1e-4).tolist() == [0, 1, 2]
    np.testing.assert_allclose(x[:3], 1 / 3, atol=1e-6)
    assert cohesion(a[:3, :3], x[:3] / x[:3].sum()) == pytest.approx(0.9)


@pytest.mark.parametrize("k", [2, 3, 5, 8])
def test_cohesion_of_equal_affinities_is_that_affinity_whatever_the_size(k):
    a = np.full((k, k), 0.6)
    np.fill_diagonal(a, 0.0)
    assert cohesion(a, np.full(k, 1 / k)) == pytest.approx(0.6)


def test_peel_extracts_disjoint_sets_best_first_and_stops_below_min_cohesion():
    a = np.zeros((7, 7))
    a[np.ix_([0, 1, 2], [0, 1, 2])] = 0.9
    a[np.ix_([3, 4], [3, 4])] = 0.5
    a[5, 6] = a[6, 5] = 0.1  # a weak pair: below min_cohesion 0.3
    np.fill_diagonal(a, 0.0)
    sets = peel(a, DominantSetsParams(min_cohesion=0.3))
    assert [g.tolist() for g, _ in sets] == [[0, 1, 2], [3, 4]]
    assert [c for _, c in sets] == pytest.approx([0.9, 0.5])


def test_two_groups_of_three_and_a_singleton_are_recovered():
    pos, yaw = two_triples_and_a_singleton()
    found = dominant_sets(pos, yaw, DominantSetsParams())
    assert [g.tolist() for g, _ in found] == [[0, 1, 2], [3, 4, 5]]
    assert all(0.0 < c <= 1.0 for _, c in found)


def test_in_the_estimator_pipeline_in_place_of_gcff():
    pos, yaw = two_triples_and_a_singleton()
    rows = enumerate(zip(pos, yaw, strict=True))
    people = [Person(10 + i, tuple(p), yaw=float(y)) for i, (p, y) in rows]
    params = EstimatorParams(pipeline=("dominant_sets",))
    est = ContextEstimator(params=params).update(0.0, people)
    groups = sorted(tuple(sorted(c.members)) for c in est.candidates if c.kind == "fformation")
    assert groups == [(10, 11, 12), (13, 14, 15)]
    cand = next(c for c in est.candidates if c.members == (10, 11, 12))
    np.testing.assert_allclose(cand.geometry["ospace_center"], [0.0, 0.0], atol=1e-9)
    assert cand.geometry["ospace_radius"] == pytest.approx(0.7)


def test_detector_skips_walkers_and_claimed_people():
    pos, yaw = two_triples_and_a_singleton()
    vel = np.zeros_like(pos)
    vel[3:6] = (1.2, 0.0)  # the second triple walks
    frame = TrackFrame(np.arange(7), pos, vel, yaw)
    det = DETECTORS.get("dominant_sets")()
    assert [c.members for c in det(frame, MapKnowledge(), frozenset())] == [(0, 1, 2)]
    assert det(frame, MapKnowledge(), frozenset({0, 1, 2})) == []


def test_a_member_facing_away_stays_in_unless_headings_are_fully_trusted():
    pos, yaw = circle((0.0, 0.0), 0.7, 3)
    yaw = yaw.copy()
    yaw[2] += np.pi  # a head-pose classifier's wrong class: member 2 faces outward
    base = DominantSetsParams(sigma_distance=1.0, stride=0.6, sigma_vote=0.3, min_cohesion=0.2)
    soft = dominant_sets(pos, yaw, replace(base, reliability=0.5))
    assert [g.tolist() for g, _ in soft] == [[0, 1, 2]]
    trusted = dominant_sets(pos, yaw, replace(base, reliability=1.0))
    assert [g.tolist() for g, _ in trusted] == [[0, 1]]


@given(
    st.integers(0, 2**31 - 1),
    st.integers(2, 12),
    st.floats(0.0, 1.0),
)
def test_permuting_people_permutes_the_groups(seed, k, reliability):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(0.0, 4.0, (k, 2))
    yaw = rng.uniform(-np.pi, np.pi, k)
    params = DominantSetsParams(reliability=reliability)
    perm = rng.permutation(k)
    before = {frozenset(g.tolist()) for g, _ in dominant_sets(pos, yaw, params)}
    after = {frozenset(perm[g].tolist()) for g, _ in dominant_sets(pos[perm], yaw[perm], params)}
    assert before == after


def test_affinity_is_symmetric_in_unit_range_with_zero_diagonal():
    rng = np.random.default_rng(3)
    a = affinity(rng.uniform(0, 5, (9, 2)), rng.uniform(-3, 3, 9), DominantSetsParams())
    assert np.allclose(a, a.T) and np.all(np.diag(a) == 0)
    assert a.min() >= 0.0 and a.max() <= 1.0


@pytest.mark.parametrize(
    ("matrix", "message"),
    [
        (np.zeros((2, 3)), "square"),
        (np.array([[0.0, np.nan], [np.nan, 0.0]]), "NaN"),
        (np.array([[0.0, -0.1], [-0.1, 0.0]]), "non-negative"),
        (np.array([[0.0, 0.5], [0.2, 0.0]]), "symmetric"),
    ],
)
def test_bad_affinity_is_rejected(matrix, message):
    with pytest.raises(InvalidInputError, match=message):
        peel(matrix, DominantSetsParams())


def test_bad_tracks_are_rejected():
    with pytest.raises(InvalidInputError, match="NaN"):
        affinity(np.array([[0.0, np.nan], [1.0, 0.0]]), np.zeros(2), DominantSetsParams())
    with pytest.raises(InvalidInputError, match=r"\(K, 2\)"):
        affinity(np.zeros((3, 2)), np.zeros(2), DominantSetsParams())


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("sigma_distance", 0.0),
        ("reliability", 1.5),
        ("min_cohesion", -0.1),
        ("sigma_vote", float("nan")),
        ("support", 0.5),
        ("iterations", 0),
    ],
)
def test_bad_parameters_name_the_field(field, value):
    with pytest.raises(ConfigurationError, match=f"DominantSetsParams.{field}"):
        DominantSetsParams(**{field: value})
    with pytest.raises(ConfigurationError, match=field):
        ContextEstimator(
            params=EstimatorParams(
                pipeline=("dominant_sets",), detector_params={"dominant_sets": {field: value}}
            )
        )


def test_the_registered_factory_is_the_detector():
    assert DETECTORS.get("dominant_sets") is DominantSetsDetector

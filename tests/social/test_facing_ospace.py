"""An F-formation's members face its o-space: people standing back to back, however close,
are no conversation (newcomer trial: two people 0.3-0.7 m apart facing away from each other
were reported as a group with confidence 0.58-0.74, and could become a join target)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.core.scene import Person
from socialnav.social.perception import ContextEstimator, EstimatorParams, gcff_kernel
from socialnav.social.perception.base import faces_ospace
from socialnav.social.perception.dominant_sets import DominantSetsParams, dominant_sets
from socialnav.social.perception.fformations import FFormationParams, gcff

DOMINANT_SETS_PIPELINE = ("desk_queue", "viewers", "queue", "dominant_sets", "walking_group")


def pair(distance: float, facing: bool) -> tuple[np.ndarray, np.ndarray]:
    """Two people ``distance`` m apart on the x axis, face to face or back to back."""
    pos = np.array([[0.0, 0.0], [distance, 0.0]])
    yaw = np.array([0.0, math.pi]) if facing else np.array([math.pi, 0.0])
    return pos, yaw


def estimated_groups(pipeline, pos, yaw):
    params = EstimatorParams() if pipeline is None else EstimatorParams(pipeline=pipeline)
    estimator = ContextEstimator(params=params)
    people = [
        Person(i + 1, tuple(p), yaw=float(y)) for i, (p, y) in enumerate(zip(pos, yaw, strict=True))
    ]
    for k in range(10):
        estimate = estimator.update(0.1 * k, people)
    return estimate.context.groups


@pytest.mark.parametrize("distance", [0.3, 0.5, 0.7])
@pytest.mark.parametrize("pipeline", [None, DOMINANT_SETS_PIPELINE], ids=["gcff", "dominant"])
def test_bug_people_back_to_back_are_reported_as_a_conversation(pipeline, distance):
    back = estimated_groups(pipeline, *pair(distance, facing=False))
    assert back == ()
    face = estimated_groups(pipeline, *pair(distance + 0.5, facing=True))
    assert [g.member_ids for g in face] == [(1, 2)]  # the detectors still see a real pair


@pytest.mark.parametrize("compiled", [True, False], ids=["compiled", "reference"])
def test_gcff_drops_back_to_back_pairs_in_both_implementations(compiled):
    was = gcff_kernel.enabled()
    gcff_kernel.set_enabled(compiled)
    try:
        assert gcff(*pair(0.4, facing=False), FFormationParams()) == []
        groups = gcff(*pair(0.9, facing=True), FFormationParams())
        assert [g.tolist() for g in groups] == [[0, 1]]
    finally:
        gcff_kernel.set_enabled(was)


def test_dominant_sets_drops_back_to_back_pairs():
    params = DominantSetsParams()
    assert dominant_sets(*pair(0.4, facing=False), params) == []
    assert [g.tolist() for g, _ in dominant_sets(*pair(0.9, facing=True), params)] == [[0, 1]]


def test_faces_ospace_asks_for_a_strict_majority():
    # four people on a unit circle; k of them face the centre, the others face outward
    angles = np.arange(4) * math.pi / 2
    pos = np.column_stack([np.cos(angles), np.sin(angles)])
    for k, expected in [(4, True), (3, True), (2, False), (0, False)]:
        yaw = angles + math.pi
        yaw[k:] = angles[k:]
        assert faces_ospace(pos, yaw, np.zeros(2)) is expected, k
    # a centre exactly beside a person (neither in front nor behind) is not in front
    assert not faces_ospace(
        np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([0.5 * math.pi] * 2), np.array([0.5, 0.0])
    )


@given(
    st.floats(0.2, 2.0),
    st.floats(-math.pi, math.pi),
    st.floats(-0.5, 0.5),
    st.floats(-0.5, 0.5),
)
def test_no_detector_groups_a_pair_facing_away_from_each_other(distance, bearing, turn_a, turn_b):
    # each faces away from the other, within ±29° of straight away (wider turns let both face
    # one point to their side, which is a formation)
    a = np.zeros(2)
    b = distance * np.array([math.cos(bearing), math.sin(bearing)])
    pos = np.stack([a, b])
    yaw = np.array([bearing + math.pi + turn_a, bearing + turn_b])
    assert gcff(pos, yaw, FFormationParams()) == []
    assert dominant_sets(pos, yaw, DominantSetsParams()) == []

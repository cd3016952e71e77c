"""People tracker (no ROS): ids by gated global-nearest-neighbour association, α-β velocities."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.core.errors import ConfigurationError
from socialnav.integrations.ros2.people import PeopleTracker, TrackerParams

DT = 0.1


def walk(tracker: PeopleTracker, starts, velocities, steps: int, t0: float = 0.0, order=None):
    starts, velocities = np.asarray(starts, float), np.asarray(velocities, float)
    for k in range(steps):
        t = t0 + k * DT
        z = starts + velocities * t
        idx = np.arange(len(z)) if order is None else order(k, len(z))
        tracker.update(t, z[idx])
    return t0 + (steps - 1) * DT


def test_constant_velocity_is_estimated() -> None:
    tracker = PeopleTracker()
    walk(tracker, [[6.0, 0.45]], [[-0.5, 0.0]], 30)
    (p,) = tracker.people()
    assert p.velocity == pytest.approx((-0.5, 0.0), abs=1e-9)
    assert p.yaw == pytest.approx(math.pi)
    assert p.position == pytest.approx((6.0 - 0.5 * 2.9, 0.45))


def test_noisy_velocity_converges() -> None:
    rng = np.random.default_rng(0)
    tracker = PeopleTracker()
    truth = np.array([1.0, 0.5])
    for k in range(100):
        tracker.update(k * DT, truth * k * DT + rng.normal(0, 0.03, 2))
    (p,) = tracker.people()
    assert np.hypot(*(np.asarray(p.velocity) - truth)) < 0.15


def test_crossing_people_keep_their_ids() -> None:
    """Two people walk through each other's path; prediction carries the ids across."""
    tracker = PeopleTracker()
    reverse = lambda k, n: np.arange(n)[:: (-1) ** k]  # noqa: E731 - detections reorder
    walk(tracker, [[0.0, 0.0], [4.0, 0.3]], [[1.0, 0.0], [-1.0, 0.0]], 41, order=reverse)
    a, b = tracker.people()
    assert (a.id, b.id) == (1, 2)
    assert a.position[0] == pytest.approx(4.0) and a.velocity[0] == pytest.approx(1.0)
    assert b.position[0] == pytest.approx(0.0) and b.velocity[0] == pytest.approx(-1.0)


def test_lost_person_is_dropped_and_ids_are_not_reused() -> None:
    tracker = PeopleTracker(TrackerParams(timeout=0.5))
    tracker.update(0.0, [[0.0, 0.0]])
    tracker.update(1.0, [[0.0, 0.0]])  # 1 s later: the old track timed out
    (p,) = tracker.people()
    assert p.id == 2


def test_far_detection_starts_a_new_track() -> None:
    tracker = PeopleTracker(TrackerParams(gate=1.0))
    tracker.update(0.0, [[0.0, 0.0]])
    tracker.update(0.1, [[3.0, 0.0]])
    assert [p.id for p in tracker.people()] == [1, 2]


def test_glitch_speed_is_clipped_and_garbage_dropped() -> None:
    tracker = PeopleTracker(TrackerParams(gate=2.0, max_speed=3.0))
    tracker.update(0.0, [[0.0, 0.0], [np.nan, 1.0]])
    tracker.update(0.1, [[1.5, 0.0], [1e300, 0.0]])  # 15 m/s for one frame
    (p,) = tracker.people()
    assert np.hypot(*p.velocity) == pytest.approx(3.0)
    assert tracker.dropped == 2


def test_old_or_repeated_messages_are_ignored() -> None:
    tracker = PeopleTracker()
    tracker.update(1.0, [[0.0, 0.0]])
    tracker.update(1.0, [[5.0, 0.0]])
    tracker.update(0.5, [[5.0, 0.0]])
    assert [p.position for p in tracker.people()] == [(0.0, 0.0)]


def test_standing_person_keeps_the_detected_orientation() -> None:
    tracker = PeopleTracker()
    tracker.update(0.0, [[1.0, 1.0]], [0.7])
    tracker.update(0.1, [[1.0, 1.0]], [0.8])
    tracker.update(0.2, [[1.0, 1.0]], [np.nan])
    assert tracker.people()[0].yaw == pytest.approx(0.8)


def test_parameters_are_checked() -> None:
    with pytest.raises(ConfigurationError, match="gate"):
        TrackerParams(gate=0.0)
    with pytest.raises(ConfigurationError, match="beta"):
        TrackerParams(beta=2.0)


@given(st.permutations(range(5)), st.integers(0, 2**31 - 1))
def test_ids_do_not_depend_on_detection_order(perm, seed) -> None:
    """Separated people: the same tracks whatever order each message lists them in."""
    rng = np.random.default_rng(seed)
    starts = np.column_stack([np.arange(5) * 3.0, rng.uniform(-1, 1, 5)])
    vel = rng.uniform(-1, 1, (5, 2))
    ordered, shuffled = PeopleTracker(), PeopleTracker()
    walk(ordered, starts, vel, 10)
    walk(shuffled, starts, vel, 10, order=lambda k, n: np.asarray(perm) if k % 2 else np.arange(n))
    for a, b in zip(ordered.people(), shuffled.people(), strict=True):
        assert a.id == b.id
        assert a.position == pytest.approx(b.position)
        assert a.velocity == pytest.approx(b.velocity)

"""The standing test from a track's position history (``velocity_source="positions"``): a
standing person's jitter never reads as walking at any frame rate, a walker is found walking
at any frame rate, and the least-squares velocity is the slope of the positions."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.core.errors import ConfigurationError
from socialnav.core.scene import Person
from socialnav.social.perception import ContextEstimator, EstimatorParams
from socialnav.social.perception.estimator import history_velocity

SPACINGS = (0.1, 0.4, 1.0, 2.0)  # s


def differenced(frames, dt):
    """People of every frame with the velocities a raw tracker reports: finite differences of
    consecutive positions over ``dt`` (zero on the first frame)."""
    out, last = [], {}
    for people in frames:
        here = []
        for pid, xy, yaw in people:
            prev = last.get(pid)
            v = (0.0, 0.0) if prev is None else tuple((xy - prev) / dt)
            here.append(Person(pid, (float(xy[0]), float(xy[1])), v, yaw))
            last[pid] = xy
        out.append(here)
    return out


def jittered_triangle(rng, frames, sigma):
    """Three people standing 0.6 m from a common centre, facing it, their positions jittered
    by ``sigma`` (m) per axis in every frame."""
    angles = 2 * np.pi * np.arange(3) / 3
    spots = 0.6 * np.column_stack([np.cos(angles), np.sin(angles)])
    return [
        [(i, spots[i] + rng.normal(0, sigma, 2), float(angles[i] + np.pi)) for i in range(3)]
        for _ in range(frames)
    ]


def test_the_velocity_of_points_on_a_line_is_their_slope():
    t = np.array([0.0, 0.5, 1.0, 1.5])
    xy = np.column_stack([2.0 + 1.2 * t, -1.0 - 0.5 * t])
    v = history_velocity(t, xy, jitter=0.05, z=2.0, min_displacement=0.5)
    np.testing.assert_allclose(v, (1.2, -0.5), atol=1e-12)


def test_motion_inside_the_jitter_or_short_of_the_leave_distance_is_standing():
    t = np.array([0.0, 0.1, 0.2])
    # 0.6 m/s, but over 0.2 s: 12 cm, well inside what 5 cm jitter explains for 3 samples
    xy = np.column_stack([0.6 * t, np.zeros(3)])
    assert history_velocity(t, xy, jitter=0.05, z=2.0) == (0.0, 0.0)
    # precise positions (jitter 1 mm): significant, but short of the 0.5 m leave distance
    assert history_velocity(t, xy, jitter=0.001, z=2.0, min_displacement=0.5) == (0.0, 0.0)
    v = history_velocity(t, xy, jitter=0.001, z=2.0, min_displacement=0.0)
    np.testing.assert_allclose(v, (0.6, 0.0), atol=1e-12)
    assert history_velocity(t[:1], xy[:1], jitter=0.05, z=2.0) == (0.0, 0.0)


@pytest.mark.parametrize("dt", SPACINGS)
def test_jittered_standing_people_with_differenced_velocities_stay_standing(dt):
    # 5 cm jitter per axis at 10 Hz differences to ~0.7 m/s: taken as the velocity, some of
    # these people walked and the group broke up (the measured source below); from the
    # position history they stand in every frame at every spacing, and stay one group
    rng = np.random.default_rng(4)
    frames = differenced(jittered_triangle(rng, 60, 0.05), dt)
    est = ContextEstimator(params=EstimatorParams(velocity_source="positions"))
    for k, people in enumerate(frames):
        out = est.update(k * dt, people)
        assert all(p.velocity == (0.0, 0.0) for p in out.context.people)
        if k >= 5:
            assert [g.member_ids for g in out.context.groups] == [(0, 1, 2)]


def test_the_measured_source_takes_differenced_jitter_for_walking_at_10_hz():
    # the failure the positions source removes (why the CoffeeBreak sequence depended on Δt)
    rng = np.random.default_rng(4)
    frames = differenced(jittered_triangle(rng, 60, 0.05), 0.1)
    est = ContextEstimator()
    speeds = [
        np.hypot(*p.velocity)
        for k, people in enumerate(frames)
        for p in est.update(0.1 * k, people).context.people
    ]
    assert max(speeds) >= 0.3


@pytest.mark.parametrize("dt", SPACINGS)
def test_a_walker_is_walking_within_a_second_at_any_frame_rate(dt):
    rng = np.random.default_rng(5)
    est = ContextEstimator(params=EstimatorParams(velocity_source="positions"))
    for k in range(int(np.ceil(4.0 / dt)) + 1):
        t = k * dt
        xy = np.array([1.2 * t, 0.0]) + rng.normal(0, 0.05, 2)
        out = est.update(t, [Person(7, (float(xy[0]), float(xy[1])), yaw=0.0)])
        speed = np.hypot(*out.context.people[0].velocity)
        if t >= 1.0 + 1e-9:
            assert speed == pytest.approx(1.2, abs=0.3)


@given(
    dt=st.floats(0.05, 3.0),
    sigma=st.floats(0.0, 0.08),
    seed=st.integers(0, 2**16),
)
def test_standing_jitter_never_moves_whatever_the_spacing(dt, sigma, seed):
    # the test is on displacement over time against the jitter, not on jitter / Δt
    rng = np.random.default_rng(seed)
    t = dt * np.arange(12)
    for n in range(2, 13):
        xy = rng.normal(0.0, sigma, (n, 2))
        assert history_velocity(t[:n], xy, jitter=0.05, z=2.0, min_displacement=0.5) == (0, 0)


def test_an_unknown_velocity_source_is_a_configuration_error():
    with pytest.raises(ConfigurationError, match="velocity_source"):
        ContextEstimator(params=EstimatorParams(velocity_source="guess"))  # type: ignore[arg-type]

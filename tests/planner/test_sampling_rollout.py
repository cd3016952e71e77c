"""Velocity sampling (dynamic window) and the vectorized rollout against closed-form motion."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.robot import PIONEER, PR2
from socialnav.planner.rollout import RolloutParams, num_steps, rollout
from socialnav.planner.sampling import SamplingParams, axis_samples, sample_twists, unique_rows


def test_axis_window_and_zero_inserted():
    v = axis_samples(0.0, -0.1, 0.55, 2.5, 0.1, 4)
    assert v.min() == pytest.approx(-0.1) and v.max() == pytest.approx(0.25)
    assert 0.0 in v and v.size == 5  # linspace(-0.1, 0.25, 4) misses 0 → inserted
    # no crossing → no zero
    w = axis_samples(0.5, -0.1, 0.55, 2.5, 0.1, 3)
    assert 0.0 not in w and w.min() == pytest.approx(0.25) and w.max() == pytest.approx(0.55)


def test_round_off_zero_is_exact():
    v = axis_samples(0.0, -0.1, 0.5, 1.5, 0.1, 6)  # linspace(-0.1, 0.15, 6) hits ~1e-17
    assert np.count_nonzero(np.abs(v) < 1e-6) == 1 and 0.0 in v


def test_velocity_outside_limits_is_clipped():
    v = axis_samples(2.0, -0.1, 0.55, 2.5, 0.1, 3)
    assert v.max() == pytest.approx(0.55) and v.min() == pytest.approx(0.30)


def test_differential_drive_has_no_lateral_samples():
    tw = sample_twists(PIONEER, np.zeros(3), SamplingParams())
    assert tw.shape[0] > 0 and np.all(tw[:, 1] == 0.0)


def test_holonomic_samples_lateral_and_rows_are_unique():
    tw = sample_twists(PR2, np.zeros(3), SamplingParams())
    assert np.unique(tw[:, 1]).size >= 5
    assert np.unique(tw, axis=0).shape == tw.shape


def test_minimum_speeds_and_in_place_rotations():
    tw = sample_twists(PR2, np.zeros(3), SamplingParams())
    trans = np.hypot(tw[:, 0], tw[:, 1])
    rot = np.abs(tw[:, 2])
    assert np.all((trans >= PR2.min_vel_trans) | (rot >= PR2.min_vel_theta))
    in_place = tw[trans == 0.0]
    assert in_place.shape[0] > 0
    assert np.all(np.abs(in_place[:, 2]) >= PR2.min_in_place_vel_theta)
    assert np.any(in_place[:, 2] > 0) and np.any(in_place[:, 2] < 0)
    assert not np.any(np.all(tw == 0.0, axis=1))  # standing still is never sampled


def test_no_in_place_rotation_when_standstill_is_out_of_reach():
    tw = sample_twists(PR2, np.array([0.5, 0.0, 0.0]), SamplingParams())
    assert np.all(tw[:, 0] > 0.2)


@settings(max_examples=40, deadline=None)
@given(
    vx=st.floats(-0.1, 0.55),
    vy=st.floats(-0.3, 0.3),
    w=st.floats(-1.0, 1.0),
    holonomic=st.booleans(),
)
def test_samples_stay_in_the_dynamic_window(vx, vy, w, holonomic):
    robot = PR2 if holonomic else PIONEER
    vel = np.array([vx, vy if holonomic else 0.0, w])
    tw = sample_twists(robot, vel, SamplingParams())
    dt = 0.1
    lim = np.array([robot.acc_lim_x, robot.acc_lim_y, robot.acc_lim_theta]) * dt + 1e-9
    assert np.all(tw[:, 0] <= robot.max_vel_x + 1e-12) and np.all(tw[:, 0] >= robot.min_vel_x)
    assert np.all(np.abs(tw[:, 1]) <= robot.max_vel_y + 1e-12)
    assert np.all(np.abs(tw[:, 2]) <= robot.max_vel_theta + 1e-12)
    vel_c = np.clip(
        vel, [robot.min_vel_x, -robot.max_vel_y, -1.0], [robot.max_vel_x, robot.max_vel_y, 1.0]
    )
    translating = np.hypot(tw[:, 0], tw[:, 1]) > 0
    assert np.all(np.abs(tw[translating] - vel_c) <= lim)


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(0, 400),
    levels=st.integers(1, 6),
)
def test_unique_rows_is_numpy_unique(seed, n, levels):
    """The sampler's row dedup is ``np.unique(axis=0)``: same rows, same order (many ties)."""
    rng = np.random.default_rng(seed)
    rows = rng.integers(-levels, levels + 1, (n, 3)) * 0.1
    expected = np.unique(rows, axis=0)
    got = unique_rows(rows)
    assert got.shape == expected.shape and np.array_equal(got, expected)
    assert np.array_equal(unique_rows(expected), expected)  # already in order: kept as is
    if expected.shape[0] > 1:  # one row out of order (or a duplicate): sorted again
        shuffled = np.concatenate([expected, expected[:1]])
        assert np.array_equal(unique_rows(shuffled), expected)


@settings(max_examples=40, deadline=None)
@given(
    vx=st.floats(-0.1, 0.55),
    vy=st.floats(-0.3, 0.3),
    w=st.floats(-1.0, 1.0),
    holonomic=st.booleans(),
    counts=st.tuples(st.integers(1, 14), st.integers(1, 10), st.integers(1, 18)),
)
def test_samples_are_numpy_unique_of_the_grid(vx, vy, w, holonomic, counts):
    """Sorted unique rows exactly as ``np.unique(axis=0)`` leaves them (the selection order)."""
    robot = PR2 if holonomic else PIONEER
    tw = sample_twists(robot, np.array([vx, vy, w]), SamplingParams(*counts))
    assert np.array_equal(tw, np.unique(tw, axis=0))


# ---- rollout -----------------------------------------------------------------------------

PARAMS = RolloutParams(sim_time=1.7, sim_granularity=0.005, angular_sim_granularity=0.01)


def test_time_grid_is_shared_and_starts_now():
    tw = np.array([[0.5, 0.0, 0.0], [0.1, 0.0, 0.2]])
    tr = rollout(np.array([1.0, 2.0, 0.3]), np.zeros(3), tw, PR2, RolloutParams())
    steps = num_steps(tw, RolloutParams())
    assert steps == int(np.ceil(0.5 * 1.7 / 0.025))
    assert tr.poses.shape == (2, steps + 1, 3)
    assert tr.t[0] == 0.0 and tr.t[-1] == pytest.approx(1.7)
    np.testing.assert_allclose(tr.poses[:, 0], [[1.0, 2.0, 0.3]] * 2)


def test_straight_line():
    tr = rollout(
        np.array([1.0, 1.0, np.pi / 4]), np.zeros(3), np.array([[0.4, 0.0, 0.0]]), PR2, PARAMS
    )
    d = 0.4 * tr.t
    np.testing.assert_allclose(tr.poses[0, :, 0], 1.0 + d / np.sqrt(2), atol=1e-12)
    np.testing.assert_allclose(tr.poses[0, :, 1], 1.0 + d / np.sqrt(2), atol=1e-12)


def test_circle_of_radius_v_over_w():
    v, w = 0.5, 1.0
    tr = rollout(np.zeros(3), np.zeros(3), np.array([[v, 0.0, w]]), PR2, PARAMS)
    r = v / w
    exact = np.stack([r * np.sin(w * tr.t), r * (1 - np.cos(w * tr.t))], axis=1)
    # Euler with the previous heading: error O(v·w·dt·T)
    np.testing.assert_allclose(tr.poses[0, :, :2], exact, atol=0.01)
    np.testing.assert_allclose(np.hypot(tr.poses[0, :, 0], tr.poses[0, :, 1] - r), r, atol=0.01)
    np.testing.assert_allclose(tr.poses[0, :, 2], w * tr.t, atol=1e-12)


def test_pure_rotation_stays_in_place():
    tr = rollout(np.array([2.0, -1.0, 3.0]), np.zeros(3), np.array([[0.0, 0.0, -0.8]]), PR2, PARAMS)
    np.testing.assert_allclose(tr.poses[0, :, :2], [[2.0, -1.0]] * tr.t.size, atol=1e-12)
    expected = (3.0 - 0.8 * tr.t + np.pi) % (2 * np.pi) - np.pi
    np.testing.assert_allclose(tr.poses[0, :, 2], expected, atol=1e-12)


def test_holonomic_diagonal_in_body_frame():
    yaw = np.pi / 2
    tr = rollout(np.array([0.0, 0.0, yaw]), np.zeros(3), np.array([[0.3, 0.2, 0.0]]), PR2, PARAMS)
    # body (0.3, 0.2) at yaw 90° is world (-0.2, 0.3)
    np.testing.assert_allclose(tr.poses[0, -1, :2], np.array([-0.2, 0.3]) * 1.7, atol=1e-12)


def test_float32_rollout_matches_float64():
    tw = sample_twists(PR2, np.zeros(3), SamplingParams())
    a = rollout(np.array([3.0, 4.0, 1.0]), np.zeros(3), tw, PR2, RolloutParams())
    b = rollout(np.array([3.0, 4.0, 1.0]), np.zeros(3), tw, PR2, RolloutParams(), dtype=np.float32)
    assert b.poses.dtype == np.float32
    np.testing.assert_allclose(b.poses[..., :2], a.poses[..., :2], atol=1e-5)

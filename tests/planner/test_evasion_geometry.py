"""Analytic cases for the evasion geometry: closest approach and move-then-hold rollouts."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.core.robot import PR2
from socialnav.planner.evasion import (
    closest_approach,
    evasion_twists,
    move_and_hold,
    person_gap_minima,
)
from socialnav.planner.rollout import RolloutParams, rollout


def test_closest_approach_of_a_walker_passing_beside_a_standing_robot():
    # A walker 5 m ahead, 0.7 m to the side, at 1 m/s toward the robot: 0.7 m after 5 s.
    d, t = closest_approach((0.0, 0.0), (0.0, 0.0), [[5.0, 0.7]], [[-1.0, 0.0]])
    assert d[0] == pytest.approx(0.7) and t[0] == pytest.approx(5.0)
    # Separating: the approach is now.
    d, t = closest_approach((0.0, 0.0), (0.0, 0.0), [[5.0, 0.7]], [[1.0, 0.0]])
    assert d[0] == pytest.approx(np.hypot(5.0, 0.7)) and t[0] == 0.0


finite = st.floats(-5.0, 5.0, allow_nan=False)


@given(finite, finite, finite, finite, finite, finite)
def test_closest_approach_is_the_minimum_over_time(px, py, vx, vy, rx, ry):
    d, t = closest_approach((0.0, 0.0), (rx, ry), [[px, py]], [[vx, vy]])
    ts = np.linspace(0.0, 20.0, 2001)
    rel = np.array([px, py])[None] + ts[:, None] * (np.array([vx - rx, vy - ry]))[None]
    sampled = np.hypot(*rel.T)
    assert d[0] <= sampled.min() + 1e-9
    assert t[0] >= 0.0
    at_t = np.array([px, py]) + t[0] * np.array([vx - rx, vy - ry])
    assert d[0] == pytest.approx(np.hypot(*at_t), abs=1e-9)


def test_move_and_hold_stops_at_each_duration():
    twists = np.array([[0.0, 0.3, 0.0], [0.5, 0.0, 0.0]])
    base = rollout(np.zeros(3), np.zeros(3), twists, PR2, RolloutParams(4.0, 0.05, 0.1))
    held = move_and_hold(base, [1.0, 4.0])
    assert held.poses.shape == (4, base.t.size, 3)
    # Sideways 0.3 m/s for 1 s, then still: 0.3 m at the end; for 4 s: 1.2 m.
    assert held.end_poses[0, 1] == pytest.approx(0.3, abs=1e-9)
    assert held.end_poses[2, 1] == pytest.approx(1.2, abs=1e-9)
    assert held.end_poses[1, 0] == pytest.approx(0.5, abs=1e-9)
    np.testing.assert_array_equal(held.twists, np.tile(twists, (2, 1)))


def test_a_move_that_clears_a_walkers_lane_and_holds_keeps_the_larger_gap():
    # A walker on the robot's line 4 m ahead at 1 m/s: stepping 0.9 m aside and holding keeps
    # clear over the whole pass; standing still or driving on does not.
    twists = np.array([[0.0, 0.0, 0.0], [0.0, 0.3, 0.0], [0.5, 0.0, 0.0]])
    base = rollout(np.zeros(3), np.zeros(3), twists, PR2, RolloutParams(6.0, 0.05, 0.1))
    held = move_and_hold(base, [3.0])
    gaps = person_gap_minima(
        held, PR2, np.array([[4.0, 0.0]]), np.array([[-1.0, 0.0]]), np.array([0.25])
    )
    assert gaps[1, 0] == pytest.approx(0.9 - 0.25 - PR2.circumscribed_radius, abs=1e-6)
    assert gaps[0, 0] < 0 and gaps[2, 0] < 0


def test_holonomic_evasion_can_turn_while_driving_at_full_speed():
    # Sideways the PR2 makes 0.3 m/s; an arc at 0.55 m/s gains more lateral distance in 2 s.
    assert not (evasion_twists(PR2)[:, 2] != 0).any()  # the ROS-like default: translations
    twists = evasion_twists(PR2, arcs=True)
    arcs = twists[(twists[:, 0] == PR2.max_vel_x) & (twists[:, 2] != 0.0)]
    assert len(arcs) >= 2 and (arcs[:, 2] > 0).any() and (arcs[:, 2] < 0).any()
    base = rollout(np.zeros(3), np.zeros(3), twists, PR2, RolloutParams(2.0, 0.05, 0.1))
    lateral = np.abs(base.end_poses[:, 1])
    assert lateral.max() > 0.3 * 2.0 + 0.1


@given(
    seed=st.integers(0, 2**31 - 1),
    n_twists=st.integers(1, 12),
    n_people=st.integers(0, 6),
    holds=st.lists(st.floats(0.0, 4.0), min_size=1, max_size=4),
)
def test_person_gap_minima_compiled_equals_numpy(
    seed: int, n_twists: int, n_people: int, holds: list[float]
) -> None:
    """The compiled minimum (root of the minimum squared distance) gives NumPy's values bit
    for bit on move-then-hold rollouts among random walkers."""
    from socialnav.planner import kernels

    if not kernels.enabled():
        pytest.skip("reference path selected")
    rng = np.random.default_rng(seed)
    twists = np.column_stack(
        [
            rng.uniform(-0.2, 0.5, n_twists),
            rng.uniform(-0.3, 0.3, n_twists),
            rng.uniform(-1, 1, n_twists),
        ]
    )
    base = rollout(rng.uniform(-1, 1, 3), np.zeros(3), twists, PR2, RolloutParams(4.0, 0.05, 0.1))
    trajs = move_and_hold(base, holds)
    people = rng.uniform(-4.0, 4.0, (n_people, 2))
    velocities = rng.uniform(-1.5, 1.5, (n_people, 2))
    radii = rng.uniform(0.2, 0.3, n_people)
    out = {}
    for flag in (False, True):
        previous = kernels.set_enabled(flag)
        try:
            out[flag] = person_gap_minima(trajs, PR2, people, velocities, radii)
        finally:
            kernels.set_enabled(previous)
    assert out[True].shape == (len(twists) * len(holds), n_people)
    assert np.array_equal(out[False], out[True])

"""Task and efficiency metrics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socialnav.metrics import METRICS


def m(name, record):
    return METRICS.get(name)(record)


def test_collision_onsets_split_by_kind(make_record):
    n = 6
    rec = make_record(
        np.zeros((n, 2)),
        collision_person=[False, True, True, False, True, False],
        collision_obstacle=[True, True, False, False, False, False],
    )
    assert m("collisions_person", rec) == 2
    assert m("collisions_obstacle", rec) == 1
    assert m("collisions", rec) == 3
    assert m("success", rec) == 0.0


def test_no_collision_counts_zero(make_record, seg):
    rec = make_record(seg((0, 0), (5, 0), 50))
    assert m("collisions_person", rec) == 0
    assert m("collisions_obstacle", rec) == 0


def test_success_timeout_and_spl_on_a_straight_run(make_record, seg):
    rec = make_record(seg((0, 0), (5, 0), 50), time_limit=60.0)
    assert m("success", rec) == 1.0
    assert m("timeout", rec) == 0.0
    assert m("path_length_ratio", rec) == pytest.approx(1.0)
    assert m("spl", rec) == pytest.approx(1.0)
    late = make_record(seg((0, 0), (5, 0), 50), time_limit=4.0)  # reached at t = 5 s
    assert m("timeout", late) == 1.0
    assert m("success", late) == 0.0
    assert m("spl", late) == 0.0


def test_path_length_ratio_and_spl_on_a_detour(make_record, seg):
    path = np.vstack([seg((0, 0), (3, 0), 30), seg((3, 0), (3, 4), 40)[1:]])
    rec = make_record(path)
    assert m("path_length", rec) == pytest.approx(7.0)
    assert m("path_length_ratio", rec) == pytest.approx(7.0 / 5.0)
    assert m("spl", rec) == pytest.approx(5.0 / 7.0)


def test_ratio_nan_when_starting_on_target(make_record):
    rec = make_record(np.zeros((5, 2)))
    assert math.isnan(m("path_length_ratio", rec))
    assert math.isnan(m("spl", rec))


def test_time_not_moving_counts_waiting_before_the_goal(make_record, seg):
    wait = np.zeros((11, 2))  # 10 steps standing still = 1 s
    path = np.vstack([wait, seg((0, 0), (2, 0), 20)[1:], np.tile([2.0, 0.0], (30, 1))])
    rec = make_record(path)
    # the 3 s standing at the goal afterwards do not count
    assert m("time_not_moving", rec) == pytest.approx(1.0)


def test_bug_extra_time_of_a_holonomic_robot_driving_diagonally_is_not_negative(make_record, seg):
    """A PR2 ended with extra_time −0.5 s on a queue run: v_max was its forward limit 0.55 m/s,
    while its base drives at hypot(0.55, 0.3) = 0.63 m/s diagonally."""
    v = np.hypot(0.55, 0.3)
    path = seg((0, 0), (10 * 0.55 / v, 10 * 0.3 / v), round(10 / v / 0.1))
    rec = make_record(path, goal_tolerance=0.01, meta={"robot": "pr2"})
    assert m("extra_time", rec) >= -0.11  # one control step of discretisation


def test_extra_time_uses_max_speed_from_meta(make_record, seg):
    path = seg((0, 0), (10, 0), 200)  # 0.5 m/s, reached at t = 20 s
    rec = make_record(path, goal_tolerance=0.01, meta={"max_speed": 1.0})
    assert m("extra_time", rec) == pytest.approx(20.0 - 9.99)
    pr2 = make_record(path, goal_tolerance=0.01, meta={"robot": "pr2"})
    assert m("extra_time", pr2) == pytest.approx(20.0 - 9.99 / np.hypot(0.55, 0.3))
    pioneer = make_record(path, goal_tolerance=0.01, meta={"robot": "pioneer"})
    assert m("extra_time", pioneer) == pytest.approx(20.0 - 9.99 / 0.5)
    assert math.isnan(m("extra_time", make_record(path, goal_tolerance=0.01)))
    # arrival at 1.0 m tolerance: at t = 18 s at 0.5 m/s vs 9 m / 1 m/s straight
    loose = make_record(path, goal_tolerance=1.0, meta={"max_speed": 1.0})
    assert m("extra_time", loose) == pytest.approx(18.0 - 9.0)

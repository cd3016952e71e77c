"""Table 1 metrics on analytic episodes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socialnav.metrics import METRICS, compute_metrics


def m(name, record):
    return METRICS.get(name)(record)


def test_straight_pass_beside_static_person_gives_lateral_1_5(make_record, seg):
    rec = make_record(seg((0, 0), (10, 0), 100), people=[[5.0, 1.5]])
    assert m("lateral_distance", rec) == pytest.approx(1.5)
    assert m("deviation_distance", rec) != m("deviation_distance", rec)  # NaN: never deviated
    assert m("proxemic_intrusions", rec) == 0


def test_lateral_distance_interpolates_the_crossing(make_record, seg):
    # The robot drifts left at 0.1 m per metre; the person stands between two samples (x=5.05).
    xy = seg((0, 0), (10, 1.0), 100)
    rec = make_record(xy, people=[[5.05, 2.0]], start=(0, 0, 0), goal=(10, 0, 0))
    assert m("lateral_distance", rec) == pytest.approx(2.0 - 0.505)


def test_table1_traditional_pass_with_walking_person(make_record, seg):
    # hallway_passing geometry: robot at y=-0.45 at 0.5 m/s, person at y=+0.45 at -0.5 m/s.
    steps = 100  # 10 s at dt=0.1
    robot = seg((0.5, -0.45), (5.5, -0.45), steps)
    person = seg((6.0, 0.45), (1.0, 0.45), steps)[:, None, :]
    rec = make_record(robot, people=person, goal_tolerance=0.12)
    values = compute_metrics(rec, ["lateral_distance", "proxemic_intrusions", "total_distance"])
    assert values["lateral_distance"] == pytest.approx(0.9)
    assert values["proxemic_intrusions"] == 1
    # reached at the first sample within 0.12 m (0.1 m short): 4.9 m travelled, t = 9.8 s
    assert values["total_distance"] == pytest.approx(4.9)
    assert math.isnan(m("deviation_distance", rec))
    assert m("time_to_goal", rec) == pytest.approx(9.8)


def test_lateral_distance_nan_when_they_never_pass_or_no_people(make_record, seg):
    rec = make_record(seg((0, 0), (4, 0), 40), people=[[10.0, 1.0]])
    assert math.isnan(m("lateral_distance", rec))
    assert math.isnan(m("lateral_distance", make_record(seg((0, 0), (4, 0), 40))))


def test_total_distance_stops_at_goal(make_record, seg):
    path = np.vstack([seg((0, 0), (3, 0), 30), seg((3, 0), (3, 4), 40)[1:]])
    wiggle = np.array([[3.05, 4.0], [3.0, 4.05], [3.0, 4.0]])  # inside the 0.1 m tolerance
    rec = make_record(np.vstack([path, wiggle]), goal=(3, 4, 0))
    # reached at (3, 3.9), the first sample within 0.1 m; the wiggle afterwards is not counted
    assert m("total_distance", rec) == pytest.approx(6.9)
    assert m("path_length", rec) == pytest.approx(7.0 + 0.05 + math.hypot(0.05, 0.05) + 0.05)


def test_time_to_goal_first_entry_held_until_end(make_record):
    # distance to goal (0,0): 1.0, 0.05 (in), 0.5 (out), 0.05 (in from t=0.3), 0.0
    xy = np.array([[1.0, 0], [0.05, 0], [0.5, 0], [0.05, 0], [0.0, 0]])
    rec = make_record(xy, goal=(0, 0, 0), goal_tolerance=0.1)
    assert m("time_to_goal", rec) == pytest.approx(0.3)
    assert m("total_distance", rec) == pytest.approx(0.95 + 0.45 + 0.45)
    never = make_record(xy[:3], goal=(0, 0, 0))
    assert math.isnan(m("time_to_goal", never))
    assert math.isnan(m("total_distance", never))


def test_person_crossing_personal_space_twice_gives_two_intrusions(make_record, seg):
    robot = np.zeros((121, 2))
    there = seg((-3, 0), (3, 0), 60)
    person = np.vstack([there, there[::-1][1:]])[:, None, :]
    rec = make_record(robot, people=person)
    assert m("proxemic_intrusions", rec) == 2


def test_intrusion_counts_start_inside_and_not_the_boundary(make_record):
    person = np.array([[0.5, 0], [2.0, 0], [1.2, 0], [1.19, 0]])[:, None, :]
    rec = make_record(np.zeros((4, 2)), people=person)
    assert m("proxemic_intrusions", rec) == 2  # start inside + the 1.2 -> 1.19 entry


def test_intrusions_sum_over_people(make_record):
    rec = make_record(np.zeros((3, 2)), people=[[1.0, 0.0], [0.0, -0.5], [5.0, 5.0]])
    assert m("proxemic_intrusions", rec) == 2


def test_deviation_distance_at_known_time(make_record):
    # Straight along x at 1 m/s, then from t=2 s the robot veers left at 0.3 m/s: the lateral
    # offset exceeds 0.1 m at t = 2 + 1/3 s (between samples), where p = (2 + 1/3, 0.1).
    t = np.arange(0, 51) * 0.1
    xy = np.column_stack([t, np.where(t > 2, 0.3 * (t - 2), 0.0)])
    rec = make_record(xy, people=[[10.0, 0.5]], start=(0, 0, 0), goal=(5, 0, 0))
    expected = math.hypot(10.0 - (2 + 1 / 3), 0.5 - 0.1)
    assert m("deviation_distance", rec) == pytest.approx(expected, rel=1e-9)


def test_deviation_uses_closest_person(make_record, seg):
    xy = seg((0, 0), (4, 1), 40)
    rec = make_record(xy, people=[[20.0, 0.0], [3.0, 2.0]], start=(0, 0, 0), goal=(4, 0, 0))
    # offset 0.25*x exceeds 0.1 at x = 0.4: robot (0.4, 0.1); closest person is (3, 2)
    assert m("deviation_distance", rec) == pytest.approx(math.hypot(2.6, 1.9))

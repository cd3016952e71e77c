"""Safety and proxemics metrics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socialnav.metrics import METRICS
from socialnav.metrics.proxemics import kirby_intrusion


def m(name, record):
    return METRICS.get(name)(record)


def test_min_distances_center_edge_footprint(make_record):
    rec = make_record(np.zeros((3, 2)), people=[[1.0, 0.0]])
    assert m("min_distance_center", rec) == pytest.approx(1.0)
    assert m("min_distance_edge", rec) == pytest.approx(1.0 - math.sqrt(0.08) - 0.25)
    assert m("min_distance_footprint", rec) == pytest.approx(1.0 - 0.2 - 0.25)
    turned = make_record(np.zeros((3, 2)), yaw=np.pi / 4, people=[[1.0, 0.0]])
    assert m("min_distance_footprint", turned) == pytest.approx(1.0 - math.sqrt(0.08) - 0.25)
    touching = make_record(np.zeros((2, 2)), people=[[0.3, 0.0]])
    assert m("min_distance_footprint", touching) == pytest.approx(0.3 - 0.2 - 0.25)


def test_hall_zone_shares_and_compliance(make_record):
    d = np.array([0.2, 0.3, 1.0, 2.0, 2.5, 4.0, 5.0, 0.5])
    person = np.column_stack([d, np.zeros_like(d)])[:, None, :]
    rec = make_record(np.zeros((8, 2)), people=person)
    shares = [m(f"time_share_{z}", rec) for z in ("intimate", "personal", "social", "public")]
    assert shares == pytest.approx([0.25, 0.25, 0.25, 0.25])
    assert m("psc_1.2", rec) == pytest.approx(0.5)
    assert m("psc_0.45", rec) == pytest.approx(0.75)


def test_zone_shares_use_the_closest_person(make_record):
    rec = make_record(np.zeros((2, 2)), people=[[0.3, 0.0], [10.0, 0.0]])
    assert m("time_share_intimate", rec) == 1.0
    assert m("time_share_public", rec) == 0.0


def test_no_people_gives_nan(make_record, seg):
    rec = make_record(seg((0, 0), (1, 0), 10))
    for name in ("min_distance_center", "psc_1.2", "time_share_social", "passing_side"):
        assert math.isnan(m(name, rec))


def test_time_to_collision_head_on(make_record):
    # robot still at the origin (radius 0.3), person at (5, 0) walking at -1 m/s (radius 0.25)
    rec = make_record(
        np.zeros((4, 2)), people=[[5.0, 0.0]], people_velocities=[[-1.0, 0.0]], robot_radius=0.3
    )
    assert m("min_time_to_collision", rec) == pytest.approx(5.0 - 0.55)
    away = make_record(
        np.zeros((4, 2)), people=[[5.0, 0.0]], people_velocities=[[1.0, 0.0]], robot_radius=0.3
    )
    assert m("min_time_to_collision", away) == math.inf
    miss = make_record(
        np.zeros((4, 2)), people=[[5.0, 1.0]], people_velocities=[[-1.0, 0.0]], robot_radius=0.3
    )
    assert m("min_time_to_collision", miss) == math.inf
    overlap = make_record(np.zeros((2, 2)), people=[[0.5, 0.0]], robot_radius=0.3)
    assert m("min_time_to_collision", overlap) == 0.0


def test_time_to_collision_uses_robot_motion(make_record, seg):
    # robot drives +x at 1 m/s toward a still person 5 m ahead
    rec = make_record(seg((0, 0), (1, 0), 10), people=[[5.0, 0.0]], robot_radius=0.3)
    assert m("min_time_to_collision", rec) == pytest.approx(4.0 - 0.55)


@pytest.mark.parametrize(("side", "expected"), [(1.0, 1.0), (-1.0, -1.0)])
def test_winding_number_passing_side(make_record, seg, side, expected):
    rec = make_record(seg((0, 0), (10, 0), 100), people=[[5.0, side]])
    w = (math.pi - 2 * math.atan(1 / 5)) / (2 * math.pi)
    assert m("winding_number", rec) == pytest.approx(expected * w)
    assert m("passing_side", rec) == expected


def test_passing_side_zero_without_a_pass(make_record, seg):
    rec = make_record(seg((0, 0), (2, 0), 20), people=[[10.0, 1.0]])
    assert m("passing_side", rec) == 0.0


def test_oncoming_person_on_the_robots_left_is_plus_one(make_record, seg):
    robot = seg((1, -0.5), (19, -0.5), 180)
    person = seg((19, 0.75), (1, 0.75), 180)[:, None, :]
    assert m("passing_side", make_record(robot, people=person)) == 1.0


def test_kirby_static_person_front_side_rear(make_record):
    # person at the origin facing +x (yaw from the context), robot at front / rear / side
    def value(x, y):
        rec = make_record([[x, y]] * 2, people=[[0.0, 0.0]], person_yaws=[0.0])
        return kirby_intrusion(rec)[0, 0]

    assert value(1.0, 0.0) == pytest.approx(math.exp(-1 / (2 * 0.5**2)))
    assert value(-1.0, 0.0) == pytest.approx(math.exp(-1 / (2 * 0.25**2)))
    assert value(0.0, 1.0) == pytest.approx(math.exp(-1 / (2 * (1 / 3) ** 2)))
    assert value(0.0, 0.0) == pytest.approx(1.0)


def test_kirby_moving_person_stretches_in_its_direction(make_record):
    # person walking +y at 1 m/s: sigma_h = 2, robot 1 m ahead of it
    rec = make_record([[0.0, 1.0]] * 3, people=[[0.0, 0.0]], people_velocities=[[0.0, 1.0]])
    assert m("kirby_intrusion_max", rec) == pytest.approx(math.exp(-1 / 8))
    assert m("kirby_intrusion_mean", rec) == pytest.approx(math.exp(-1 / 8))

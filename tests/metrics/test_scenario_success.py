"""Scenario-specific metrics and the success conditions of each family."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from socialnav.core.robot import PR2
from socialnav.core.scene import Artwork, Group, Queue
from socialnav.metrics import METRICS, evaluate_success
from socialnav.metrics.series import convex_overlap_depth
from socialnav.sim.scenario import load_scenario


def m(name, record):
    return METRICS.get(name)(record)


# --- separating-axis depth ---------------------------------------------------------------------


def square(cx, cy, half):
    return np.array(
        [
            [cx + half, cy + half],
            [cx - half, cy + half],
            [cx - half, cy - half],
            [cx + half, cy - half],
        ]
    )


def test_convex_overlap_depth_analytic():
    assert convex_overlap_depth(square(0, 0, 0.5), square(0.9, 0, 0.5)) == pytest.approx(0.1)
    assert convex_overlap_depth(square(0, 0, 0.5), square(0.9, 0, 0.5)[::-1]) == (
        pytest.approx(0.1)
    )
    assert convex_overlap_depth(square(0, 0, 0.5), square(1.0, 0, 0.5)) == 0.0  # touching
    assert convex_overlap_depth(square(0, 0, 0.5), square(3.0, 0, 0.5)) == 0.0
    assert convex_overlap_depth(square(0, 0, 1.0), square(0, 0, 0.1)) == pytest.approx(1.1)
    diamond = np.array([[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]])
    # the square's corner (0.4, 0.4) lies 0.2/sqrt(2) inside the diamond's edge x + y = 1
    near = convex_overlap_depth(diamond, square(0.6, 0.6, 0.2))
    assert near == pytest.approx(0.2 / math.sqrt(2))
    batch = convex_overlap_depth(
        np.stack([square(0, 0, 0.5), square(5, 5, 0.5)]), square(0.9, 0, 0.5)
    )
    assert batch == pytest.approx([0.1, 0.0])


# --- queue -----------------------------------------------------------------------------------

QUEUE_PEOPLE = [[0.0, 0.0], [0.0, -0.8], [0.0, -1.6]]
QUEUE = Queue(member_ids=(0, 1, 2), service_point=(0.0, 0.9))
TAIL = (0.0, -2.4, np.pi / 2)


def queue_record(make_record, xy, yaw=np.pi / 2):
    return make_record(
        xy,
        yaw=yaw,
        people=QUEUE_PEOPLE,
        queues=(QUEUE,),
        family="queue",
        scenario="queue_line",
        target=TAIL,
        goal=(0.0, 0.5, np.pi / 2),
    )


def test_queue_joined_at_the_tail(make_record, seg):
    rec = queue_record(make_record, seg((3, -3), (0, -2.4), 40))
    assert m("queue_cut_in", rec) == 0
    assert m("queue_cut_in_time", rec) == 0.0
    assert m("queue_slot_error", rec) == pytest.approx(0.0)
    assert m("queue_heading_error", rec) == pytest.approx(0.0)
    result = evaluate_success(rec)
    assert result == {
        "reached_goal": True,
        "no_collision": True,
        "at_tail_slot": True,
        "arrival_yaw": True,
        "facing_line": True,
        "no_cut_in": True,
        "success": True,
    }


def test_queue_cut_in_between_members(make_record, seg):
    xy = np.vstack([seg((2, -0.4), (-2, -0.4), 40), seg((-2, -0.4), (0, -2.4), 20)[1:]])
    rec = queue_record(make_record, xy)
    assert m("queue_cut_in", rec) == 1
    # footprint half-width 0.2 + band half-width 0.25: inside for |x| < 0.45, 9 samples
    assert m("queue_cut_in_time", rec) == pytest.approx(0.9)
    result = evaluate_success(rec)
    assert not result["no_cut_in"]
    assert result["at_tail_slot"]
    assert not result["success"]


def test_queue_cut_in_uses_the_footprint_not_the_centre(make_record):
    inside = queue_record(make_record, [[0.4, -0.4]] * 3)
    outside = queue_record(make_record, [[0.5, -0.4]] * 3)
    assert m("queue_cut_in", inside) == 1
    assert m("queue_cut_in", outside) == 0


def test_queue_wrong_heading_or_spot_fails(make_record, seg):
    facing_away = queue_record(make_record, seg((3, -3), (0, -2.4), 40), yaw=0.0)
    assert m("queue_heading_error", facing_away) == pytest.approx(np.pi / 2)
    assert not evaluate_success(facing_away)["facing_line"]
    beside_desk = queue_record(make_record, seg((3, 0.5), (0.6, 0.5), 40))
    assert m("queue_slot_error", beside_desk) == pytest.approx(math.hypot(0.6, 2.9))
    result = evaluate_success(beside_desk)
    assert not result["at_tail_slot"]
    assert not result["success"]


def test_queue_slot_error_is_nan_outside_the_queue_family(make_record, seg):
    rec = make_record(seg((0, 0), (1, 0), 10), people=QUEUE_PEOPLE, queues=(QUEUE,))
    assert math.isnan(m("queue_slot_error", rec))
    assert not math.isnan(m("queue_cut_in", rec))


# --- group -----------------------------------------------------------------------------------

ANGLES = np.radians([90.0, 180.0, 270.0])
GROUP_PEOPLE = 0.9 * np.column_stack([np.cos(ANGLES), np.sin(ANGLES)])
GROUP = Group(member_ids=(0, 1, 2))
SPOT = (0.9, 0.0, np.pi)


def group_record(make_record, xy, yaw=np.pi, footprint=PR2.polygon):
    return make_record(
        xy,
        yaw=yaw,
        people=GROUP_PEOPLE,
        groups=(GROUP,),
        family="group",
        scenario="group_join",
        target=SPOT,
        goal=(0.0, 0.0, np.pi),
        footprint=footprint,
    )


def test_group_joined_at_the_free_spot(make_record, seg):
    rec = group_record(make_record, seg((5, 0), (0.9, 0), 41))
    assert m("join_spot_error", rec) == pytest.approx(0.0, abs=1e-12)
    assert m("join_heading_error", rec) == pytest.approx(0.0)
    assert m("ospace_intrusion_time_center", rec) == 0.0
    assert m("ospace_intrusion_depth_center", rec) == 0.0
    # the PR2's front edge (0.325 m ahead) reaches 0.9 - 0.325 = 0.575 < 0.6: footprint variant
    assert m("ospace_intrusion_depth_footprint", rec) == pytest.approx(0.025)
    assert m("ospace_intrusion_time_footprint", rec) > 0.0
    result = evaluate_success(rec)
    assert result["outside_o_space"]
    assert result["success"]


def test_spot_families_arrive_within_the_spot_radius(make_record, seg):
    # the robot stops 0.2 m short of the spot; the record's own tolerance is 0.1 m
    rec = group_record(make_record, seg((5, 0), (1.1, 0), 39))
    assert rec.goal_tolerance == pytest.approx(0.1)
    assert math.isnan(m("time_to_goal", rec))  # metrics keep the record's tolerance
    result = evaluate_success(rec)
    assert result["reached_goal"]
    assert result["success"]
    short = group_record(make_record, seg((5, 0), (1.3, 0), 37))
    assert not evaluate_success(short)["reached_goal"]


def test_group_traditional_goes_to_the_centre(make_record, seg):
    rec = group_record(make_record, seg((5, 0), (0, 0), 50))
    assert m("ospace_intrusion_depth_center", rec) == pytest.approx(0.6)
    # inside while |x| < 0.6: x in {0.5, 0.4, ..., 0.0} = 6 samples
    assert m("ospace_intrusion_time_center", rec) == pytest.approx(0.6)
    result = evaluate_success(rec)
    assert not result["outside_o_space"]
    assert not result["at_free_spot"]
    assert not result["success"]


def test_group_not_facing_the_centre_fails(make_record, seg):
    rec = group_record(make_record, seg((5, 0), (0.9, 0), 41), yaw=np.pi / 2)
    assert m("join_heading_error", rec) == pytest.approx(np.pi / 2)
    result = evaluate_success(rec)
    assert not result["facing_centre"]
    assert not result["success"]


# --- gallery ---------------------------------------------------------------------------------

ART = Artwork(center=(0.0, 3.0), width=1.2, facing=-np.pi / 2, viewer_ids=(0,))
VIEWER = [[0.0, 1.5]]


def gallery_record(make_record, xy, family, target, yaw=0.0, waypoint=None):
    return make_record(
        xy,
        yaw=yaw,
        people=VIEWER,
        artworks=(ART,),
        family=family,
        scenario=family,
        target=target,
        goal=target,
        waypoint=waypoint,
    )


def test_gallery_activity_passing_behind_the_viewer(make_record, seg):
    rec = gallery_record(
        make_record,
        seg((-3, 0.8), (3, 0.8), 60),
        "gallery_activity",
        (3.0, 0.8, 0.0),
        waypoint=(0.0, 0.8),
    )
    assert m("activity_space_time", rec) == 0.0
    assert m("activity_space_depth", rec) == 0.0
    assert m("waypoint_min_distance", rec) == pytest.approx(0.0, abs=1e-12)
    assert evaluate_success(rec) == {
        "reached_goal": True,
        "no_collision": True,
        "outside_activity_space": True,
        "success": True,
    }


def test_gallery_activity_crossing_between_viewer_and_art(make_record, seg):
    rec = gallery_record(
        make_record, seg((-3, 2.2), (3, 2.2), 60), "gallery_activity", (3.0, 2.2, 0.0)
    )
    # trapezoid half-width at y = 2.2 is 0.3 + 0.3 * 0.7 / 1.5 = 0.44; at x = 0 the robot's
    # 0.4 m square sits fully inside, so the depth exceeds its half-size
    assert m("activity_space_time", rec) > 0.0
    assert m("activity_space_depth", rec) > 0.2
    result = evaluate_success(rec)
    assert result["reached_goal"]
    assert not result["outside_activity_space"]
    assert not result["success"]


def test_gallery_present_at_the_presenter_spot(make_record, seg):
    spot = (1.3, 2.2, math.atan2(-0.7, -1.3))  # facing the viewer at (0, 1.5)
    rec = gallery_record(
        make_record, seg((4, 0), spot[:2], 40), "gallery_present", spot, yaw=spot[2]
    )
    assert m("presenter_spot_error", rec) == pytest.approx(0.0, abs=1e-12)
    assert m("viewer_distance_final", rec) == pytest.approx(math.hypot(1.3, 0.7))
    assert m("presenter_heading_error", rec) == pytest.approx(0.0, abs=1e-12)
    assert m("activity_space_time", rec) == 0.0
    assert evaluate_success(rec)["success"]


def test_gallery_present_traditional_stops_in_front_of_the_art(make_record, seg):
    spot = (1.3, 2.2, 0.0)
    rec = gallery_record(make_record, seg((4, 0), (0, 2.4), 40), "gallery_present", spot)
    assert m("presenter_spot_error", rec) == pytest.approx(math.hypot(1.3, 0.2))
    result = evaluate_success(rec)
    assert not result["at_presenter_spot"]
    assert not result["outside_activity_space"]
    assert not result["success"]


# --- hallway and common conditions ---------------------------------------------------------------


def test_hallway_personal_space_condition(make_record, seg):
    wide = make_record(seg((0, 0), (10, 0), 100), people=[[5.0, 1.5]])
    assert evaluate_success(wide) == {
        "reached_goal": True,
        "no_collision": True,
        "no_personal_space_intrusion": True,
        "success": True,
    }
    close = make_record(seg((0, 0), (10, 0), 100), people=[[5.0, 0.9]])
    result = evaluate_success(close)
    assert not result["no_personal_space_intrusion"]
    assert not result["success"]


def test_hallway_headon_reports_but_does_not_require_personal_space(make_record, seg):
    rec = make_record(seg((0, 0), (10, 0), 100), people=[[5.0, 0.9]], scenario="hallway_headon")
    # the scenario file says so (success: no_personal_space_intrusion: {required: false})
    rec = dataclasses.replace(rec, success=load_scenario("hallway_headon").success_spec())
    result = evaluate_success(rec)
    assert not result["no_personal_space_intrusion"]
    assert result["success"]


def test_collision_or_late_arrival_fails_every_family(make_record, seg):
    hit = make_record(seg((0, 0), (10, 0), 100), collision_obstacle=[False] * 50 + [True] * 51)
    assert evaluate_success(hit)["no_collision"] is False
    assert evaluate_success(hit)["success"] is False
    late = make_record(seg((0, 0), (10, 0), 100), time_limit=5.0)
    assert evaluate_success(late)["reached_goal"] is False


def test_success_rejects_bad_family_or_missing_context(make_record, seg):
    with pytest.raises(ValueError, match="unknown scenario family"):
        evaluate_success(make_record(seg((0, 0), (1, 0), 10), family="maze"))
    with pytest.raises(ValueError, match="queue"):
        evaluate_success(make_record(seg((0, 0), (1, 0), 10), family="queue"))
    with pytest.raises(ValueError, match="group"):
        evaluate_success(make_record(seg((0, 0), (1, 0), 10), family="group"))
    with pytest.raises(ValueError, match="viewer"):
        evaluate_success(make_record(seg((0, 0), (1, 0), 10), family="gallery_activity"))

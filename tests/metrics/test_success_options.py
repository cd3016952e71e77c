"""Per-scenario success options (tolerances, conditions not required) and the gallery's
facing-the-viewer condition."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socialnav.core.scene import Artwork
from socialnav.metrics import evaluate_success, success_conditions
from socialnav.sim.scenario import ConditionOption, SuccessOptions

ART = Artwork(center=(0.0, 3.0), width=1.2, facing=-np.pi / 2, viewer_ids=(0,))
SPOT = (1.3, 2.2, math.atan2(-0.7, -1.3))  # facing the viewer at (0, 1.5)


def present(make_record, seg, end, yaw, options=None):
    meta = {"robot": "pr2"}
    if options is not None:
        meta["success_options"] = options.model_dump()
    return make_record(
        seg((4, 0), end, 40),
        yaw=yaw,
        people=[[0.0, 1.5]],
        artworks=(ART,),
        family="gallery_present",
        scenario="gallery_present",
        target=SPOT,
        goal=SPOT,
        meta=meta,
    )


def test_presenter_must_face_the_viewer(make_record, seg):
    facing = evaluate_success(present(make_record, seg, SPOT[:2], SPOT[2]))
    assert facing["facing_viewer"] and facing["success"]
    away = evaluate_success(present(make_record, seg, SPOT[:2], SPOT[2] + 1.0))
    assert not away["facing_viewer"]
    assert not away["success"]


def test_generated_tolerance_is_tighter_than_the_paper_suite(make_record, seg):
    off = (SPOT[0] + 0.2, SPOT[1])  # 0.2 m from the spot: inside 0.3 m, outside 0.10 m
    paper = evaluate_success(present(make_record, seg, off, SPOT[2]))
    assert paper["reached_goal"] and paper["at_presenter_spot"]
    tight = SuccessOptions(position_tolerance=0.10, yaw_tolerance=0.2)
    gen = evaluate_success(present(make_record, seg, off, SPOT[2], tight))
    assert not gen["reached_goal"] and not gen["at_presenter_spot"] and not gen["success"]
    close = (SPOT[0] + 0.05, SPOT[1])
    assert evaluate_success(present(make_record, seg, close, SPOT[2], tight))["success"]


def test_yaw_tolerance_is_part_of_arrival(make_record, seg):
    tight = SuccessOptions(position_tolerance=0.10, yaw_tolerance=0.2)
    # 0.3 rad off: facing the viewer within 0.5 rad, but not within the 0.2 rad arrival yaw
    res = evaluate_success(present(make_record, seg, SPOT[:2], SPOT[2] + 0.3, tight))
    assert not res["reached_goal"]
    assert not res["success"]


def test_a_condition_not_required_keeps_its_reason_and_does_not_fail(make_record, seg):
    people = [[5.0, 0.8]]  # passes at 0.8 m: the personal-space condition fails
    reason = "the corridor allows at most 0.90 m from a person"
    opts = SuccessOptions(
        per_robot={
            "pr2": {"no_personal_space_intrusion": ConditionOption(required=False, reason=reason)}
        }
    )
    rec = make_record(
        seg((0, 0), (10, 0), 100),
        people=people,
        meta={"robot": "pr2", "success_options": opts.model_dump()},
    )
    cond = {c.name: c for c in success_conditions(rec)}
    assert not cond["no_personal_space_intrusion"].passed
    assert not cond["no_personal_space_intrusion"].required
    assert cond["no_personal_space_intrusion"].reason == reason
    assert evaluate_success(rec)["success"]
    # the same scene for another robot: the override is per robot, so it is required again
    other = make_record(
        seg((0, 0), (10, 0), 100),
        people=people,
        meta={"robot": "pioneer", "success_options": opts.model_dump()},
    )
    assert not evaluate_success(other)["success"]


@pytest.mark.parametrize("family", ["mixed"])
def test_mixed_family_uses_the_structure_conditions(make_record, seg, family):
    from socialnav.core.scene import Queue

    queue = Queue(member_ids=(0, 1), service_point=(0.0, 0.9))
    rec = make_record(
        seg((3, -3), (0.0, -1.6), 40),
        yaw=np.pi / 2,
        people=[[0.0, 0.0], [0.0, -0.8]],
        queues=(queue,),
        family=family,
        target=(0.0, -1.6, np.pi / 2),
    )
    names = {c.name for c in success_conditions(rec)}
    assert {"at_tail_slot", "facing_line", "no_cut_in"} <= names

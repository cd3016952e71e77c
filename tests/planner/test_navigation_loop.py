"""A minimal kinematic loop (integrate the commanded twist; no simulator) through the Navigator."""

from __future__ import annotations

import logging

import numpy as np
import pytest
from _planner_helpers import collides, step_pose, world

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.local_planner import PlannerStatus, traditional_planner
from socialnav.planner.navigator import Navigator
from socialnav.planner.recovery import RecoveringPlanner, RecoveryParams


def drive(
    robot: RobotModel,
    segments,
    start,
    goal,
    steps: int,
    polygons=(),
    window=10.0,
    recovery=None,
    width=8.0,
    height=4.0,
):
    cm, occ = world(width, height, segments, robot, polygons=polygons)
    planner = RecoveringPlanner(traditional_planner(robot), recovery)
    nav = Navigator(robot, planner, cm, np.asarray(goal, dtype=float), window_size=window)
    pose = np.asarray(start, dtype=float)
    vel = np.zeros(3)
    statuses = []
    for k in range(steps):
        res = nav.step(0.1 * k, pose, vel, SocialContext())
        statuses.append(res.status)
        assert np.all(np.isfinite(res.cmd))
        if res.status in (PlannerStatus.GOAL_REACHED, PlannerStatus.STUCK):
            break
        vel = res.cmd
        pose = step_pose(pose, vel)
        assert not collides(pose, robot, occ, cm.geometry), f"collision at step {k}: {pose}"
    return pose, statuses


CORRIDOR = [[[0.0, 0.5], [8.0, 0.5]], [[0.0, 3.5], [8.0, 3.5]]]


@pytest.mark.parametrize("robot", [PR2, PIONEER])
def test_corridor_to_goal(robot):
    pose, statuses = drive(robot, CORRIDOR, (1.0, 2.0, 0.0), (6.5, 2.0, 0.0), 400)
    assert statuses[-1] == PlannerStatus.GOAL_REACHED
    assert np.hypot(pose[0] - 6.5, pose[1] - 2.0) <= 0.1 + 1e-9
    assert abs(pose[2]) <= 0.1 + 1e-9


def test_around_a_box():
    box = [np.array([[3.4, 1.4], [4.6, 1.4], [4.6, 2.6], [3.4, 2.6]])]
    pose, statuses = drive(PIONEER, CORRIDOR, (1.0, 2.0, 0.0), (6.5, 2.0, 0.0), 500, polygons=box)
    assert statuses[-1] == PlannerStatus.GOAL_REACHED
    assert np.hypot(pose[0] - 6.5, pose[1] - 2.0) <= 0.1 + 1e-9


def test_walled_off_goal_is_replaced_by_a_reachable_point_not_driven_at():
    # The goal sits in a pocket walled off from the corridor. With a 3 m local window the pocket
    # is out of sight at first. navfn default_tolerance (1 m): the substitute is the nearest
    # point reachable from the robot, on the near side of the wall, and the robot stops there.
    walls = [*CORRIDOR, [[5.0, 0.5], [5.0, 3.5]], [[5.8, 0.5], [5.8, 3.5]]]
    pose, statuses = drive(
        PR2,
        walls,
        (1.0, 2.0, 0.0),
        (5.4, 2.0, 0.0),
        400,
        window=3.0,
        recovery=RecoveryParams(movement_time_allowance=5.0, controller_patience=8.0),
    )
    assert statuses[-1] == PlannerStatus.GOAL_REACHED
    assert 4.2 < pose[0] < 4.95


class _Goal:
    def __init__(self, pose, is_waypoint):
        self.pose = np.asarray(pose, dtype=float)
        self.is_waypoint = is_waypoint
        self.position_tolerance = 0.2
        self.yaw_tolerance = 0.2


def test_waypoint_social_goal_is_visited_first_then_the_given_goal():
    cm, _ = world(8.0, 4.0, CORRIDOR, PR2)
    waypoint = _Goal((3.5, 2.8, 0.0), True)
    nav = Navigator(
        PR2,
        RecoveringPlanner(traditional_planner(PR2)),
        cm,
        np.array([6.5, 2.0, 0.0]),
        social_goal_fn=lambda s, g, p: waypoint,
    )
    pose, vel = np.array([1.0, 2.0, 0.0]), np.zeros(3)
    closest = np.inf
    for k in range(500):
        res = nav.step(0.1 * k, pose, vel, SocialContext())
        if res.status == PlannerStatus.GOAL_REACHED:
            break
        vel = res.cmd
        pose = step_pose(pose, vel)
        closest = min(closest, np.hypot(*(pose[:2] - waypoint.pose[:2])))
    assert res.status == PlannerStatus.GOAL_REACHED
    assert closest <= 0.2 + 1e-9
    assert np.hypot(pose[0] - 6.5, pose[1] - 2.0) <= 0.1 + 1e-9


def test_navigator_step_never_raises():
    cm, _ = world(8.0, 4.0, CORRIDOR, PR2)

    def broken(social, goal, pose):
        raise RuntimeError("perception failed")

    nav = Navigator(
        PR2, traditional_planner(PR2), cm, np.array([6.5, 2.0, 0.0]), social_goal_fn=broken
    )
    res = nav.step(0.0, np.array([1.0, 2.0, 0.0]), np.zeros(3), SocialContext())
    assert res.status == PlannerStatus.INVALID_INPUT and "perception failed" in res.message
    nav = Navigator(PR2, traditional_planner(PR2), cm, np.array([6.5, 2.0, 0.0]))
    res = nav.step(0.0, np.array([np.nan, 2.0, 0.0]), np.zeros(3), SocialContext())
    assert res.status == PlannerStatus.INVALID_INPUT and np.all(res.cmd == 0)
    res = nav.step(0.0, np.array([1.0, 2.0, 0.0]), np.zeros(3), SocialContext())
    assert res.status == PlannerStatus.OK


def test_an_internal_failure_is_said_so_and_logged_once_per_kind(caplog):
    # A failure inside the step is not the input's: the status stays INVALID_INPUT (the loop
    # must go on), but the message says "internal error" and the traceback is logged once.
    cm, _ = world(8.0, 4.0, CORRIDOR, PR2)
    calls = []

    def broken(social, goal, pose):
        calls.append(1)
        raise RuntimeError(f"perception failed at {len(calls)}")  # one line, varying texts

    nav = Navigator(
        PR2, traditional_planner(PR2), cm, np.array([6.5, 2.0, 0.0]), social_goal_fn=broken
    )
    with caplog.at_level(logging.ERROR, logger="socialnav.planner.navigator"):
        for k in range(3):
            res = nav.step(0.1 * k, np.array([1.0, 2.0, 0.0]), np.zeros(3), SocialContext())
            assert res.status == PlannerStatus.INVALID_INPUT and np.all(res.cmd == 0)
            assert res.message == f"internal error, RuntimeError: perception failed at {k + 1}"
    assert len(calls) == 3
    records = [r for r in caplog.records if r.name == "socialnav.planner.navigator"]
    assert len(records) == 1 and records[0].exc_info is not None
    assert "perception failed at 1" in records[0].getMessage()
    nav.reset()  # a new episode logs again
    with caplog.at_level(logging.ERROR, logger="socialnav.planner.navigator"):
        nav.step(0.0, np.array([1.0, 2.0, 0.0]), np.zeros(3), SocialContext())
    assert len([r for r in caplog.records if r.name == "socialnav.planner.navigator"]) == 2


def test_an_input_error_raised_inside_the_step_is_not_called_internal(caplog):
    cm, _ = world(8.0, 4.0, CORRIDOR, PR2)

    def refuses(social, goal, pose):
        raise InvalidInputError("person 4: a group member far from the others")

    nav = Navigator(
        PR2, traditional_planner(PR2), cm, np.array([6.5, 2.0, 0.0]), social_goal_fn=refuses
    )
    with caplog.at_level(logging.ERROR, logger="socialnav.planner.navigator"):
        res = nav.step(0.0, np.array([1.0, 2.0, 0.0]), np.zeros(3), SocialContext())
    assert res.status == PlannerStatus.INVALID_INPUT
    assert res.message == "InvalidInputError: person 4: a group member far from the others"
    assert not [r for r in caplog.records if r.name == "socialnav.planner.navigator"]


@pytest.mark.parametrize(
    ("time", "pose", "velocity", "field"),
    [
        ("abc", (1.0, 2.0, 0.0), (0.0, 0.0, 0.0), "time"),
        (0.0, "1,0,0", (0.0, 0.0, 0.0), "pose"),
        (0.0, (1.0, 2.0, 0.0), "fast", "velocity"),
        (None, (1.0, 2.0, 0.0), (0.0, 0.0, 0.0), "time"),
    ],
)
def test_input_of_the_wrong_type_is_named_not_an_internal_error(
    time, pose, velocity, field, caplog
):
    cm, _ = world(8.0, 4.0, CORRIDOR, PR2)
    nav = Navigator(PR2, traditional_planner(PR2), cm, np.array([6.5, 2.0, 0.0]))
    with caplog.at_level(logging.ERROR, logger="socialnav.planner.navigator"):
        res = nav.step(time, pose, velocity, SocialContext())
    assert res.status == PlannerStatus.INVALID_INPUT and np.all(res.cmd == 0)
    assert res.message.startswith(f"{field} must be"), res.message
    assert not caplog.records


def test_a_layer_failing_a_deferred_replan_is_logged_and_the_plan_kept(caplog):
    # Deferred replanning (the ROS node's default) keeps the current plan when a replan
    # fails; that failure, too, is a defect to hear about.
    cm, _ = world(8.0, 4.0, CORRIDOR, PR2)
    plans = []

    def layer(costmap, social, partners=None):
        plans.append(1)
        if len(plans) > 1:
            raise ConfigurationError("sigma must be > 0")
        return costmap

    nav = Navigator(
        PR2,
        traditional_planner(PR2),
        cm,
        np.array([6.5, 2.0, 0.0]),
        global_layer=layer,
        replan_mode="deferred",
        replan_period=0.5,
    )
    pose, vel = np.array([1.0, 2.0, 0.0]), np.zeros(3)
    with caplog.at_level(logging.ERROR, logger="socialnav.planner.navigator"):
        for k in range(30):
            res = nav.step(0.1 * k, pose, vel, SocialContext())
            assert res.status == PlannerStatus.OK, res.message
            vel = res.cmd
            pose = step_pose(pose, vel)
    assert len(plans) > 2 and "replan failed: ConfigurationError" in nav.last_plan_status
    records = [r for r in caplog.records if r.name == "socialnav.planner.navigator"]
    assert len(records) == 1 and "deferred replan" in records[0].getMessage()

"""Objectives, the local planner's statuses and goal handling, oscillation, recovery."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest
from _planner_helpers import blank, context, straight, world

from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import PIONEER, PR2
from socialnav.moo.selection import WeightedSum
from socialnav.planner.critics import (
    Critic,
    CriticScore,
    CriticUnavailable,
    GoalDistanceCritic,
    OccupancyCritic,
    PathDistanceCritic,
)
from socialnav.planner.local_planner import (
    LocalPlanner,
    LocalPlannerParams,
    OscillationGuard,
    PlannerStatus,
    traditional_objectives,
    traditional_planner,
)
from socialnav.planner.objectives import Objective, evaluate
from socialnav.planner.recovery import RecoveringPlanner, RecoveryParams, clearance
from socialnav.world.grid import LETHAL, Costmap


@dataclass(frozen=True)
class _Fixed(Critic):
    """Test critic: cost = column ``col`` of the end point; illegal where x > ``limit``."""

    name: ClassVar[str] = "fixed"
    unit: ClassVar[str] = "m"
    col: int = 0
    limit: float = np.inf

    def score(self, trajs, ctx):
        end = trajs.poses[:, -1]
        return CriticScore(end[:, self.col].copy(), {"too_far": end[:, 0] > self.limit})


@dataclass(frozen=True)
class _Unavailable(Critic):
    name: ClassVar[str] = "unavailable"
    unit: ClassVar[str] = "-"

    def prepare(self, ctx):
        raise CriticUnavailable("nothing to score")

    def score(self, trajs, ctx):  # pragma: no cover - never reached
        raise AssertionError


def _ctx():
    cm = blank(80, 80)
    return context(
        cm, PR2, pose=(2.0, 2.0, 0.0), path=np.array([[2.0, 2.0], [3.5, 2.0]]), goal=(3.5, 2.0, 0.0)
    )


def test_objective_matrix_legal_mask_and_rejections():
    tr = straight(np.array([[1.0, 3.0], [2.0, 1.0], [3.0, 2.0]]), start=(0.0, 0.0))
    objs = (
        Objective("a", ((_Fixed(0, limit=2.5), 2.0), (_Fixed(1), 1.0))),
        Objective("b", ((_Fixed(1), 3.0),)),
    )
    ev = evaluate(objs, tr, _ctx())
    assert ev.names == ("a", "b")
    np.testing.assert_allclose(ev.F[:2], [[5.0, 9.0], [5.0, 3.0]])
    assert np.all(np.isinf(ev.F[2]))
    assert ev.legal.tolist() == [True, True, False]
    assert ev.rejected[("fixed", "too_far")] == 1
    assert set(ev.raw) == {"fixed", "fixed#2"}  # two parameterizations of one kind


def test_objective_rejects_bad_terms():
    with pytest.raises(ConfigurationError):
        Objective("x", ())
    with pytest.raises(ConfigurationError):
        Objective("x", ((_Fixed(), -1.0),))


def test_weighted_sum_over_one_objective_is_argmin_parity():
    cm, _ = world(6.0, 4.0, [[[3.0, 0.0], [3.0, 2.2]]], PR2)
    ctx = context(
        cm,
        PR2,
        pose=(1.5, 1.0, 0.3),
        velocity=(0.2, 0.0, 0.1),
        path=np.array([[1.5, 1.0], [2.5, 3.0], [5.0, 3.0]]),
        goal=(5.0, 3.0, 0.0),
    )
    planner = traditional_planner(PR2)
    res = planner.plan(ctx, record=True)
    rec = res.record
    assert res.status == PlannerStatus.OK and rec is not None
    manual = np.where(rec.legal, rec.F[:, 0], np.inf)
    assert rec.chosen == int(np.argmin(manual))
    np.testing.assert_array_equal(res.cmd, rec.twists[rec.chosen])
    # F is exactly Σ bias · raw of the navigation terms
    p = LocalPlannerParams()
    expected = (
        p.path_distance_bias * rec.raw["path_distance"]
        + p.goal_distance_bias * rec.raw["goal_distance"]
        + p.occdist_scale * rec.raw["occupancy"]
        + p.heading_scale * rec.raw["heading"]
    )
    np.testing.assert_allclose(rec.F[rec.legal, 0], expected[rec.legal])
    assert rec.num_samples == rec.twists.shape[0] > 100
    assert {"sample", "rollout", "select", "total"} <= set(rec.timing)
    assert "legal" in rec.rejection_summary()


def test_invalid_input_and_empty_path_are_statuses():
    planner = traditional_planner(PR2)
    ctx = _ctx()
    bad = context(ctx.costmap, PR2, pose=(np.nan, 2.0, 0.0), path=ctx.global_path, goal=ctx.goal)
    assert planner.plan(bad).status == PlannerStatus.INVALID_INPUT
    empty = context(ctx.costmap, PR2, pose=(2.0, 2.0, 0.0), path=np.zeros((0, 2)), goal=ctx.goal)
    res = planner.plan(empty, record=True)
    assert res.status == PlannerStatus.NO_PATH and np.all(res.cmd == 0)
    assert res.record is not None and res.record.status == "NO_PATH"


def test_critic_unavailable_is_a_status():
    planner = LocalPlanner(PR2, (Objective("x", ((_Unavailable(), 1.0),)),), WeightedSum([1.0]))
    res = planner.plan(_ctx())
    assert res.status == PlannerStatus.CRITIC_UNAVAILABLE and np.all(res.cmd == 0)


def test_no_legal_trajectory_gives_zero_command():
    cm = blank(80, 80)
    costs = cm.costs.copy()
    costs[:] = LETHAL
    costs[38:42, 38:42] = 0  # the robot stands in a hole
    ctx = context(
        Costmap(costs, cm.geometry),
        PR2,
        pose=(2.0, 2.0, 0.0),
        path=np.array([[2.0, 2.0], [3.5, 2.0]]),
        goal=(3.5, 2.0, 0.0),
    )
    res = traditional_planner(PR2).plan(ctx, record=True)
    assert res.status == PlannerStatus.NO_LEGAL_TRAJECTORY and np.all(res.cmd == 0)
    assert res.record.rejected[("occupancy", "collision")] == res.record.num_samples


def test_goal_handling_stop_rotate_reached():
    planner = traditional_planner(PIONEER)
    cm = blank(80, 80)
    goal = (2.0, 2.0, 1.0)
    kw = {"path": np.array([[2.0, 2.0]]), "goal": goal}
    # within xy tolerance but moving: brake
    r = planner.plan(context(cm, PIONEER, pose=(2.05, 2.0, 0.0), velocity=(0.4, 0, 0), **kw))
    assert r.status == PlannerStatus.ROTATING_TO_GOAL and 0 <= r.cmd[0] < 0.4
    # stopped: rotate toward the goal yaw (+)
    r = planner.plan(context(cm, PIONEER, pose=(2.05, 2.0, 0.0), **kw))
    assert r.status == PlannerStatus.ROTATING_TO_GOAL and r.cmd[2] > 0 and r.cmd[0] == 0
    # latched: a little drift outside the tolerance still rotates
    r = planner.plan(context(cm, PIONEER, pose=(2.15, 2.0, 0.5), **kw))
    assert r.status == PlannerStatus.ROTATING_TO_GOAL
    r = planner.plan(context(cm, PIONEER, pose=(2.15, 2.0, 0.95), **kw))
    assert r.status == PlannerStatus.GOAL_REACHED and np.all(r.cmd == 0)


def _drive_in_cmd(robot, align: bool, yaw: float) -> np.ndarray:
    """The command 0.4 m short of a goal at (2.4, 2.0, ``yaw``), driving in at 0.3 m/s."""
    params = LocalPlannerParams(stop_at_goal=True, heading_goal_align=align)
    path = np.array([[2.0, 2.0], [2.4, 2.0]])
    ctx = context(
        blank(80, 80),
        robot,
        pose=(2.0, 2.0, 0.0),
        velocity=(0.3, 0, 0),
        path=path,
        goal=(2.4, 2.0, yaw),
    )
    r = traditional_planner(robot, params).plan(ctx)
    assert r.status == PlannerStatus.OK and r.cmd[0] > 0.0
    return r.cmd


def test_goal_align_turns_a_holonomic_base_toward_the_goal_yaw_while_driving_in():
    # The goal faces 90° left or right of the travel. With heading_goal_align the PR2 drives in
    # turning toward the goal's yaw at the most the dynamic window allows (acc_lim_theta ×
    # period); without, the goal's yaw does not change its command.
    window = PR2.acc_lim_theta * LocalPlannerParams().controller_period
    np.testing.assert_array_equal(
        _drive_in_cmd(PR2, False, np.pi / 2), _drive_in_cmd(PR2, False, -np.pi / 2)
    )
    assert _drive_in_cmd(PR2, True, np.pi / 2)[2] == pytest.approx(window, abs=0.02)
    assert _drive_in_cmd(PR2, True, -np.pi / 2)[2] == pytest.approx(-window, abs=0.02)


def test_goal_align_leaves_a_differential_drive_to_turn_in_place_at_the_goal():
    # A differential drive can only turn on the way in by bending its path (module docstring
    # of critics.heading): the goal's yaw does not change its command.
    for align in (False, True):
        np.testing.assert_array_equal(
            _drive_in_cmd(PIONEER, align, np.pi / 2), _drive_in_cmd(PIONEER, align, -np.pi / 2)
        )


def test_oscillation_guard_locks_the_reversed_axis_until_moved():
    g = OscillationGuard(0.05, 0.2)
    pose = np.zeros(3)
    g.update(pose, np.array([0.3, 0.0, 0.0]), 0.05)
    assert not g.illegal(np.array([[-0.1, 0, 0]])).any()
    g.update(pose, np.array([-0.1, 0.0, 0.0]), 0.05)  # reversal: now backward only
    assert g.illegal(np.array([[0.2, 0, 0], [-0.1, 0, 0]])).tolist() == [True, False]
    g.update(np.array([0.01, 0, 0]), np.array([-0.1, 0.0, 0.0]), 0.05)
    assert g.illegal(np.array([[0.2, 0, 0]])).all()
    g.update(np.array([0.06, 0, 0]), np.array([-0.1, 0.0, 0.0]), 0.05)  # moved 6 cm: free
    assert not g.illegal(np.array([[0.2, 0, 0]])).any()


def test_params_validation():
    with pytest.raises(ConfigurationError):
        LocalPlannerParams(sim_time=0.0)
    with pytest.raises(ConfigurationError):
        LocalPlannerParams(vx_samples=0)
    objs = traditional_objectives()
    assert [type(c) for c, _ in objs[0].terms][:3] == [
        PathDistanceCritic,
        GoalDistanceCritic,
        OccupancyCritic,
    ]


@pytest.mark.parametrize(
    "name", ["latch_xy_goal_tolerance", "stop_at_goal", "heading_goal_align", "footprint_check"]
)
@pytest.mark.parametrize("value", ["no", "False", 1, 0, None])
def test_bool_params_refuse_other_types(name, value):
    # "no" used to switch heading_goal_align on (newcomer trial): a truthy string.
    with pytest.raises(ConfigurationError, match=name):
        LocalPlannerParams(**{name: value})
    # NumPy's bool is a bool, stored as Python's (a NumPy bool broke the ROS parameter table)
    assert getattr(LocalPlannerParams(**{name: np.bool_(True)}), name) is True


def test_clearance_rays():
    cm = blank(80, 80)
    costs = cm.costs.copy()
    costs[:, 60] = LETHAL  # wall at x = 3.0
    ctx = context(Costmap(costs, cm.geometry), PR2, pose=(2.0, 2.0, 0.0))
    d = clearance(ctx, np.array([0.0, np.pi]), 1.5)
    assert d[0] == pytest.approx(0.95, abs=0.06) and d[1] == pytest.approx(1.5)


def test_recovery_then_stuck_when_boxed_in():
    cm, _ = world(
        4.0,
        4.0,
        [
            [[1.4, 1.4], [2.6, 1.4]],
            [[2.6, 1.4], [2.6, 2.6]],
            [[2.6, 2.6], [1.4, 2.6]],
            [[1.4, 2.6], [1.4, 1.4]],
        ],
        PIONEER,
    )
    planner = RecoveringPlanner(
        traditional_planner(PIONEER),
        RecoveryParams(movement_time_allowance=3.0, controller_patience=5.0, max_recoveries=3),
    )
    pose = np.array([2.0, 2.0, 0.0])
    seen = []
    for k in range(80):
        ctx = context(
            cm,
            PIONEER,
            pose=pose,
            path=np.array([[2.0, 2.0], [3.5, 2.0]]),
            goal=(3.5, 2.0, 0.0),
            time=0.1 * k,
        )
        res = planner.plan(ctx)
        seen.append(res.status)
        pose = pose + 0.1 * np.array(
            [np.cos(pose[2]) * res.cmd[0], np.sin(pose[2]) * res.cmd[0], res.cmd[2]]
        )
    assert PlannerStatus.RECOVERING in seen
    assert seen[-1] == PlannerStatus.STUCK
    assert np.hypot(pose[0] - 2.0, pose[1] - 2.0) < 0.3
    # STUCK is a status, not a latch: once the box is gone the planner drives on at once.
    open_map, _ = world(4.0, 4.0, [], PIONEER)
    ctx = context(
        open_map,
        PIONEER,
        pose=pose,
        path=np.array([pose[:2], [3.5, 2.0]]),
        goal=(3.5, 2.0, 0.0),
        time=8.1,
    )
    assert planner.plan(ctx).status == PlannerStatus.OK

"""Episodes on navground: scripted humans, recording, collisions, determinism, baselines."""

from __future__ import annotations

import numpy as np
import pytest

from socialnav.core.robot import PIONEER, PR2
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.sim.baselines import GoToGoalController
from socialnav.sim.controller import GOAL_REACHED
from socialnav.sim.engine import ControllerBehavior, build_world
from socialnav.sim.recorder import StaticGeometry, person_collisions
from socialnav.sim.runner import run_episode
from socialnav.sim.scenario import Scenario, load_scenario


class ConstantTwist:
    """Test controller: the same body twist forever."""

    def __init__(self, cmd: tuple[float, float, float]) -> None:
        self.cmd = np.asarray(cmd, dtype=float)
        self.seen: list[tuple[float, np.ndarray, np.ndarray, int]] = []

    def reset(self, scenario, robot) -> None:
        self.seen.clear()

    def step(self, time, pose, velocity, social) -> PlannerResult:
        self.seen.append((time, pose.copy(), velocity.copy(), len(social.people)))
        return PlannerResult(self.cmd.copy(), PlannerStatus.OK)


def corridor(people: list[dict], start=(1.0, 0.0, 0.0), goal=(19.0, 0.0, 0.0), **kw) -> Scenario:
    return Scenario.model_validate(
        {
            "name": "test",
            "family": "hallway",
            "map": {"walls": [[[0, -1.5], [20, -1.5]], [[0, 1.5], [20, 1.5]]]},
            "start": start,
            "goal": goal,
            "people": people,
            **kw,
        }
    )


def test_scripted_walker_moves_at_its_speed_in_a_straight_line() -> None:
    scn = corridor(
        [
            {
                "id": 1,
                "position": [5.0, 0.2],
                "behavior": {"type": "walk", "speed": 0.25, "heading": 0.0, "until": [6.0, 0.2]},
            }
        ]
    )
    behavior = ControllerBehavior()  # no controller: the robot stands still
    simw = build_world(scn, PR2, behavior)
    xs, vs = [], []
    for _ in range(60):
        pos, vel, yaw = simw.people_state()
        xs.append(pos[0].copy())
        vs.append(vel[0].copy())
        simw.world.update(0.1)
    xs, vs = np.array(xs), np.array(vs)
    t = np.arange(60) * 0.1
    walking = t <= 4.0
    np.testing.assert_allclose(xs[walking, 0], 5.0 + 0.25 * t[walking], atol=1e-5)
    np.testing.assert_allclose(xs[:, 1], 0.2, atol=1e-6)
    np.testing.assert_allclose(xs[~walking, 0], 6.0, atol=1e-5)  # stopped at the end point
    np.testing.assert_allclose(vs[1:40], [[0.25, 0.0]] * 39, atol=1e-6)
    np.testing.assert_allclose(vs[45:], 0.0, atol=1e-9)
    np.testing.assert_allclose(yaw, 0.0)
    np.testing.assert_allclose(simw.robot.position, [1.0, 0.0])


def test_go_to_goal_episode_records_consistent_shapes() -> None:
    res = run_episode(
        "hallway_stationary", GoToGoalController(), "pr2", seed=0, record_diagnostics=True
    )
    rec = res.record
    t = rec.num_steps
    assert rec.meta["termination"] == "goal_reached"
    assert rec.status[-1] == GOAL_REACHED
    assert np.linalg.norm(rec.robot_poses[-1, :2] - [19.0, 0.0]) <= 0.1
    assert rec.robot_poses.shape == (t, 3) and rec.robot_twists.shape == (t, 3)
    assert rec.people_positions.shape == (t, 1, 2) and rec.people_velocities.shape == (t, 1, 2)
    assert len(res.diagnostics) == t
    np.testing.assert_allclose(rec.times, np.arange(t) * 0.1)
    np.testing.assert_allclose(rec.robot_poses[0], [1.0, 0.0, 0.0])
    # Commands act over one period: consecutive poses follow the recorded body twists.
    step = np.linalg.norm(np.diff(rec.robot_xy, axis=0), axis=1)
    np.testing.assert_allclose(
        step, np.linalg.norm(rec.robot_twists[:-1, :2], axis=1) * 0.1, atol=1e-5
    )
    assert np.all(rec.robot_twists[:, 0] <= PR2.max_vel_x + 1e-9)
    np.testing.assert_allclose(rec.people_positions[:, 0], [[10.0, 0.2]] * t, atol=1e-6)
    assert rec.scenario == "hallway_stationary" and rec.family == "hallway"
    np.testing.assert_allclose(rec.target, rec.goal)  # no social goal in a hallway
    assert rec.walls.shape == (4, 2, 2)  # two long walls and two end caps
    assert rec.meta["planner"] == "GoToGoalController" and rec.meta["robot"] == "pr2"
    # how fast it can brake, for the crowd metrics (metrics.crowd.robot_limits)
    assert rec.meta["acc_lim"] == [2.5, 2.5, 3.2] and rec.meta["max_vel"] == [0.55, 0.3, 1.0]
    # It drives straight through the person: flagged, and only near x = 10.
    hit = rec.collision_person
    assert hit.any() and not rec.collision_obstacle.any()
    assert np.all(np.abs(rec.robot_poses[hit, 0] - 10.0) < 0.325 + 0.25 + 1e-6)


@pytest.mark.parametrize(("offset", "expected"), [(0.5, True), (0.65, False)])
def test_person_collision_uses_the_footprint_not_the_disc(offset: float, expected: bool) -> None:
    # PR2 half-width 0.325 + person 0.25 = 0.575; the circumscribed disc would reach 0.71.
    scn = corridor([{"id": 7, "position": [5.0, offset]}], goal=(9.0, 0.0, 0.0))
    rec = run_episode(scn, ConstantTwist((0.5, 0.0, 0.0)), PR2).record
    assert bool(rec.collision_person.any()) is expected
    assert rec.meta["termination"] == "time_limit" and rec.num_steps == 601


def test_wall_collision_flagged() -> None:
    scn = corridor([], start=(2.0, 0.0, 0.0))
    rec = run_episode(scn, ConstantTwist((0.0, 0.3, 0.0)), PR2).record
    y = rec.robot_poses[:, 1]
    # Kinematic simulation: the robot passes through; it touches while the footprint straddles.
    straddles = (y + 0.325 >= 1.5 - 1e-6) & (y - 0.325 <= 1.5 + 1e-6)
    np.testing.assert_array_equal(rec.collision_obstacle, straddles)
    assert rec.collision_obstacle.any() and not rec.collision_person.any()


def test_static_geometry_desk_and_disc() -> None:
    s = load_scenario("queue_line")
    static = StaticGeometry(
        s.walls_array(), tuple(s.obstacle_polygons()), np.array([[3.0, 3.0, 0.5]])
    )
    square = PR2.polygon

    def at(x: float, y: float) -> np.ndarray:
        return square + np.array([x, y])

    assert static.collides(at(12.5, 19.8))  # overlaps the desk front (y = 20.0)
    assert not static.collides(at(12.5, 19.6))
    assert static.collides(at(12.5, 20.3))  # inside the desk
    assert static.collides(at(3.7, 3.0)) and not static.collides(at(3.9, 3.0))
    # The early "no" (bounding disc) never changes the answer.
    radius = PR2.circumscribed_radius
    for x in np.linspace(2.0, 14.0, 41):
        for y in np.linspace(2.0, 21.0, 39):
            fp = at(x, y)
            assert static.collides(fp, np.array([x, y]), radius) == static.collides(fp)
    assert person_collisions(square, np.array([[0.0, 0.0]]), np.array([0.25]))
    assert not person_collisions(square, np.zeros((0, 2)), np.zeros(0))


def test_pioneer_never_moves_sideways() -> None:
    ctrl = ConstantTwist((0.4, 0.3, 0.5))  # asks for lateral motion: clipped to 0
    rec = run_episode(corridor([], start=(5.0, 0.0, 0.0)), ctrl, PIONEER).record
    assert np.all(rec.robot_twists[:, 1] == 0.0)
    np.testing.assert_allclose(rec.robot_twists[0], [0.4, 0.0, 0.5])
    # The body velocity the controller sees is the previous command.
    np.testing.assert_allclose(ctrl.seen[3][2], [0.4, 0.0, 0.5], atol=1e-5)
    heading = np.arctan2(*np.diff(rec.robot_xy[:20], axis=0).T[::-1])
    np.testing.assert_allclose(np.cos(heading - rec.robot_poses[:19, 2] - 0.025), 1.0, atol=1e-3)


def test_same_seed_identical_record_and_seeds_differ() -> None:
    a = run_episode("hallway_passing", "go_to_goal", "pioneer", seed=3).record
    b = run_episode("hallway_passing", "go_to_goal", "pioneer", seed=3).record
    c = run_episode("hallway_passing", "go_to_goal", "pioneer", seed=4).record
    for name in (
        "times",
        "robot_poses",
        "robot_twists",
        "people_positions",
        "people_velocities",
        "collision_person",
        "status",
    ):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.meta == b.meta
    assert not np.array_equal(a.people_positions[0], c.people_positions[0])


def test_controller_sees_ground_truth_social_context() -> None:
    ctrl = ConstantTwist((0.0, 0.0, 0.0))
    run_episode("group_join", ctrl, "pr2")
    assert [s[3] for s in ctrl.seen[:3]] == [3, 3, 3]
    np.testing.assert_allclose([s[0] for s in ctrl.seen[:3]], [0.0, 0.1, 0.2])


def test_navground_orca_baseline_runs() -> None:
    res = run_episode("hallway_stationary", "orca", "pr2", record_diagnostics=True)
    rec = res.record
    assert rec.meta["planner"] == "orca"
    assert rec.meta["termination"] == "goal_reached"
    assert np.linalg.norm(rec.robot_xy[-1] - rec.target[:2]) <= rec.goal_tolerance
    assert not rec.collision_person.any()  # ORCA sees the person as a neighbour
    assert rec.robot_twists[:, 0].max() <= PR2.max_vel_x + 1e-5


def test_social_goal_is_the_target() -> None:
    rec = run_episode("queue_line", "orca", "pioneer").record
    assert rec.meta["social_goal"] == "queue_tail"
    assert not np.allclose(rec.target[:2], rec.goal[:2])
    rec = run_episode("gallery_activity", ConstantTwist((0, 0, 0)), "pr2").record
    assert rec.waypoint is not None and rec.waypoint.shape == (2,)
    np.testing.assert_allclose(rec.target, rec.goal)


def test_reactive_humans_react() -> None:
    # A reactive walker heading at a robot standing in its way deviates; a scripted one doesn't.
    ppl = [
        {
            "id": 1,
            "position": [8.0, 0.0],
            "behavior": {"type": "walk", "velocity": [-1.0, 0.0], "until": [1.0, 0.0]},
        }
    ]
    scn = corridor(ppl, start=(4.0, 0.0, 0.0), time_limit=6.0)
    still = ConstantTwist((0.0, 0.0, 0.0))
    scripted = run_episode(scn, still, "pr2").record
    reactive = run_episode(scn, still, "pr2", humans="reactive").record
    assert scripted.collision_person.any()
    assert np.abs(scripted.people_positions[:, 0, 1]).max() < 1e-6
    assert np.abs(reactive.people_positions[:, 0, 1]).max() > 0.2
    assert not reactive.collision_person.any()
    assert reactive.meta["humans"] == "reactive"

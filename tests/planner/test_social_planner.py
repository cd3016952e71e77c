"""The social planner's headline behaviour, planner level (no simulator for the passing test).

A static person stands 0.2 m off the centreline of a 12 m × 3 m corridor at x = 6. The PaCcET
planner (preset ``paccet``) must pass with at least 1.2 m (the paper's personal-space radius,
centre to centre) between robot and person; the traditional planner (navigation cost only)
does not. Both reach the goal without touching a wall or the person. The loop integrates the
commanded body twist exactly (``step_pose``), so the result is the planner's alone.
"""

from __future__ import annotations

import numpy as np
import pytest
from _planner_helpers import collides, step_pose, world
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.geometry import body_to_world, signed_distance_to_polygon
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.local_planner import PlannerStatus
from socialnav.planner.presets import build_navigator

PERSONAL_SPACE = 1.2
LENGTH, WIDTH = 12.0, 3.0
CENTRE_Y = WIDTH / 2
PERSON = np.array([6.0, CENTRE_Y + 0.2])
START = (1.0, CENTRE_Y, 0.0)
GOAL = np.array([11.0, CENTRE_Y, 0.0])
GOAL_TOLERANCE = 0.1  # LocalPlannerParams.xy_goal_tolerance
CORRIDOR = [
    [[0.0, 0.0], [LENGTH, 0.0]],
    [[0.0, WIDTH], [LENGTH, WIDTH]],
    [[0.0, 0.0], [0.0, WIDTH]],
    [[LENGTH, 0.0], [LENGTH, WIDTH]],
]
SOCIAL = SocialContext(people=(Person(1, (float(PERSON[0]), float(PERSON[1])), yaw=np.pi),))


def drive(preset: str, robot: RobotModel, max_steps: int = 600) -> dict:
    """Run the navigator of ``preset`` until GOAL_REACHED with a zero command (or STUCK)."""
    costmap, occupied = world(LENGTH, WIDTH, CORRIDOR, robot)
    nav = build_navigator(preset, robot, costmap, GOAL, SOCIAL)
    pose, vel = np.array(START, dtype=float), np.zeros(3)
    centre_dist, edge_dist, wall_hits, cmds, xy = [], [], 0, [], []
    status = None
    for k in range(max_steps):
        result = nav.step(0.1 * k, pose, vel, SOCIAL)
        status = result.status
        cmds.append(result.cmd.copy())
        if status == PlannerStatus.STUCK or (
            status == PlannerStatus.GOAL_REACHED and np.all(np.abs(result.cmd) < 1e-3)
        ):
            break
        vel = result.cmd
        pose = step_pose(pose, vel)
        footprint = body_to_world(robot.polygon, pose)
        xy.append(pose[:2].copy())
        centre_dist.append(float(np.hypot(*(pose[:2] - PERSON))))
        edge_dist.append(float(signed_distance_to_polygon(PERSON, footprint)))
        wall_hits += collides(pose, robot, occupied, costmap.geometry)
    return {
        "status": status,
        "pose": pose,
        "min_centre": min(centre_dist),
        "min_edge": min(edge_dist),
        "wall_hits": wall_hits,
        "cmds": np.array(cmds),
        "xy": np.array(xy),
    }


@pytest.fixture(scope="module")
def runs() -> dict[tuple[str, str], dict]:
    return {
        (preset, robot.name): drive(preset, robot)
        for preset in ("paccet", "traditional")
        for robot in (PR2, PIONEER)
    }


@pytest.mark.parametrize("robot", ["pr2", "pioneer"])
@pytest.mark.parametrize("preset", ["paccet", "traditional"])
def test_both_planners_reach_the_goal_without_collision(runs, preset: str, robot: str) -> None:
    run = runs[(preset, robot)]
    assert run["status"] == PlannerStatus.GOAL_REACHED
    assert np.hypot(*(run["pose"][:2] - GOAL[:2])) <= GOAL_TOLERANCE + 1e-9
    assert run["wall_hits"] == 0
    assert run["min_edge"] > Person(1, (0.0, 0.0)).radius  # the person is never touched


@pytest.mark.parametrize("robot", ["pr2", "pioneer"])
def test_paccet_keeps_personal_space_and_traditional_does_not(runs, robot: str) -> None:
    assert runs[("paccet", robot)]["min_centre"] >= PERSONAL_SPACE
    assert runs[("traditional", robot)]["min_centre"] < PERSONAL_SPACE


@pytest.mark.parametrize("robot", ["pr2", "pioneer"])
def test_paccet_passes_on_the_free_side(runs, robot: str) -> None:
    # the person stands above the centreline: 1.2 m fits only below, between person and wall
    xy = runs[("paccet", robot)]["xy"]
    abreast = np.abs(xy[:, 0] - PERSON[0]) <= 0.1
    assert abreast.any()
    assert np.all(xy[abreast, 1] <= PERSON[1] - PERSONAL_SPACE + 0.1)


@pytest.mark.parametrize("robot", [PR2, PIONEER], ids=["pr2", "pioneer"])
@pytest.mark.parametrize("preset", ["paccet", "traditional"])
def test_commands_respect_the_velocity_limits(runs, preset: str, robot: RobotModel) -> None:
    cmds = runs[(preset, robot.name)]["cmds"]
    assert np.all(np.isfinite(cmds))
    assert np.all(cmds[:, 0] <= robot.max_vel_x + 1e-9)
    assert np.all(cmds[:, 0] >= robot.min_vel_x - 1e-9)
    assert np.all(np.abs(cmds[:, 1]) <= robot.max_vel_y + 1e-9)
    assert np.all(np.abs(cmds[:, 2]) <= robot.max_vel_theta + 1e-9)


# --- determinism and bad input --------------------------------------------------------------------


def test_same_seed_gives_identical_records() -> None:
    from socialnav.sim.runner import run_episode
    from socialnav.sim.scenario import load_scenario

    a = run_episode("hallway_passing", "paccet", "pr2", seed=3).record
    b = run_episode("hallway_passing", "paccet", "pr2", seed=3).record
    assert a.num_steps == b.num_steps
    for name in ("times", "robot_poses", "robot_twists", "people_positions", "people_velocities"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert list(a.status) == list(b.status)
    # the seed matters: another seed moves the walker's start
    scenario = load_scenario("hallway_passing")
    walker_start = tuple(a.people_positions[0, 0])
    assert walker_start == pytest.approx(scenario.randomize(3).people[0].position)
    assert walker_start != pytest.approx(scenario.randomize(4).people[0].position)


def test_same_inputs_give_the_same_commands_and_records() -> None:
    costmap, _ = world(LENGTH, WIDTH, CORRIDOR, PR2)
    navs = [build_navigator("paccet", PR2, costmap, GOAL, SOCIAL, record=True) for _ in range(2)]
    pose, vel = np.array(START, dtype=float), np.zeros(3)
    for k in range(30):
        first, second = (nav.step(0.1 * k, pose, vel, SOCIAL) for nav in navs)
        np.testing.assert_array_equal(first.cmd, second.cmd)
        assert first.status == second.status
        np.testing.assert_array_equal(first.record.fitness, second.record.fitness)
        assert first.record.chosen == second.record.chosen
        vel = first.cmd
        pose = step_pose(pose, vel)


BAD_INPUTS = {
    "nan x": (0.0, [np.nan, 1.5, 0.0], [0.0, 0.0, 0.0]),
    "nan yaw": (0.0, [1.0, 1.5, np.nan], [0.0, 0.0, 0.0]),
    "inf velocity": (0.0, [1.0, 1.5, 0.0], [np.inf, 0.0, 0.0]),
    "nan time": (np.nan, [1.0, 1.5, 0.0], [0.0, 0.0, 0.0]),
    "short pose": (0.0, [1.0, 1.5], [0.0, 0.0, 0.0]),
    "string pose": (0.0, ["a", 1.5, 0.0], [0.0, 0.0, 0.0]),
}


@pytest.mark.parametrize("preset", ["paccet", "paccet_paper", "traditional"])
def test_bad_input_gives_invalid_input_and_a_zero_command(preset: str) -> None:
    costmap, _ = world(LENGTH, WIDTH, CORRIDOR, PR2)
    nav = build_navigator(preset, PR2, costmap, GOAL, SOCIAL)
    for name, (time, pose, vel) in BAD_INPUTS.items():
        result = nav.step(time, pose, vel, SOCIAL)
        assert result.status == PlannerStatus.INVALID_INPUT, name
        np.testing.assert_array_equal(result.cmd, np.zeros(3), err_msg=name)
    # and the navigator still works afterwards
    result = nav.step(1.0, np.array(START), np.zeros(3), SOCIAL)
    assert result.status == PlannerStatus.OK
    assert result.cmd[0] > 0.0


@settings(max_examples=25, deadline=None)
@given(
    x=st.floats(0.0, LENGTH),
    y=st.floats(0.0, WIDTH),
    yaw=st.floats(-4.0, 4.0),
    nan_at=st.sampled_from([None, 0, 1, 2]),
)
def test_paccet_never_raises_and_commands_are_finite(x, y, yaw, nan_at) -> None:
    costmap, _ = world(LENGTH, WIDTH, CORRIDOR, PIONEER)
    nav = build_navigator("paccet", PIONEER, costmap, GOAL, SOCIAL)
    pose = np.array([x, y, yaw])
    if nan_at is not None:
        pose[nan_at] = np.nan
    result = nav.step(0.0, pose, np.zeros(3), SOCIAL)
    assert result.cmd.shape == (3,)
    assert np.all(np.isfinite(result.cmd))
    if nan_at is not None:
        assert result.status == PlannerStatus.INVALID_INPUT
        assert np.all(result.cmd == 0.0)
    else:
        assert result.status != PlannerStatus.INVALID_INPUT, result.message
        assert result.cmd[1] == 0.0  # differential drive: never a lateral command

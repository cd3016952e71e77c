"""The contact guard: no command of any status closes the footprint on a person it touches.

Recorded crowds (ETH/UCY) had ``paccet`` PR2 episodes with an *active* contact although the
local planner's approach rule forbids closing on anyone in contact: the commands that did it
were not selections but the decelerating zero command of ``WAITING`` (a turn at 0.68 rad/s is
still 0.36 rad/s one cycle later) and evasive steps.
"""

from __future__ import annotations

import numpy as np
import pytest
from _planner_helpers import world
from hypothesis import given, settings
from hypothesis import strategies as st

from shared import crowd_data
from socialnav.core.geometry import signed_distance_to_polygon, world_to_body_frames
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.contact_guard import (
    MAX_GRID,
    ContactGuardParams,
    approach_speeds,
    braking_twists,
    cells_under,
    executed,
    footprint_cells,
    footprint_on_lethal,
    guard_contact,
    sequence_poses,
    stop_poses,
)
from socialnav.planner.limits import enforce_limits, within_limits
from socialnav.planner.presets import PRESETS, build_navigator
from socialnav.world.grid import LETHAL, Costmap, GridGeometry

DT = 0.1
SPEED = ContactGuardParams().approach_speed


def _approach(cmd, pose, robot, social) -> float:
    return float(
        approach_speeds(
            stop_poses(pose, executed(np.asarray(cmd, float)[None], robot), robot, DT),
            robot,
            social.positions(),
            social.velocities(),
            social.radii(),
            DT,
            ContactGuardParams().contact_tolerance,
        )[0]
    )


def _next(pose, cmd) -> np.ndarray:
    """``(1, 3)``: the pose one period after ``pose`` under ``cmd``."""
    return sequence_poses(pose, np.asarray(cmd, float)[None, None], DT)[:, 1]


# A PR2 turning left at 0.68 rad/s; someone stands 1 cm outside its right edge, near the back:
# the turn sweeps that part of the edge toward them (its points move at w·|x| along -y).
TURNING = np.array([0.0, 0.0, 0.68])
BESIDE = SocialContext((Person(1, (-0.25, -0.325 - 0.3 - 0.01), (0.0, 0.0), radius=0.3),))


def test_the_brake_of_a_turn_sweeps_a_corner_into_someone_and_the_guard_steps_away():
    pose = np.zeros(3)
    brake = enforce_limits(np.zeros(3), TURNING, PR2, DT)
    assert brake[2] == pytest.approx(0.36)
    assert _approach(brake, pose, PR2, BESIDE) > 0.05  # the crowd metric's active speed
    cmd, worst = guard_contact(brake, pose, TURNING, PR2, BESIDE, DT)
    assert worst <= SPEED
    assert _approach(cmd, pose, PR2, BESIDE) == pytest.approx(worst)
    assert within_limits(cmd, TURNING, PR2, DT)
    assert cmd[1] > 0.0  # a step to the left, away from them, while the turn slows


def test_the_paccet_navigator_never_closes_on_someone_touching_it():
    # The navigator's command in that state, whatever its status.
    costmap, _ = world(8.0, 8.0, [], PR2)
    pose = np.array([4.0, 4.0, 0.0])
    person = BESIDE.people[0]
    social = SocialContext(
        (
            Person(
                1,
                (pose[0] + person.position[0], pose[1] + person.position[1]),
                (0.0, 0.0),
                radius=0.3,
            ),
        )
    )
    nav = build_navigator("paccet", PR2, costmap, np.array([7.0, 7.0, 0.0]), social)
    res = nav.step(0.0, pose, TURNING, social)
    assert within_limits(res.cmd, TURNING, PR2, DT)
    assert _approach(res.cmd, pose, PR2, social) <= SPEED


def test_a_command_that_closes_on_nobody_passes_unchanged():
    cmd = np.array([0.3, 0.1, 0.2])
    far = SocialContext((Person(1, (3.0, 0.0), (0.0, 0.0)),))
    assert guard_contact(cmd, np.zeros(3), cmd, PR2, far, DT)[0] is cmd
    # in contact, but moving away from them
    behind = SocialContext((Person(1, (-0.325 - 0.31, 0.0), (0.0, 0.0), radius=0.3),))
    out, worst = guard_contact(cmd, np.zeros(3), cmd, PR2, behind, DT)
    assert out is cmd and worst <= SPEED


def test_a_differential_drive_robot_that_cannot_stop_in_time_brakes_hardest():
    # A Pioneer at 0.5 m/s with someone touching its front: every reachable command closes on
    # them (deceleration 1.5 m/s² leaves at least 0.35 m/s); the guard picks the slowest.
    v = np.array([0.5, 0.0, 0.0])
    ahead = SocialContext((Person(1, (0.225 + 0.3 + 0.01, 0.0), (0.0, 0.0), radius=0.3),))
    cmd, worst = guard_contact(v, np.zeros(3), v, PIONEER, ahead, DT)
    assert worst > SPEED
    assert cmd[0] == pytest.approx(0.35)
    brake = enforce_limits(np.zeros(3), v, PIONEER, DT)
    assert worst <= _approach(brake, np.zeros(3), PIONEER, ahead) + 1e-12


def test_the_guard_never_steps_onto_a_wall_it_is_not_on():
    # The same turn with a wall 1.5 cm left of the robot: the brake's turn lifts the front-left
    # corner 1.2 cm, the guard's step away from the person 2 cm, onto the wall; with the map,
    # the guard keeps off it and closes on the person as little as that allows.
    costs = np.zeros((160, 160), np.uint8)
    costs[87:, :] = LETHAL  # y >= 4.35 m
    costmap = Costmap(costs, GridGeometry((160, 160), 0.05))
    pose = np.array([4.0, 4.35 - 0.015 - 0.325, 0.0])
    person = BESIDE.people[0]
    at = (pose[0] + person.position[0], pose[1] + person.position[1])
    social = SocialContext((Person(1, at, (0.0, 0.0), radius=0.3),))
    brake = enforce_limits(np.zeros(3), TURNING, PR2, DT)
    free, _ = guard_contact(brake, pose, TURNING, PR2, social, DT)
    walled, _ = guard_contact(brake, pose, TURNING, PR2, social, DT, costmap=costmap)
    assert not footprint_on_lethal(costmap, pose[None], PR2)[0]
    assert footprint_on_lethal(costmap, _next(pose, free), PR2)[0]
    assert not footprint_on_lethal(costmap, _next(pose, brake), PR2)[0]
    assert not footprint_on_lethal(costmap, _next(pose, walled), PR2)[0]
    assert within_limits(walled, TURNING, PR2, DT)
    assert not np.array_equal(walled, brake)  # it still moves off the person where it can
    assert _approach(walled, pose, PR2, social) < _approach(brake, pose, PR2, social)


def test_bug_someone_appearing_within_reach_gets_the_brake_not_the_forecasts_choice():
    # Recorded crowds dev eth_hotel 34 (PR2): a person's track starts beside the robot while it
    # turns; no command avoids closing on them, and the guard sent the command whose forecast
    # approach was slowest, which kept turning at 1 rad/s for a period; the next period's turn
    # swept a corner into them. A constant-velocity forecast of someone just seen is the least
    # reliable one: now the plain brake, every axis toward zero at its limit.
    v = np.array([0.5, 0.0, 0.0])
    ahead = SocialContext((Person(7, (0.225 + 0.3 + 0.01, 0.1), (-0.3, 0.0), radius=0.3),))
    brake = enforce_limits(np.zeros(3), v, PIONEER, DT)
    slowest, worst = guard_contact(v, np.zeros(3), v, PIONEER, ahead, DT)
    assert worst > SPEED and not np.array_equal(slowest, brake)  # none passes
    fresh, _ = guard_contact(v, np.zeros(3), v, PIONEER, ahead, DT, appeared=frozenset({7}))
    np.testing.assert_allclose(fresh, brake)
    # someone else appearing out of reach changes nothing
    other, _ = guard_contact(v, np.zeros(3), v, PIONEER, ahead, DT, appeared=frozenset({8}))
    np.testing.assert_allclose(other, slowest)
    # Second trial: a newcomer within reach but not the one closed on braked the robot too;
    # the brake is for when only the people who just appeared make every command fail.
    side = Person(8, (-0.1, 0.9), (0.0, 0.0), radius=0.3)  # within reach, not touched
    both = SocialContext((ahead.people[0], side))
    base, _ = guard_contact(v, np.zeros(3), v, PIONEER, both, DT)
    known, _ = guard_contact(v, np.zeros(3), v, PIONEER, both, DT, appeared=frozenset({8}))
    np.testing.assert_allclose(known, base)
    new, _ = guard_contact(v, np.zeros(3), v, PIONEER, both, DT, appeared=frozenset({7}))
    np.testing.assert_allclose(new, brake)


def test_the_navigator_tells_the_guard_who_appeared():
    # A Pioneer at 0.5 m/s; someone walking at it 1 cm ahead, whom no reachable command avoids
    # closing on. Seen for the first time this cycle: the navigator brakes at the limits. In
    # view since the first cycle: the guard's slowest forecast approach, not the brake.
    costmap, _ = world(8.0, 8.0, [], PIONEER)
    pose = np.array([4.0, 4.0, 0.0])
    v = np.array([0.5, 0.0, 0.0])
    walker = Person(7, (4.0 + 0.225 + 0.3 + 0.01, 4.1), (-0.3, 0.0), radius=0.3)
    near = SocialContext((walker,))
    far = SocialContext((Person(2, (1.0, 1.0), (0.0, 0.0), radius=0.3),))
    goal = np.array([7.0, 4.0, 0.0])
    brake = enforce_limits(np.zeros(3), v, PIONEER, DT)
    nav = build_navigator("paccet", PIONEER, costmap, goal, far)
    nav.step(0.0, pose, v, far)
    np.testing.assert_allclose(nav.step(0.1, pose, v, near).cmd, brake)
    nav = build_navigator("paccet", PIONEER, costmap, goal, near)
    nav.step(0.0, pose, v, near)
    known = nav.step(0.1, pose, v, near).cmd
    assert within_limits(known, v, PIONEER, DT) and not np.allclose(known, brake)
    # An invalid cycle leaves the navigator's state alone: the walker is still new after it.
    nav = build_navigator("paccet", PIONEER, costmap, goal, far)
    nav.step(0.0, pose, v, far)
    assert nav.step(float("nan"), pose, v, near).status.value == "INVALID_INPUT"
    np.testing.assert_allclose(nav.step(0.1, pose, v, near).cmd, brake)


ROBOTS = st.sampled_from([PR2, PIONEER])


@settings(max_examples=150, deadline=None)
@given(
    robot=ROBOTS,
    v=st.tuples(*(st.floats(-1.0, 1.0) for _ in range(3))),
    c=st.tuples(*(st.floats(-1.0, 1.0) for _ in range(3))),
    person=st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0)),
    walk=st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0)),
)
def test_the_guarded_command_is_reachable_and_never_closes_faster_than_needed(
    robot: RobotModel, v, c, person, walk
):
    lo = np.array([robot.min_vel_x, -robot.max_vel_y, -robot.max_vel_theta])
    hi = np.array([robot.max_vel_x, robot.max_vel_y, robot.max_vel_theta])
    velocity = lo + (np.asarray(v) + 1.0) / 2.0 * (hi - lo)
    cmd = enforce_limits(lo + (np.asarray(c) + 1.0) / 2.0 * (hi - lo), velocity, robot, DT)
    social = SocialContext((Person(1, person, walk, radius=0.3),))
    pose = np.zeros(3)
    out, worst = guard_contact(cmd, pose, velocity, robot, social, DT)
    assert within_limits(out, velocity, robot, DT, tol=1e-9)
    assert worst == pytest.approx(_approach(out, pose, robot, social))
    before = _approach(cmd, pose, robot, social)
    if before <= SPEED:
        assert out is cmd
    else:
        # never worse than the command, nor than the brake (up to the 0.1 mm/s near-tie rule)
        assert worst <= before + 1e-4
        brake = enforce_limits(np.zeros(3), velocity, robot, DT)
        assert worst <= max(SPEED, _approach(brake, pose, robot, social) + 1e-4)


@pytest.mark.parametrize("value", [-0.1, float("nan")])
def test_bad_guard_parameters_name_the_field(value):
    with pytest.raises(Exception, match="approach_speed"):
        ContactGuardParams(approach_speed=value)
    with pytest.raises(Exception, match="grid"):
        ContactGuardParams(grid=4)


def test_paccet_guards_and_the_baselines_do_not():
    assert PRESETS.get("paccet").contact_guard is not None
    assert PRESETS.get("traditional").contact_guard is None


def test_bug_pr2_turned_into_a_walker_while_braking_recorded_crowd_eth_hotel_dev_seed_67():
    from socialnav.experiments.crowd import CrowdSpec, run_crowd_planner
    from socialnav.metrics import crowd as cm

    spec = CrowdSpec(str(crowd_data("eth_hotel_obsmat.txt")), "paccet", "pr2", 67)
    record = run_crowd_planner(spec).record
    assert cm.collisions_active(record) == 0


def test_bug_a_turn_the_robot_could_not_stop_before_it_swept_into_someone():
    # A Pioneer turning right at 1 rad/s, someone 8 cm off its right edge near the front. One
    # more cycle of the turn touches nobody (the edge comes 2 cm closer), but stopping the turn
    # takes three more cycles at 3 rad/s², and by then the edge sweeps into them; braking now
    # does not. The first guard looked one step ahead and let the turn go on (recorded crowd
    # eth_hotel, Pioneer, dev seed 26: an active contact two cycles later).
    v = np.array([0.0, 0.0, -1.0])
    person = Person(1, (0.15, -0.19 - 0.3 - 0.08), (0.0, 0.0), radius=0.3)
    social = SocialContext((person,))
    one_step = _next(np.zeros(3), v)
    gap = signed_distance_to_polygon(
        world_to_body_frames(np.array(person.position)[None], one_step)[0], PIONEER.polygon
    )
    assert float(gap) - 0.3 > ContactGuardParams().contact_tolerance  # no contact after one step
    assert _approach(v, np.zeros(3), PIONEER, social) > 0.05  # but during the stop
    cmd, worst = guard_contact(v, np.zeros(3), v, PIONEER, social, DT)
    assert worst <= SPEED
    assert -1.0 < cmd[2] < 0.0  # it slows the turn now
    assert within_limits(cmd, v, PIONEER, DT)


def _corridor() -> Costmap:
    """Walls below y = 1 m and from y = 3 m up, 8 m long, 0.05 m cells."""
    costs = np.zeros((80, 160), np.uint8)
    costs[:20, :] = LETHAL
    costs[60:, :] = LETHAL
    return Costmap(costs, GridGeometry((80, 160), 0.05))


def _stop_on_wall(costmap: Costmap, pose, cmd, robot: RobotModel) -> bool:
    twists = braking_twists(executed(np.asarray(cmd, float)[None], robot), robot, DT)
    return bool(footprint_on_lethal(costmap, sequence_poses(pose, twists, DT)[0, 1:], robot).any())


def test_bug_the_stop_after_the_guards_command_ran_into_a_wall():
    # A PR2 turning toward the upper wall with a walker touching it: the first guard checked
    # the wall one period ahead only and chose a faster command whose stop reached the wall,
    # although the brake and many other commands stop clear of both.
    cm = _corridor()
    pose, v = np.array([4.0, 2.574, 1.772]), np.array([0.281, 0.268, 0.507])
    cmd = np.array([0.069, 0.018, 0.827])
    social = SocialContext((Person(1, (4.06, 1.869), (-0.919, -0.117), radius=0.3),))
    assert _approach(cmd, pose, PR2, social) > SPEED
    out, worst = guard_contact(cmd, pose, v, PR2, social, DT, costmap=cm)
    assert worst <= SPEED
    assert not _stop_on_wall(cm, pose, out, PR2)
    assert within_limits(out, v, PR2, DT)


def test_bug_a_wall_cell_touched_behind_let_the_guard_onto_another_wall():
    # The wall test of above, with one more LETHAL cell the back edge already touches: the
    # first guard switched the wall rule off for every cell once the footprint touched any.
    costs = np.zeros((160, 160), np.uint8)
    costs[87:, :] = LETHAL
    pose = np.array([4.0, 4.35 - 0.015 - 0.325, 0.0])
    row, col = GridGeometry((160, 160), 0.05).world_to_cell([pose[0] - 0.325, pose[1]])
    costs[row, col] = LETHAL
    cm = Costmap(costs, GridGeometry((160, 160), 0.05))
    person = BESIDE.people[0]
    at = (pose[0] + person.position[0], pose[1] + person.position[1])
    social = SocialContext((Person(1, at, (0.0, 0.0), radius=0.3),))
    assert footprint_on_lethal(cm, pose[None], PR2)[0]
    brake = enforce_limits(np.zeros(3), TURNING, PR2, DT)
    out, _ = guard_contact(brake, pose, TURNING, PR2, social, DT, costmap=cm)
    flat, inside = footprint_cells(cm, pose[None], PR2)
    now = flat[inside & (cm.costs.reshape(-1)[flat] >= LETHAL)]
    twists = braking_twists(executed(out[None], PR2), PR2, DT)
    stop = sequence_poses(pose, twists, DT)[0, 1:]
    assert not footprint_on_lethal(cm, stop, PR2, now).any()


@pytest.mark.parametrize(
    ("cmd", "velocity", "period"),
    [
        (np.array([0, 0, 0]), np.array([0.0, 0.0, 0.68]), DT),  # integers
        ([0.0, 0.0, 0.0], [0.0, 0.0, 0.68], DT),  # lists
        (np.array([np.nan, 0.0, 0.0]), TURNING, DT),
        (np.zeros(3), np.array([np.inf, 0.0, 0.0]), DT),
        (np.zeros(3), TURNING, 0.0),
        (np.zeros(3), TURNING, -0.1),
        (np.zeros(3), TURNING, float("nan")),
    ],
)
def test_odd_but_finite_typed_input_never_raises(cmd, velocity, period):
    out, worst = guard_contact(cmd, np.zeros(3), velocity, PR2, BESIDE, period)
    assert np.asarray(out).shape == (3,)
    readable = np.all(np.isfinite(np.asarray(cmd, float))) and np.all(
        np.isfinite(np.asarray(velocity, float))
    )
    if not readable or not (period > 0):
        assert out is cmd and worst == -np.inf  # nothing it can judge: left as it is


def test_the_stopping_command_of_invalid_input_is_guarded_too():
    # A pose just off the map is INVALID_INPUT with a stopping command; that command, too,
    # may not sweep the PR2's corner into the person beside it.
    costmap, _ = world(8.0, 8.0, [], PR2)
    pose = np.array([8.01, 4.0, 0.0])
    person = BESIDE.people[0]
    at = (pose[0] + person.position[0], pose[1] + person.position[1])
    social = SocialContext((Person(1, at, (0.0, 0.0), radius=0.3),))
    nav = build_navigator("paccet", PR2, costmap, np.array([7.0, 7.0, 0.0]), social)
    res = nav.step(0.0, pose, TURNING, social)
    assert res.status.name == "INVALID_INPUT"
    assert _approach(res.cmd, pose, PR2, social) <= SPEED
    assert within_limits(res.cmd, TURNING, PR2, DT)


def test_the_grid_takes_numpy_integers_and_is_bounded():
    assert ContactGuardParams(grid=np.int64(9)).grid == 9
    with pytest.raises(Exception, match="grid"):
        ContactGuardParams(grid=MAX_GRID + 2)


def test_bug_a_wall_cell_already_under_the_footprint_made_the_guard_push_a_person():
    # A LETHAL cell under the PR2 but off its outline (a post it stands over) read as a wall
    # the stop would newly touch, so the guard chose a command closing on the walker at
    # 0.068 m/s instead of one at 0.018 m/s (second newcomer trial, random search).
    costs = np.zeros((160, 160), np.uint8)
    pose = np.array([4.0, 4.0, 1.3241])
    v, cmd = np.array([0.3739, -0.2053, 0.5169]), np.array([0.1239, 0.0410, 0.5829])
    social = SocialContext((Person(1, (4.4275, 3.5841), (0.916, 0.538), radius=0.3),))
    free, worst_free = guard_contact(
        cmd, pose, v, PR2, social, DT, costmap=Costmap(costs, GridGeometry((160, 160), 0.05))
    )
    costs[81, 86] = LETHAL
    post = Costmap(costs, GridGeometry((160, 160), 0.05))
    assert 81 * 160 + 86 in cells_under(post, pose, PR2)
    assert not footprint_on_lethal(post, pose[None], PR2)[0]  # not on the outline
    out, worst = guard_contact(cmd, pose, v, PR2, social, DT, costmap=post)
    assert worst_free <= SPEED and worst <= SPEED
    np.testing.assert_array_equal(out, free)


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")  # 1e300 squared, in a norm
def test_a_command_far_beyond_the_limits_or_a_tiny_period_does_not_raise():
    for cmd, period in ((np.array([0.0, 0.0, 1e300]), DT), (np.zeros(3), 1e-9)):
        out, _ = guard_contact(cmd, np.zeros(3), TURNING, PR2, BESIDE, period)
        assert np.asarray(out).shape == (3,)

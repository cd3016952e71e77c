"""The planner options that make ``paccet`` generalize: interaction partners at the
interaction's own distance, and rollouts that stop at the goal (no slow final approach)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_social_critics import make_ctx, straight

from socialnav.core.robot import PR2
from socialnav.core.scene import Group, Person, Queue, SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner.critics.interpersonal import InterpersonalCritic, partner_thresholds
from socialnav.planner.local_planner import stop_at_goal
from socialnav.social.goals import SocialGoal, o_formation_join_pose, queue_tail_pose

MEMBERS = [(0.0, 0.9), (-0.9, 0.0), (0.0, -0.9)]  # the paper's group_join, centred at 0
WALKER = (3.0, 3.0)


def group_scene():
    people = (*tuple(Person(i + 1, p) for i, p in enumerate(MEMBERS)), Person(9, WALKER))
    social = SocialContext(people, groups=(Group((1, 2, 3), "join"),))
    goal = o_formation_join_pose(np.array(MEMBERS))
    ctx = dataclasses.replace(make_ctx(social=social, social_goal=goal), goal=goal.pose)
    return ctx, goal


def test_partners_get_the_spots_own_distance_others_keep_1_5_m():
    ctx, goal = group_scene()
    own = partner_thresholds(ctx, 1.5, 0.05)
    gaps = np.linalg.norm(np.array(MEMBERS) - goal.pose[:2], axis=1)
    for k, gap in enumerate(gaps):
        expected = gap - 0.05 if gap < 1.5 else 1.5
        assert own[k] == pytest.approx(expected)
    assert own[3] == 1.5  # the walker is nobody's partner


def test_bug_id_objective_forbids_the_join_spot_without_partner_distance():
    """The issue's stall: ID > 0 at the very spot the social goal asks for."""
    ctx, goal = group_scene()
    trajs = straight([goal.pose[:2]], start=(4.0, 0.0))
    plain = InterpersonalCritic(evaluation="max_over_time").score(trajs, ctx).cost
    partner = InterpersonalCritic(evaluation="max_over_time", partner_distance=True)
    assert plain[0] > 1.0
    assert partner.score(trajs, ctx).cost[0] == 0.0
    # a step inside the formation still costs: the interaction's distance is a threshold too
    inside = straight([goal.pose[:2] * 0.5], start=(4.0, 0.0))
    assert partner.score(inside, ctx).cost[0] > 0.0


def test_no_partners_when_not_steering_to_a_stopping_social_goal():
    ctx, goal = group_scene()
    elsewhere = dataclasses.replace(ctx, goal=np.array([5.0, 5.0, 0.0]))
    assert np.all(partner_thresholds(elsewhere, 1.5, 0.05) == 1.5)
    wp = SocialGoal(goal.pose, "waypoint", is_waypoint=True)
    waypoint = dataclasses.replace(ctx, social_goal=wp)
    assert np.all(partner_thresholds(waypoint, 1.5, 0.05) == 1.5)
    # no social goal, a given goal far from everyone (a given goal near people: the test below)
    nobody = dataclasses.replace(ctx, social_goal=None, goal=np.array([5.0, 5.0, 0.0]))
    assert np.all(partner_thresholds(nobody, 1.5, 0.05) == 1.5)


def test_queue_partner_is_the_person_ahead():
    people = (Person(1, (0.0, 0.0)), Person(2, (0.0, -0.8)))
    social = SocialContext(people, queues=(Queue((1, 2), (0.0, 0.6), 0.8),))
    tail = SocialGoal(np.array([0.0, -1.6, np.pi / 2]), "queue_tail")
    ctx = dataclasses.replace(make_ctx(social=social, social_goal=tail), goal=tail.pose)
    own = partner_thresholds(ctx, 1.5, 0.05)
    assert own[1] == pytest.approx(0.75)  # queue spacing less the margin
    assert own[0] == 1.5  # 1.6 m away: beyond the 1.5 m threshold anyway


def test_stop_at_goal_holds_each_rollout_at_its_first_pose_inside_the_tolerance():
    t = np.linspace(0.0, 1.0, 11)
    xs = np.stack([t * 2.0, t * 0.5])  # fast (passes the goal at x = 1) and slow (never reaches)
    poses = np.zeros((2, 11, 3))
    poses[..., 0] = xs
    trajs = Trajectories(np.zeros((2, 3)), poses, t)
    out = stop_at_goal(trajs, np.array([1.0, 0.0, 0.0]), 0.25)
    # the first sample within 0.25 m of x = 1 is x = 0.8 (t = 0.4): arrived, on the goal since
    assert out.poses[0, 4:, 0] == pytest.approx(1.0)
    assert out.poses[0, 3, 0] == pytest.approx(0.6)
    assert np.all(np.diff(out.poses[0, :, 0]) >= 0.0)
    np.testing.assert_array_equal(out.poses[1], trajs.poses[1])
    same = stop_at_goal(trajs, np.array([10.0, 0.0, 0.0]), 0.1)
    assert same is trajs


def test_paccet_preset_stops_rollouts_at_the_goal_inside_the_suites_tolerance():
    from socialnav.planner.presets import PRESETS

    preset = PRESETS.get("paccet")
    assert preset.params.stop_at_goal
    assert preset.params.xy_goal_tolerance < 0.10  # the generated suite's arrival tolerance
    assert preset.spot_tolerance is not None and preset.spot_tolerance[0] < 0.10
    assert not PRESETS.get("traditional").params.stop_at_goal  # the ROS baseline stays ROS
    assert PR2.name == "pr2"


def test_passing_distance_stops_rewarding_standing_still_for_an_oncoming_walker():
    """Table 1 hallway: the walker will pass 1.4 m to the side whether the robot stands or
    drives on; the rollout-only ID scored standing still better (the closest approach falls
    after its horizon) and the PR2 stopped ~4 s. With the passing distance both cost alike,
    and standing in the walker's lane costs what the encounter will."""
    walker = SocialContext((Person(1, (2.0, 1.4), velocity=(-0.5, 0.0)),))
    ctx = make_ctx(social=walker)
    trajs = straight([(0.0, 0.0), (0.8, 0.0), (0.8, 1.4)], duration=1.7, steps=18)
    plain = InterpersonalCritic(evaluation="max_over_time").score(trajs, ctx).cost
    passing = InterpersonalCritic(evaluation="max_over_time", hold_horizon=3.0)
    cost = passing.score(trajs, ctx).cost
    assert plain[0] < plain[1]  # the artefact: standing still looks better
    assert cost[0] == pytest.approx(cost[1])  # both pass at 1.4 m
    assert cost[0] == pytest.approx(np.exp(1 / 1.4))
    assert cost[2] > 10 * cost[0]  # ends in the walker's lane
    static = SocialContext((Person(1, (2.0, 1.4)),))
    ctx_static = make_ctx(social=static)
    np.testing.assert_array_equal(  # nobody walking: no change
        passing.score(trajs, ctx_static).cost,
        InterpersonalCritic(evaluation="max_over_time").score(trajs, ctx_static).cost,
    )


def test_arrival_time_prefers_the_rollout_that_arrives_first():
    from socialnav.planner.critics.arrival import ArrivalTimeCritic

    t = np.linspace(0.0, 1.0, 11)
    poses = np.zeros((3, 11, 3))
    poses[0, :, 0] = t * 2.0  # arrives at t = 0.4 (x = 0.8, within 0.25 m of x = 1)
    poses[1, :, 0] = t * 1.0  # arrives at t = 0.8
    poses[2, :, 0] = t * 0.2  # never arrives
    trajs = stop_at_goal(Trajectories(np.zeros((3, 3)), poses, t), np.array([1.0, 0.0, 0.0]), 0.25)
    ctx = dataclasses.replace(make_ctx(), goal=np.array([1.0, 0.0, 0.0]))
    cost = ArrivalTimeCritic().score(trajs, ctx).cost
    np.testing.assert_allclose(cost, [0.4, 0.8, 1.1])


def test_rollouts_do_not_stop_at_a_waypoint_they_pass_through():
    """Gallery passing got STUCK beside the viewer: snapping rollouts onto a 0.5 m waypoint hid
    their real end points (nearer the viewer) from the social critics."""
    wp = SocialGoal(np.array([1.0, 2.0, 0.0]), "waypoint", is_waypoint=True)
    ctx = dataclasses.replace(make_ctx(social_goal=wp), goal=wp.pose)
    assert ctx.steers_to_waypoint()
    after = dataclasses.replace(ctx, goal=np.array([6.0, 2.0, 0.0]))  # waypoint passed
    assert not after.steers_to_waypoint()
    spot = SocialGoal(np.array([1.0, 2.0, 0.0]), "queue_tail")
    assert not dataclasses.replace(ctx, social_goal=spot).steers_to_waypoint()


def test_bug_robot_at_the_spot_makes_room_to_turn_instead_of_staying_latched():
    """Generated queue, PR2 (dev seeds 4 and 5): at the tail slot, 0.67 m behind the last
    member, the PR2's corners (0.46 m out) would sweep into them on the in-place turn to the
    goal yaw; the latched goal check then reported NO_LEGAL_TRAJECTORY until the time limit.
    Here a wall 0.38 m ahead blocks the turn: the robot backs off, turns, and drives back."""
    from socialnav.planner.context import PlanningContext
    from socialnav.planner.local_planner import PlannerStatus, traditional_planner
    from socialnav.world.grid import LETHAL, Costmap, GridGeometry

    geometry = GridGeometry((60, 60), 0.05, (-1.5, -1.5))
    costs = np.zeros((60, 60), np.uint8)
    costs[28:32, 38:40] = LETHAL  # x in [0.40, 0.50), y in [-0.10, 0.10)
    costmap = Costmap(costs, geometry)
    planner = traditional_planner(PR2)
    pose, velocity = np.zeros(3), np.zeros(3)
    goal = np.array([0.0, 0.0, np.pi / 2])
    statuses = []
    for k in range(150):
        ctx = PlanningContext(pose, velocity, goal, np.zeros((1, 2)), costmap, PR2, time=0.1 * k)
        result = planner.plan(ctx)
        statuses.append(result.status)
        if result.status == PlannerStatus.GOAL_REACHED:
            break
        c, s = np.cos(pose[2]), np.sin(pose[2])
        cmd = result.cmd
        pose = pose + 0.1 * np.array([c * cmd[0] - s * cmd[1], s * cmd[0] + c * cmd[1], cmd[2]])
        velocity = cmd
    assert statuses[0] == PlannerStatus.ROTATING_TO_GOAL  # making room, not stuck
    assert statuses[-1] == PlannerStatus.GOAL_REACHED
    assert np.hypot(*pose[:2]) <= planner.params.xy_goal_tolerance
    assert abs(pose[2] - np.pi / 2) <= planner.params.yaw_goal_tolerance


@pytest.mark.parametrize("dx", np.linspace(0.0, 0.045, 10))
def test_bug_footprint_grazing_a_person_is_a_collision_at_any_sub_cell_offset(dx):
    """A PR2 corner ending 1 cm inside a person's disc is illegal wherever the disc sits in
    its cell: people were rasterized by cell centres only, and a PR2 turning beside a queue
    member it stood behind grazed them by 4 cm (generated queue, dev seed 5)."""
    from socialnav.core.scene import SocialContext
    from socialnav.planner.context import PlanningContext
    from socialnav.planner.critics.occupancy import OccupancyCritic
    from socialnav.planner.navigator import Navigator
    from socialnav.world.grid import Costmap, GridGeometry

    costmap = Costmap(np.zeros((80, 80), np.uint8), GridGeometry((80, 80), 0.05, (-2.0, -2.0)))
    corner = PR2.circumscribed_radius  # the corner at yaw pi/4 lies on +x
    person = Person(1, (corner + 0.25 - 0.01 + dx, 0.0), radius=0.25)
    social = SocialContext((person,))
    navigator = Navigator.__new__(Navigator)  # only the people layer is exercised
    navigator.people_as_obstacles, navigator.robot = True, PR2
    local = navigator._with_people(costmap, social)
    poses = np.array([[[-0.1, 0.0, np.pi / 4], [0.0, 0.0, np.pi / 4]]])
    trajs = Trajectories(np.zeros((1, 3)), poses, np.array([0.0, 0.1]))
    ctx = PlanningContext(
        np.array([-0.1, 0.0, np.pi / 4]), np.zeros(3), np.zeros(3), np.zeros((1, 2)), local, PR2
    )
    score = OccupancyCritic().score(trajs, ctx)
    assert not np.isfinite(score.cost[0]) or score.illegal["collision"][0]


@pytest.mark.slow
def test_bug_pr2_at_a_queue_tail_turns_to_face_the_line_without_touching_it():
    """Generated queue, dev seed 5, PR2: the slot is 0.67 m behind the last member, closer
    than the PR2's corners (0.46 m) plus the person (0.25 m). It stayed latched with the turn
    illegal (its check ran past the goal yaw), then grazed the member while turning."""
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode

    record = run_episode(generate("queue", 5), "paccet", "pr2", seed=5).record
    failed = [c.name for c in success_conditions(record) if c.required and not c.passed]
    assert failed == []


@pytest.mark.slow
@pytest.mark.parametrize("seed", [18, 37])
def test_bug_pr2_reaches_a_tight_queue_tail_facing_the_line(seed):
    """Generated queue, dev seeds 18 and 37, PR2: the slot kept the people's centre spacing
    (0.62 m and 0.63 m) from the last member, 4-5 cm between the PR2's front and their back and
    inside its own costmap's inscribed inflation of them. It stopped 0.10-0.11 m short, turned
    away while dithering there, and ended STUCK facing 40-90° off the line. The slot now keeps
    the queue's body gap (0.075 m further back for the PR2's 0.325 m front)."""
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode

    record = run_episode(generate("queue", seed), "paccet", "pr2", seed=seed).record
    failed = [c.name for c in success_conditions(record) if c.required and not c.passed]
    assert failed == []


def test_queue_slot_keeps_the_body_gap_for_the_robots_own_front():
    from socialnav.core.robot import PIONEER
    from socialnav.planner.presets import footprint_front

    assert footprint_front(PR2) == pytest.approx(0.325)
    assert footprint_front(PIONEER) == pytest.approx(0.225)
    members, desk = np.array([[0.0, 1.0], [0.0, 1.6]]), np.zeros(2)
    for robot, gap in ((PR2, 0.675), (PIONEER, 0.6)):  # a Pioneer's front is inside a person's
        goal = queue_tail_pose(members, desk, 0.6, robot_front=footprint_front(robot))
        assert goal.position == pytest.approx([0.0, 1.6 + gap])
        assert goal.yaw == pytest.approx(-np.pi / 2)  # facing the last member


@pytest.mark.parametrize("robot_name", ["pr2", "pioneer"])
def test_bug_presenter_spot_keeps_the_whole_footprint_outside_the_activity_space(robot_name):
    """Generated gallery_present, PR2 (dev seeds 5, 9, 14, 15): the spot kept 0.35 m from
    the activity space, less than a PR2's corners reach (0.46 m), and turning to face the
    viewer there put a corner 2–4 cm inside. The spot now keeps the robot's circumscribed
    radius (+5 cm) from it, so no yaw at the spot intrudes."""
    from socialnav.core.robot import PIONEER
    from socialnav.core.scene import Artwork
    from socialnav.planner.presets import StickySocialGoal, presenter_clearance
    from socialnav.social.spaces import activity_space_polygon, segment_polygon_distance

    robot = PR2 if robot_name == "pr2" else PIONEER
    viewer = Person(1, (2.326, 2.053), yaw=np.pi)
    art = Artwork((0.0, 2.112), 0.858, 0.0, viewer_ids=(1,))
    social = SocialContext((viewer,), artworks=(art,))
    given = np.array([0.93, 2.09, 0.0])  # 0.4 of the way from the art to the viewer
    spot = StickySocialGoal(art_clearance=presenter_clearance(robot))(
        social, given, np.array([8.7, 1.5, np.pi])
    )
    assert spot is not None
    poly = activity_space_polygon(np.array(art.center), art.width, art.facing, viewer.position)
    xy = np.asarray(spot.pose[:2])
    assert segment_polygon_distance(xy, xy, poly) >= robot.circumscribed_radius


def test_bug_given_goal_beside_a_standing_person_is_not_forbidden_by_id():
    """CrowdNav circle crossing, Pioneer (dev seeds 6, 8, 9): people end standing on the
    circle, one 1.0 m from the robot's goal; ID (1.5 m) rose with every step toward the goal
    and the robot crawled the last metre until the time limit. A person nearer the given goal
    than the threshold keeps the goal's own distance from them (less the margin)."""
    person = SocialContext((Person(1, (1.0, 0.0)),))
    ctx = dataclasses.replace(make_ctx(social=person), goal=np.zeros(3))
    own = partner_thresholds(ctx, 1.5, 0.05)
    assert own[0] == pytest.approx(0.95)
    critic = InterpersonalCritic(evaluation="max_over_time", partner_distance=True)
    at_goal = straight([(0.0, 0.0)], start=(-1.0, 0.0))
    assert critic.score(at_goal, ctx).cost[0] == 0.0
    plain = InterpersonalCritic(evaluation="max_over_time").score(at_goal, ctx).cost[0]
    assert plain > 1.0
    closer = straight([(0.3, 0.0)], start=(-1.0, 0.0))  # past the goal, toward them: costs
    assert critic.score(closer, ctx).cost[0] > 0.0
    far = dataclasses.replace(ctx, goal=np.array([-3.0, 0.0, 0.0]))
    assert partner_thresholds(far, 1.5, 0.05)[0] == 1.5  # a far goal changes nothing


def _turn_at_the_spot(dist, bearing, yaw0, origin):
    """PR2 at its goal position facing ``yaw0``, a person ``dist`` m away at ``bearing``, the
    goal yaw facing them; returns the smallest footprint-to-disc gap (m) while it arrives."""
    from socialnav.core.geometry import signed_distance_to_polygon
    from socialnav.planner.context import PlanningContext
    from socialnav.planner.local_planner import PlannerStatus
    from socialnav.planner.navigator import Navigator
    from socialnav.planner.presets import build_local_planner
    from socialnav.world.grid import Costmap, GridGeometry

    person = Person(1, (dist * np.cos(bearing), dist * np.sin(bearing)), radius=0.25)
    social = SocialContext((person,))
    costmap = Costmap(np.zeros((80, 80), np.uint8), GridGeometry((80, 80), 0.05, origin))
    navigator = Navigator.__new__(Navigator)  # only the people layer is exercised
    navigator.people_as_obstacles, navigator.robot = True, PR2
    local = navigator._with_people(costmap, social)
    planner = build_local_planner("paccet", PR2, social)
    pose, velocity = np.array([0.0, 0.0, yaw0]), np.zeros(3)
    goal = np.array([0.0, 0.0, bearing])
    worst, status = np.inf, None
    for k in range(150):
        ctx = PlanningContext(
            pose, velocity, goal, goal[None, :2], local, PR2, social=social, time=0.1 * k
        )
        result = planner.plan(ctx)
        status = result.status
        if status == PlannerStatus.GOAL_REACHED:
            break
        cmd = result.cmd
        for _ in range(10):  # integrate finely: a graze lasts a few degrees
            c, s = np.cos(pose[2]), np.sin(pose[2])
            pose = pose + 0.01 * np.array(
                [c * cmd[0] - s * cmd[1], s * cmd[0] + c * cmd[1], cmd[2]]
            )
            c, s = np.cos(pose[2]), np.sin(pose[2])
            poly = PR2.polygon @ np.array([[c, s], [-s, c]]) + pose[:2]
            gap = signed_distance_to_polygon(np.array(person.position), poly) - person.radius
            worst = min(worst, float(gap))
        velocity = cmd
    return worst, status


def test_bug_in_place_turn_at_the_spot_never_sweeps_a_corner_into_the_person():
    """Generated queue, PR2 (the reporting split's kind, rebuilt here by hand): at a tail slot
    0.70 m from the last member, less than the PR2's corner (0.46 m) plus the person
    (0.25 m), the in-place turn to face them swept a corner 1–2 cm into them: the rasterized
    check judged the turn legal at some sub-cell offsets. The turn is now also checked on the
    people's discs (``TURN_CLEARANCE``): the robot makes room first and never touches them."""
    from socialnav.planner.local_planner import PlannerStatus

    worst, status = _turn_at_the_spot(0.7062, 0.3800, -0.5503, (-1.9591, -1.9687))
    assert worst > 0.0
    assert status == PlannerStatus.GOAL_REACHED


def test_turn_clearance_is_the_footprint_to_disc_gap_over_the_turn():
    from socialnav.planner.context import PlanningContext
    from socialnav.planner.local_planner import turn_clearance
    from socialnav.world.grid import Costmap, GridGeometry

    costmap = Costmap(np.zeros((10, 10), np.uint8), GridGeometry((10, 10), 0.1, (-0.5, -0.5)))
    social = SocialContext((Person(1, (0.0, 0.72), radius=0.25),))
    ctx = PlanningContext(
        np.zeros(3), np.zeros(3), np.zeros(3), np.zeros((1, 2)), costmap, PR2, social=social
    )
    half = 0.325  # PR2 square: the face at yaw 0, the corner at yaw pi/4
    assert turn_clearance(np.zeros(3), 0.0, PR2, ctx) == pytest.approx(0.72 - half - 0.25)
    corner = PR2.circumscribed_radius
    swept = turn_clearance(np.zeros(3), np.pi / 2, PR2, ctx)
    assert swept == pytest.approx(0.72 - corner - 0.25, abs=1e-4)
    assert turn_clearance(np.array([5.0, 5.0, 0.0]), 3.0, PR2, ctx) == np.inf


@pytest.mark.slow
@pytest.mark.parametrize(("family", "seed"), [("crowdnav_visible", 87), ("gallery_pass", 9)])
def test_bug_pioneer_follows_a_plan_that_reaches_the_goal_from_the_side(family, seed):
    """Generated dev seeds, Pioneer: someone stands near the goal, so the social global plan
    reaches it from the side. Following the plan raised the free-space goal distance, cutting
    toward the goal raised the path distance, and turning on the spot (heading along the plan)
    cost least: the robot dithered 2.3-2.6 m short of the goal until the time limit. The goal
    term now measures the plan's length still to go (``critics.plan_progress``)."""
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode

    record = run_episode(generate(family, seed), "paccet", "pioneer", seed=seed).record
    failed = [c.name for c in success_conditions(record) if c.required and not c.passed]
    assert failed == []


def test_paccet_social_objectives_carry_the_indifference_threshold_the_paper_preset_none():
    from socialnav.planner.presets import (
        PRESETS,
        SOCIAL_INDIFFERENCE,
        LocalPlannerParams,
        SceneObjectives,
    )

    social = SocialContext((Person(1, (2.0, 0.0)), Person(2, (2.0, 1.0))))
    objectives, selection = SceneObjectives(PRESETS.get("paccet"), LocalPlannerParams()).for_scene(
        social
    )
    assert [o.indifference for o in objectives] == [0.0, SOCIAL_INDIFFERENCE]
    assert selection.options.indifference == (0.0, SOCIAL_INDIFFERENCE)
    _, paper = SceneObjectives(PRESETS.get("paccet_paper"), LocalPlannerParams()).for_scene(social)
    assert paper.options.indifference is None


@pytest.mark.slow
def test_bug_pioneer_beside_a_standing_person_turns_to_the_goal_instead_of_dithering():
    """Generated crowdnav dev seed 34, Pioneer: beside a person standing 1.08 m away, facing
    away from the goal, every candidate's ID was within 1e-6 of the others'. Normalized by that
    range, a 1e-6 lower ID outweighed turning toward the goal (0.155 better in navigation):
    the robot crept at 0.01 m/s, then waited beside the person until the time limit. Social
    objectives now carry an indifference threshold (``PaccetOptions.indifference``)."""
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode

    record = run_episode(generate("crowdnav", 34), "paccet", "pioneer", seed=34).record
    failed = [c.name for c in success_conditions(record) if c.required and not c.passed]
    assert failed == []


def test_bug_evasive_and_recovery_moves_keep_out_of_a_groups_o_space():
    """Generated mixed dev seed 45, PR2 (with an earlier objective setting): giving way's moves
    were checked against the costmap and the walkers, not the group, and one stepped into the
    o-space, where no trajectory of the planner was legal; the robot waited inside until the
    time limit. Evasive and recovery moves now keep out of o-spaces, with the group critic's
    escape from inside."""
    from socialnav.planner.context import PlanningContext
    from socialnav.planner.presets import build_local_planner
    from socialnav.planner.recovery import RecoveringPlanner
    from socialnav.world.grid import Costmap, GridGeometry

    a = np.radians([90, 180, 270])
    people = tuple(Person(i, (0.9 * np.cos(x), 0.9 * np.sin(x))) for i, x in enumerate(a))
    social = SocialContext(people, groups=(Group((0, 1, 2)),))  # o-space radius 0.6 at 0
    costmap = Costmap(np.zeros((80, 80), np.uint8), GridGeometry((80, 80), 0.1, (-4.0, -4.0)))
    planner = RecoveringPlanner(build_local_planner("paccet", PR2, social))

    def ctx(pose):
        return PlanningContext(
            np.asarray(pose, float),
            np.zeros(3),
            np.zeros(3),
            np.zeros((1, 2)),
            costmap,
            PR2,
            social=social,
        )

    moves = straight([(0.3, 0.0), (2.5, 0.0)], start=(1.5, 0.0))  # into the o-space, away
    assert planner._static_ok(ctx((1.5, 0.0, np.pi)), moves).tolist() == [False, True]
    out = straight([(0.1, 0.0), (2.5, 0.0)], start=(0.4, 0.0))  # from inside: deeper, out
    assert planner._static_ok(ctx((0.4, 0.0, 0.0)), out).tolist() == [False, True]


def test_a_local_planner_hands_its_objectives_thresholds_to_a_paccet_selection():
    """A planner built by hand (not from a preset) gets the objectives' thresholds too, unless
    its selection has its own; weighted sums are left as they are."""
    from socialnav.core.errors import ConfigurationError
    from socialnav.moo import PaccetOptions
    from socialnav.moo.selection import PaccetSelection, WeightedSum
    from socialnav.planner.local_planner import LocalPlanner, traditional_objectives
    from socialnav.planner.objectives import Objective

    nav = traditional_objectives()[0]
    social = Objective("ID", ((InterpersonalCritic(), 1.0),), 0.002)
    planner = LocalPlanner(PR2, [nav, social], PaccetSelection())
    assert planner.selection.options.indifference == (0.0, 0.002)
    own = PaccetSelection(options=PaccetOptions(indifference=(0.0, 0.5)))
    assert LocalPlanner(PR2, [nav, social], own).selection is own
    summed = WeightedSum([1.0, 1.0])
    assert LocalPlanner(PR2, [nav, social], summed).selection is summed
    with pytest.raises(Exception, match="finite number >= 0"):
        Objective("ID", ((InterpersonalCritic(), 1.0),), float("inf"))
    with pytest.raises(ConfigurationError, match=r"finite number >= 0, got \[0.1\]"):
        Objective("ID", ((InterpersonalCritic(), 1.0),), [0.1])  # type: ignore[arg-type]
    # thresholds that are not one per objective are refused when the planner is built, not in
    # plan() (which never raises)
    three = PaccetSelection(options=PaccetOptions(indifference=(0.0, 0.1, 0.1)))
    with pytest.raises(ConfigurationError, match="3 indifference thresholds for 2 objectives"):
        LocalPlanner(PR2, [nav, social], three)

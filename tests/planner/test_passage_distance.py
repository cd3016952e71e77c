"""People standing beside a narrow passage keep the passage's own distance in ID
(``InterpersonalCritic.passage_distance``): analytic corridors and the hallway it was built for."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.interpersonal import (
    ABREAST_MARGIN,
    PASSAGE_COMMIT,
    PASSAGE_REACH,
    PERSONAL_DISTANCE,
    InterpersonalCritic,
    partner_thresholds,
    passage_clearances,
)
from socialnav.world.costmap import add_obstacle_discs
from socialnav.world.grid import GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize

HALF = 1.26  # corridor half width (m): generated hallway dev seed 181
RES = 0.05


def corridor_ctx(
    people: tuple[Person, ...],
    robot: RobotModel = PIONEER,
    pose=(3.0, -0.18, 0.0),
    half: float = HALF,
) -> PlanningContext:
    """A 2.52 m corridor along x, the plan down its middle-ish line, people as obstacles the
    way the navigator marks them (their discs grown by half a cell diagonal, inflated)."""
    geometry = GridGeometry((80, 320), RES, (0.0, -2.0))
    walls = np.array([[[0.0, -half], [16.0, -half]], [[0.0, half], [16.0, half]]])
    costmap = inflate(rasterize(geometry, segments=walls), geometry, robot.inscribed_radius)
    social = SocialContext(people)
    if people:
        grown = social.radii() + RES * np.sqrt(2.0) / 2.0
        discs = np.column_stack([social.positions(), grown])
        costmap = add_obstacle_discs(costmap, discs, robot.inscribed_radius)
    path = np.column_stack([np.linspace(pose[0], 13.0, 60), np.full(60, pose[1])])
    return PlanningContext(
        pose=np.asarray(pose, dtype=float),
        velocity=np.zeros(3),
        goal=np.array([13.0, pose[1], 0.0]),
        global_path=path,
        costmap=costmap,
        robot=robot,
        social=social,
    )


def free_edge(robot: RobotModel, half: float = HALF) -> float:
    """Where the robot's centre can be nearest a wall (m from the corridor axis)."""
    return half - robot.inscribed_radius


def test_a_lone_person_is_passed_on_the_roomy_side():
    """One person 1.07 m from one wall, 1.45 m from the other: the far side's room."""
    ctx = corridor_ctx((Person(1, (5.0, -0.19)),), pose=(4.0, -0.18, 0.0))
    room = passage_clearances(ctx, 1.5)
    assert room[0] == pytest.approx(free_edge(PIONEER) + 0.19, abs=2 * RES)


def test_a_pair_side_by_side_leaves_only_the_gap_by_the_wall():
    """Dev seed 181: two people 0.69 m apart (no gap between them), 0.82 m from the wall."""
    pair = (Person(1, (5.0, -0.19)), Person(2, (5.0, 0.5)))
    ctx = corridor_ctx(pair, pose=(4.0, -0.18, 0.0))
    room = passage_clearances(ctx, 1.5)
    # the lower gap keeps the most from both: person 1 at the wall's free edge
    assert room[0] == pytest.approx(free_edge(PIONEER) - 0.19, abs=2 * RES)
    # person 2 is farther from that place than the threshold: no cap
    assert room[1] > 1.5
    own = partner_thresholds(ctx, 1.5, 0.05, passage=True, partners=False)
    assert own[0] == pytest.approx(room[0] - 0.05)
    assert own[1] == 1.5


def test_a_robot_already_in_the_narrower_gap_keeps_to_its_room():
    """A pair across the corridor leaves 0.82 m below and 0.51 m above. Approaching from afar,
    person 2 is held to the lower gap's distance (beyond the threshold: no cap); within
    PASSAGE_COMMIT m of them and beside them in the upper gap, to the upper gap's own room, so
    the pass through it costs nothing in ID (dev seed 183, Pioneer: held to the lower gap's
    distance there, it crawled and stalled). Neither gap keeps the 1.2 m personal space from
    both, so the robot may commit. Below them, on the lower gap's best line, nothing changes.
    Inside the personal space, off the gap's best line, the robot keeps its own offset."""
    pair = (Person(1, (5.0, -0.19)), Person(2, (5.0, 0.5)))
    edge = free_edge(PIONEER)
    upper = edge - 0.5  # where the robot's centre keeps most from person 2
    far = passage_clearances(corridor_ctx(pair, pose=(2.0, 1.0, 0.0)), 1.5)
    assert far[1] >= 1.5 - RES  # the lower gap's distance, about the threshold
    near = passage_clearances(corridor_ctx(pair, pose=(5.0 - PASSAGE_COMMIT + 0.1, 1.0, 0.0)), 1.5)
    assert near[1] == pytest.approx(upper, abs=RES)
    assert near[0] == pytest.approx(edge + 0.19, abs=2 * RES)  # the upper gap
    abreast = passage_clearances(corridor_ctx(pair, pose=(5.0, edge, 0.0)), 1.5)
    assert abreast[1] == pytest.approx(upper, abs=RES)
    off_line = passage_clearances(corridor_ctx(pair, pose=(5.0, 1.0, 0.0)), 1.5)
    # 7 cm short of the line, squeezed: its own offset (+ ABREAST_MARGIN)
    assert off_line[1] == pytest.approx(0.5 + ABREAST_MARGIN)
    below = passage_clearances(corridor_ctx(pair, pose=(4.2, -0.9, 0.0)), 1.5)
    assert below == pytest.approx(far, abs=RES)
    # past them, within PASSAGE_COMMIT m, still committed; in line with the person (not
    # beside them), both sides count as before
    past = passage_clearances(corridor_ctx(pair, pose=(6.0, edge, 0.0)), 1.5)
    assert past[1] == pytest.approx(upper, abs=RES)
    ahead = passage_clearances(corridor_ctx(pair, pose=(4.0, 0.5, 0.0)), 1.5)
    assert ahead[1] == pytest.approx(far[1])


def test_commitment_needs_a_place_that_keeps_the_space_from_everyone_on_its_own_side():
    """Person 1 at -0.3, person 2 at 0.9 in a 3.8 m corridor, the robot between them, above
    person 1. Above person 1 the best place keeps only ~0.8 m from person 2, below them
    ~1.4 m from everyone: the robot is not committed (newcomer trial: it was, by the
    distance from person 1 alone)."""
    pair = (Person(1, (5.0, -0.3)), Person(2, (5.0, 0.9)))
    near = passage_clearances(corridor_ctx(pair, pose=(4.0, 0.3, 0.0), half=1.9), 1.5)
    far = passage_clearances(corridor_ctx(pair, pose=(2.0, 0.3, 0.0), half=1.9), 1.5)
    assert near == pytest.approx(far)
    assert near[0] == pytest.approx(free_edge(PIONEER, 1.9) - 0.3, abs=2 * RES)


def test_bug_the_cross_section_went_through_a_wall_inside_a_persons_inflation():
    """A person 0.3 m from the wall of a 1.6 m corridor: the wall is inside their own
    inflation, and the cross-section went on through it into the free space beyond, giving
    1.5 m (0.45 m from the wall: 1.0 m). The room is on the corridor's side."""
    for y in (0.5, 0.45):
        ctx = corridor_ctx((Person(1, (5.0, y)),), pose=(4.0, -0.55, 0.0), half=0.8)
        room = passage_clearances(ctx, 1.5)
        assert room[0] == pytest.approx(free_edge(PIONEER, 0.8) + y, abs=2 * RES)


def test_no_commitment_to_a_gap_that_intrudes_when_the_other_side_keeps_the_space():
    """Person 2 alone: the lower side keeps 1.57 m from them, the upper gap 0.57 m. A robot
    beside them in the upper gap, not yet abreast of them, is not held to 0.57 m: the
    way round keeps the personal space, and ID's crawl makes it stop and replan (dev seed 107,
    Pioneer: committed, it passed at 1.06 m). Once abreast of them inside it, it keeps its own
    offset."""
    alone = (Person(2, (5.0, 0.5)),)
    near = passage_clearances(corridor_ctx(alone, pose=(4.0, 1.0, 0.0)), 1.5)
    assert near[0] > 1.5
    abreast = passage_clearances(corridor_ctx(alone, pose=(4.6, 1.0, 0.0)), 1.5)
    assert abreast[0] == pytest.approx(0.5 + ABREAST_MARGIN)


def test_bug_a_robot_inside_the_personal_space_was_held_to_a_room_it_could_not_reach():
    """Generated hallway dev seeds 73 and 196, Pioneer: beside a person standing 0.77-0.92 m
    away, the robot was held to a room it could not reach (a place a cell nearer the wall than
    its footprint allows, or the far side of the person with 1.5 m of room, behind it now), so
    every step on along its own line cost ID and the robot crawled back and forth until the
    time limit. Squeezed abreast of the person (inside the personal space, on a side that
    cannot keep it), the room is at most the robot's own offset from them (plus
    ABREAST_MARGIN, a centimetre short of the ID margin): driving on along it costs nothing,
    moving in, by 2 cm or more, still does.
    Before that, nothing changes. Two people standing 1.2 m apart, the robot between them a
    metre before them, already inside both personal spaces: not abreast, so not held to the
    gap between them (the way round keeps 1.35 m)."""
    person = (Person(1, (5.0, -0.19)),)
    y = -0.9  # in the lower gap, 0.71 m to the side of the person
    before = passage_clearances(corridor_ctx(person, pose=(4.2, y, 0.0)), 1.5)
    assert np.hypot(0.8, 0.71) < PERSONAL_DISTANCE  # inside, but 0.8 m before them
    assert before[0] == pytest.approx(free_edge(PIONEER) - 0.19, abs=2 * RES)  # its side's
    ctx = corridor_ctx(person, pose=(4.6, y, 0.0))
    assert passage_clearances(ctx, 1.5)[0] == pytest.approx(0.71 + ABREAST_MARGIN)
    from test_social_critics import straight

    critic = InterpersonalCritic(evaluation="max_over_time", passage_distance=True)
    on = straight([(4.8, y), (5.0, y), (5.4, y)], start=(4.6, y))
    assert np.all(critic.score(on, ctx).cost == 0.0)
    # moving in costs, even by 2 cm (no ratchet of free steps, cycle after cycle)
    inward = straight([(5.0, y + 0.2), (5.0, y + 0.02)], start=(4.6, y))
    assert np.all(critic.score(inward, ctx).cost > 0.0)
    pair = (Person(1, (5.0, -0.3)), Person(2, (5.0, 0.9)))
    between = passage_clearances(corridor_ctx(pair, pose=(4.0, 0.3, 0.0), half=1.9), 1.5)
    assert between[0] == pytest.approx(free_edge(PIONEER, 1.9) - 0.3, abs=2 * RES)
    # a PR2 0.7 m before them (its front 12.5 cm short of them) is not abreast either
    pr2 = passage_clearances(corridor_ctx(pair, robot=PR2, pose=(4.3, 0.3, 0.0), half=1.9), 1.5)
    assert pr2 == pytest.approx(
        passage_clearances(corridor_ctx(pair, robot=PR2, pose=(2.0, 0.3, 0.0), half=1.9), 1.5)
    )


def test_a_squeeze_is_only_where_the_robots_side_cannot_keep_the_personal_space():
    """Newcomer trial: abreast of someone inside 1.2 m on a side that keeps the personal space
    (a 3.8 m corridor, a person in its middle; a 2.8 m one, 1.35 m kept above the person), the
    threshold stays what the passage gives (1.5 m, 1.3 m) and ID still pushes the robot out:
    a cap there let it stay 0.55 m from the person for nothing."""
    critic = InterpersonalCritic(evaluation="max_over_time", passage_distance=True)
    from test_social_critics import straight

    wide = corridor_ctx((Person(1, (5.0, 0.0)),), pose=(4.6, 0.6, 0.0), half=1.9)
    assert partner_thresholds(wide, 1.5, 0.05, passage=True, partners=False)[0] == 1.5
    cost = critic.score(straight([(5.0, 1.0), (5.0, 0.6), (5.0, 0.5)], start=(4.6, 0.6)), wide)
    assert cost.cost[0] < cost.cost[1] < cost.cost[2]  # out is better, in is worse
    room_above = corridor_ctx((Person(1, (5.0, -0.19)),), pose=(4.9, 0.95, 0.0), half=1.4)
    own = partner_thresholds(room_above, 1.5, 0.05, passage=True, partners=False)[0]
    afar = corridor_ctx((Person(1, (5.0, -0.19)),), pose=(3.0, 0.95, 0.0), half=1.4)
    assert own == partner_thresholds(afar, 1.5, 0.05, passage=True, partners=False)[0]
    assert own >= PERSONAL_DISTANCE + 0.05 - 1e-9


def test_a_wide_passage_keeps_the_personal_space():
    """Where the passage leaves the 1.2 m personal space, the threshold stays above it: a
    person in the middle of a 3.2 m corridor, 1.27 m from where a PR2's centre can be."""
    half = 1.6
    ctx = corridor_ctx((Person(1, (5.0, 0.0)),), robot=PR2, pose=(4.0, -0.5, 0.0), half=half)
    room = passage_clearances(ctx, 1.5)
    assert room[0] == pytest.approx(free_edge(PR2, half), abs=2 * RES)
    own = partner_thresholds(ctx, 1.5, 0.05, passage=True, partners=False)
    assert own[0] == pytest.approx(PERSONAL_DISTANCE + 0.05)
    narrower = corridor_ctx((Person(1, (5.0, 0.0)),), robot=PR2, pose=(4.0, -0.5, 0.0), half=1.4)
    assert partner_thresholds(narrower, 1.5, 0.05, passage=True, partners=False)[0] == (
        pytest.approx(passage_clearances(narrower, 1.5)[0] - 0.05)
    )


def test_walkers_and_far_people_keep_the_threshold():
    """Only people standing near the plan are looked at; without a plan nobody is."""
    walker = Person(1, (5.0, -0.19), velocity=(-1.0, 0.0))
    far = Person(2, (5.0, 3.5))  # beyond the wall, never near the plan
    ctx = corridor_ctx((walker, far), pose=(4.0, -0.18, 0.0))
    assert np.all(np.isinf(passage_clearances(ctx, 1.5)))
    assert np.all(partner_thresholds(ctx, 1.5, 0.05, passage=True, partners=False) == 1.5)
    no_plan = corridor_ctx((Person(1, (5.0, -0.19)),))
    no_plan = dataclasses.replace(no_plan, global_path=np.zeros((0, 2)))
    assert np.isinf(passage_clearances(no_plan, 1.5)[0])


def test_a_walker_crossing_the_section_does_not_close_the_passage():
    """A walker in the gap now walks on: the gap still counts."""
    pair = (Person(1, (5.0, -0.19)), Person(2, (5.0, 0.5)))
    alone = passage_clearances(corridor_ctx(pair, pose=(4.0, -0.18, 0.0)), 1.5)
    walker = Person(3, (5.0, -0.95), velocity=(0.0, 1.0))  # in the gap by the wall now
    crossed = passage_clearances(corridor_ctx((*pair, walker), pose=(4.0, -0.18, 0.0)), 1.5)
    assert crossed[0] == pytest.approx(alone[0], abs=RES)


def test_bug_id_rises_toward_the_closest_point_so_the_robot_crawls():
    """Dev seed 181 (Pioneer): beside a pair standing 0.82 m from the wall, ID rose with every
    step toward the closest point, so slower commands always scored better; the robot
    crawled and the progress checker gave up there. With the passage's own distance, the
    way through the gap costs nothing in ID until the robot leaves the gap's best line."""
    pair = (Person(1, (5.0, -0.19)), Person(2, (5.0, 0.5)))
    y = -free_edge(PIONEER)
    ctx = corridor_ctx(pair, pose=(4.0, y, 0.0))
    from test_social_critics import straight

    ends = [(4.2, y), (4.6, y), (5.0, y)]  # slow, faster, fastest along the gap's line
    trajs = straight(ends, start=(4.0, y))
    plain = InterpersonalCritic(evaluation="max_over_time").score(trajs, ctx).cost
    assert plain[0] < plain[1] < plain[2]  # the crawl: slower is always better
    critic = InterpersonalCritic(evaluation="max_over_time", passage_distance=True)
    assert np.all(critic.score(trajs, ctx).cost == 0.0)
    inward = straight([(5.0, y + 0.2)], start=(4.0, y))  # toward the person: still costs
    assert critic.score(inward, ctx).cost[0] > 0.0


def test_bug_pioneer_crawled_beside_a_pair_standing_by_the_wall_until_the_time_limit():
    """Generated hallway dev seed 181, Pioneer: a pair stands side by side 0.82 m from the
    wall of a 2.52 m corridor, a third person just past them. The robot crawled into the gap
    at 0.08 m/s, stopped 0.3 m from the pair, waited and timed out (76 s). Now it drives
    through the gap and arrives."""
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode
    from socialnav.sim.stack import StackController

    record = run_episode(
        generate("hallway", 181), StackController("paccet"), "pioneer", seed=181
    ).record
    assert [c.name for c in success_conditions(record) if c.required and not c.passed] == []
    assert float(record.times[-1]) < 40.0


def test_bug_pioneer_stalled_in_the_narrower_gap_beside_a_pair():
    """Generated hallway dev seed 183, Pioneer: a pair stands across a 2.65 m corridor,
    leaving 0.77 m on one side and 0.61 m on the other. Giving way to a walker from behind put
    the robot, and its plan, on the narrower side; held to the wider side's distance, it
    crawled into the gap at 0.05 m/s and stalled 0.08 m from the person until the time limit.
    Now it drives through and arrives."""
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode
    from socialnav.sim.stack import StackController

    record = run_episode(
        generate("hallway", 183), StackController("paccet"), "pioneer", seed=183
    ).record
    assert [c.name for c in success_conditions(record) if c.required and not c.passed] == []
    assert float(record.times[-1]) < 35.0


def test_bug_pioneer_crawled_beside_a_person_a_cell_out_of_reach_until_the_time_limit():
    """Generated hallway dev seed 73, Pioneer: two people stand across a 2.71 m corridor; the
    robot went into the 0.91 m gap by the wall and stopped 0.87 m beside the person, against an
    estimated room of 0.95 m its footprint could not reach, and crawled there from 36 s until
    the time limit (66 s). Now it drives through and arrives."""
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode
    from socialnav.sim.stack import StackController

    record = run_episode(
        generate("hallway", 73), StackController("paccet"), "pioneer", seed=73
    ).record
    assert [c.name for c in success_conditions(record) if c.required and not c.passed] == []
    assert float(record.times[-1]) < 30.0


@settings(max_examples=60, deadline=None)
@given(
    people=st.lists(
        st.tuples(
            st.floats(-3.0, 19.0),
            st.floats(-4.0, 4.0),
            st.sampled_from([0.0, 0.05, 1.0]),
        ),
        max_size=6,
    ),
    plan=st.lists(st.tuples(st.floats(-2.0, 18.0), st.floats(-3.0, 3.0)), max_size=4),
    robot=st.sampled_from([PIONEER, PR2]),
)
def test_any_scene_gives_a_distance_or_inf_and_never_raises(people, plan, robot):
    """People anywhere (on the plan, in walls, off the map), degenerate plans (none, one point,
    repeated points): one value per person, finite and within the cross-section's reach, or
    inf; walkers always inf."""
    crowd = tuple(Person(i, (x, y), velocity=(v, 0.0)) for i, (x, y, v) in enumerate(people))
    ctx = corridor_ctx(crowd, robot=robot, pose=(4.0, 0.0, 0.0))
    ctx = dataclasses.replace(ctx, global_path=np.asarray(plan, dtype=float).reshape(-1, 2))
    room = passage_clearances(ctx, 1.5)
    assert room.shape == (len(crowd),)
    finite = np.isfinite(room)
    assert np.all((room[finite] >= 0.0) & (room[finite] <= PASSAGE_REACH + 1e-9))
    walking = np.array([v >= 0.1 for _, _, v in people], dtype=bool)
    assert not np.any(finite & walking)
    own = partner_thresholds(ctx, 1.5, 0.05, passage=True, partners=False)
    assert np.all((own > 0.0) & (own <= 1.5))

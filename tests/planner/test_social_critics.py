"""Social critics on analytic cases, forecast mode, person slots and permutation equivariance."""

import numpy as np
import pytest

from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import PR2
from socialnav.core.scene import Artwork, Group, Person, SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics import CRITICS
from socialnav.planner.critics.activity_space import ActivitySpaceCritic
from socialnav.planner.critics.group import GroupCritic
from socialnav.planner.critics.interpersonal import InterpersonalCritic
from socialnav.planner.critics.social_goal import SocialGoalCritic
from socialnav.social.goals import SocialGoal
from socialnav.world.grid import Costmap, GridGeometry

CAP = np.exp(10.0)  # exp(1 / min_distance) with the default min_distance 0.1 m


def make_ctx(social=None, pose=(0.0, 0.0, 0.0), social_goal=None, predict=True):
    costmap = Costmap(np.zeros((4, 4), np.uint8), GridGeometry((4, 4), 1.0))
    return PlanningContext(
        pose=np.asarray(pose, dtype=float),
        velocity=np.zeros(3),
        goal=np.zeros(3),
        global_path=np.zeros((0, 2)),
        costmap=costmap,
        robot=PR2,
        social=social if social is not None else SocialContext(),
        social_goal=social_goal,
        predict_people=predict,
    )


def straight(ends, start=(0.0, 0.0), steps=5, duration=1.0, yaw=0.0):
    """Straight trajectories from ``start`` to each end point ``(N, 2)``."""
    ends = np.asarray(ends, dtype=float).reshape(-1, 2)
    s = np.linspace(0.0, 1.0, steps)
    xy = np.asarray(start) + s[None, :, None] * (ends[:, None, :] - np.asarray(start))
    yaws = np.full((*xy.shape[:2], 1), yaw)
    return Trajectories(np.zeros((len(ends), 3)), np.concatenate([xy, yaws], -1), s * duration)


def stationary(point, t):
    poses = np.tile(np.append(point, 0.0), (1, len(t), 1))
    return Trajectories(np.zeros((1, 3)), poses, np.asarray(t, dtype=float))


def crowd(*points, velocities=None):
    velocities = velocities or [(0.0, 0.0)] * len(points)
    return SocialContext(
        tuple(Person(i, p, v) for i, (p, v) in enumerate(zip(points, velocities, strict=True)))
    )


# ------------------------------------------------------------------------------ interpersonal


def test_interpersonal_paper_formula():
    ctx = make_ctx(crowd((3.0, 0.0)))
    trajs = straight([(2.0, 0.0), (1.5, 0.0), (0.5, 0.0), (-1.0, 0.0)])  # ID = 1, 1.5, 2.5, 4
    score = InterpersonalCritic().score(trajs, ctx)
    np.testing.assert_allclose(score.cost, [np.e, np.exp(1 / 1.5), 0.0, 0.0])
    assert not score.illegal["person_collision"].any()


def test_interpersonal_cap_and_collision():
    ctx = make_ctx(crowd((3.0, 0.0)))
    trajs = straight([(2.95, 0.0), (2.4, 0.0), (2.0, 0.0)])  # ID = 0.05, 0.6, 1.0
    score = InterpersonalCritic().score(trajs, ctx)
    np.testing.assert_allclose(score.cost, [CAP, np.exp(1 / 0.6), np.e])
    # collision: centre distance < 0.25 + PR2 inscribed radius 0.325 (0.6 m is clear)
    np.testing.assert_array_equal(score.illegal["person_collision"], [True, False, False])
    circ = InterpersonalCritic(footprint_disc="circumscribed").score(trajs, ctx)
    np.testing.assert_array_equal(circ.illegal["person_collision"], [True, True, False])
    off = InterpersonalCritic(collision_check=False).score(trajs, ctx)
    assert "person_collision" not in off.illegal


def test_interpersonal_edge_distance():
    ctx = make_ctx(crowd((3.0, 0.0)))
    trajs = straight([(1.0, 0.0), (0.5, 0.0)])  # centre 2.0 / 2.5 → edge 1.425 / 1.925
    cost = InterpersonalCritic(distance="edge").score(trajs, ctx).cost
    edge = 2.0 - 0.25 - PR2.inscribed_radius
    np.testing.assert_allclose(cost, [np.exp(1 / edge), 0.0])


def test_interpersonal_forecast_with_moving_person():
    t = np.linspace(0.0, 2.0, 9)
    trajs = stationary((0.0, 0.0), t)
    walker = crowd((3.0, 0.0), velocities=[(-1.0, 0.0)])  # at 1.0 m when t = 2 s
    last = InterpersonalCritic(evaluation="last").score(trajs, make_ctx(walker)).cost
    over = InterpersonalCritic(evaluation="max_over_time").score(trajs, make_ctx(walker)).cost
    frozen = InterpersonalCritic(evaluation="max_over_time").score(
        trajs, make_ctx(walker, predict=False)
    )
    np.testing.assert_allclose(last, [0.0])  # the paper: end point vs people now (3 m away)
    np.testing.assert_allclose(over, [np.e])
    np.testing.assert_allclose(frozen.cost, [0.0])
    # a person walking into the robot's spot makes the stationary trajectory illegal
    runner = crowd((3.0, 0.0), velocities=[(-2.0, 0.0)])  # reaches the robot at t = 1.5 s
    hit = InterpersonalCritic().score(trajs, make_ctx(runner))
    assert hit.illegal["person_collision"][0]


def test_interpersonal_person_slots():
    # person 0 is nearest the robot at cycle start, person 1 is nearest the trajectory end
    ppl = [(1.0, 0.0), (0.0, 3.0)]
    trajs = straight([(0.0, 2.0)])
    expected = {None: np.e, 0: 0.0, 1: np.e, 2: 0.0}
    for points in (ppl, ppl[::-1]):  # person order does not matter
        ctx = make_ctx(crowd(*points))
        for slot, value in expected.items():
            cost = InterpersonalCritic(person_slot=slot).score(trajs, ctx).cost
            np.testing.assert_allclose(cost, [value], err_msg=f"slot {slot}")


def test_interpersonal_no_people():
    score = InterpersonalCritic().score(straight([(1.0, 0.0)] * 3), make_ctx())
    np.testing.assert_array_equal(score.cost, np.zeros(3))


# ------------------------------------------------------------------------------ group


def group_ctx(radius=0.9):
    a = np.radians([90, 180, 270])
    ppl = tuple(Person(i, (radius * np.cos(x), radius * np.sin(x))) for i, x in enumerate(a))
    return make_ctx(SocialContext(ppl, groups=(Group((0, 1, 2)),)), pose=(5.0, 0.0, np.pi))


def test_group_distance_formula():
    ctx = group_ctx()  # o-space: centre (0, 0), radius 0.6
    trajs = straight([(0.75, 0.0), (0.9, 0.0), (0.3, 0.0), (2.0, 0.0)], start=(5.0, 0.0))
    score = GroupCritic().score(trajs, ctx)
    np.testing.assert_allclose(score.cost, [np.exp(1 / 0.15), 0.0, CAP, 0.0])
    assert not score.illegal
    wide = GroupCritic(influence_range=1.5).score(trajs, ctx).cost
    np.testing.assert_allclose(wide[[1, 3]], [np.exp(1 / 0.3), np.exp(1 / 1.4)])


def test_group_max_over_time_and_illegal_inside():
    ctx = group_ctx()
    # passes through the centre and leaves on the far side (ends 1.0 m from the o-space edge)
    through = straight([(-1.6, 0.0), (2.0, 2.0)], start=(1.6, 0.0))
    last = GroupCritic().score(through, ctx).cost
    over = GroupCritic(evaluation="max_over_time", illegal_inside=True).score(through, ctx)
    np.testing.assert_allclose(last, [0.0, 0.0])
    assert over.cost[0] == pytest.approx(CAP)
    np.testing.assert_array_equal(over.illegal["ospace_intrusion"], [True, False])


def test_group_ignores_single_member_groups():
    ctx = make_ctx(SocialContext((Person(0, (0.0, 0.0)),), groups=(Group((0,)),)))
    assert GroupCritic().score(straight([(0.1, 0.0)]), ctx).cost[0] == 0.0


# ------------------------------------------------------------------------------ social goal


def test_social_goal_formula_and_options():
    goal = SocialGoal(np.array([3.0, 0.0, 0.5]), "queue_tail")
    ctx = make_ctx(social_goal=goal)
    trajs = straight([(1.0, 0.0), (2.0, 0.0), (3.0, 0.0)])
    np.testing.assert_allclose(SocialGoalCritic().score(trajs, ctx).cost, np.exp([2.0, 1.0, 0.0]))
    rel = SocialGoalCritic(relative=True).score(trajs, ctx).cost
    np.testing.assert_allclose(rel, np.exp([-1.0, -2.0, -3.0]))
    head = SocialGoalCritic(heading_weight=2.0, heading_radius=0.5).score(trajs, ctx).cost
    np.testing.assert_allclose(head, [np.exp(2.0), np.e, 1.0 + 2.0 * 0.5])
    wp = SocialGoal(np.array([3.0, 0.0, 0.5]), "waypoint", is_waypoint=True)
    no_head = SocialGoalCritic(heading_weight=2.0).score(trajs, make_ctx(social_goal=wp)).cost
    np.testing.assert_allclose(no_head, np.exp([2.0, 1.0, 0.0]))
    raw = SocialGoalCritic().score(trajs, make_ctx(social_goal=np.array([3.0, 0.0, 0.0]))).cost
    np.testing.assert_allclose(raw, np.exp([2.0, 1.0, 0.0]))
    far = SocialGoalCritic(max_exponent=5.0).score(straight([(-100.0, 0.0)]), ctx).cost
    np.testing.assert_allclose(far, [np.exp(5.0)])


def test_social_goal_absent_is_zero():
    np.testing.assert_array_equal(
        SocialGoalCritic().score(straight([(1.0, 0.0)] * 2), make_ctx()).cost, [0.0, 0.0]
    )


# ------------------------------------------------------------------------------ activity space


def art_ctx():
    # artwork at the origin on a wall along x, facing +y; viewer 2 m in front
    social = SocialContext(
        (Person(0, (0.0, 2.0), yaw=-np.pi / 2),),
        artworks=(Artwork((0.0, 0.0), 2.0, np.pi / 2, (0,)),),
    )
    return make_ctx(social, pose=(-3.0, 0.1, 0.0))


def test_activity_space_measures():
    ctx = art_ctx()
    t = np.array([0.0, 0.5, 1.0])
    inside = stationary((0.0, 0.1), t)  # 0.1 m inside (nearest edge: the artwork)
    outside = stationary((0.0, 2.5), t)
    for trajs, expected in ((inside, (0.1, 1.0, 0.1)), (outside, (0.0, 0.0, 0.0))):
        for measure, value in zip(("max_depth", "time", "depth_time"), expected, strict=True):
            cost = ActivitySpaceCritic(measure=measure).score(trajs, ctx).cost
            np.testing.assert_allclose(cost, [value], err_msg=measure)
    crossing = straight([(3.0, 0.5), (-3.0, 3.0)], start=(-3.0, 0.5), steps=61)
    score = ActivitySpaceCritic(illegal_inside=True).score(crossing, ctx)
    assert score.cost[0] > 0.3 and score.cost[1] == 0.0
    np.testing.assert_array_equal(score.illegal["activity_space_intrusion"], [True, False])
    margin = ActivitySpaceCritic(margin=0.2).score(stationary((0.0, 2.1), t), ctx).cost
    np.testing.assert_allclose(margin, [0.1])


# ------------------------------------------------------------------------------ shared contract

SOCIAL = SocialContext(
    (
        Person(0, (1.0, 0.5), (0.2, 0.0)),
        Person(1, (-0.5, 1.0), (0.0, -0.3)),
        Person(2, (4.0, 4.9)),
        Person(3, (3.1, 4.0)),
        Person(4, (4.9, 4.0)),
        Person(5, (0.0, -1.0), yaw=-np.pi / 2),
    ),
    groups=(Group((2, 3, 4)),),
    artworks=(Artwork((0.0, -2.5), 1.2, np.pi / 2, (5,)),),
)
ALL = [
    InterpersonalCritic(),
    InterpersonalCritic(evaluation="max_over_time", distance="edge", person_slot=1),
    GroupCritic(evaluation="max_over_time", illegal_inside=True, influence_range=1.0),
    SocialGoalCritic(heading_weight=1.0, heading_radius=2.0),
    ActivitySpaceCritic(measure="depth_time", illegal_inside=True),
]


@pytest.mark.parametrize("critic", ALL, ids=lambda c: f"{c.name}")
def test_permutation_equivariance_and_shapes(critic):
    rng = np.random.default_rng(3)
    n, steps = 64, 12
    t = np.linspace(0.0, 1.7, steps)
    xy = rng.uniform(-3.0, 5.0, (n, 1, 2)) + np.cumsum(rng.normal(0, 0.2, (n, steps, 2)), axis=1)
    poses = np.concatenate([xy, rng.uniform(-np.pi, np.pi, (n, steps, 1))], axis=-1)
    trajs = Trajectories(rng.normal(size=(n, 3)), poses, t)
    goal = SocialGoal(np.array([4.0, 3.2, -np.pi / 2]), "o_formation")
    ctx = make_ctx(SOCIAL, pose=(0.0, 0.0, 0.0), social_goal=goal)
    base = critic.score(trajs, ctx)
    assert base.cost.shape == (n,) and np.all(np.isfinite(base.cost)) and np.all(base.cost >= 0)
    assert np.ptp(base.cost) > 0  # the case exercises the critic
    perm = rng.permutation(n)
    moved = critic.score(trajs.take(perm), ctx)
    np.testing.assert_allclose(moved.cost, base.cost[perm])
    assert moved.illegal.keys() == base.illegal.keys()
    for reason, mask in base.illegal.items():
        assert mask.shape == (n,) and mask.dtype == bool
        np.testing.assert_array_equal(moved.illegal[reason], mask[perm])


def test_registered_and_validated():
    for name, cls in [
        ("interpersonal", InterpersonalCritic),
        ("group", GroupCritic),
        ("social_goal", SocialGoalCritic),
        ("activity_space", ActivitySpaceCritic),
    ]:
        assert CRITICS.get(name) is cls and cls.name == name and cls.unit
    bad = [
        lambda: InterpersonalCritic(evaluation="mean"),
        lambda: InterpersonalCritic(person_slot=-1),
        lambda: InterpersonalCritic(distance="surface"),
        lambda: InterpersonalCritic(min_distance=0.0),
        lambda: GroupCritic(evaluation="sum"),
        lambda: SocialGoalCritic(max_exponent=1000.0),
        lambda: ActivitySpaceCritic(measure="area"),
    ]
    for make in bad:
        with pytest.raises(ConfigurationError):
            make()


def test_bug_inside_an_o_space_only_going_deeper_is_illegal():
    """Generated mixed dev seed 45, PR2: giving way stepped into the group's o-space, where
    every trajectory entered it, so none was legal and the robot waited inside until the time
    limit. From inside, only a trajectory nearer the centre than now intrudes (an escape, as
    for a person overlapping the robot); from outside, nothing changes."""
    ctx = group_ctx()  # o-space: centre (0, 0), radius 0.6
    inside = make_ctx(ctx.social, pose=(0.3, 0.0, 0.0))
    t = np.linspace(0.0, 1.0, 5)
    moves = Trajectories(
        np.zeros((4, 3)),
        np.concatenate(
            [
                stationary((0.3, 0.0), t).poses,
                straight([(1.5, 0.0)], start=(0.3, 0.0)).poses,
                straight([(0.1, 0.0)], start=(0.3, 0.0)).poses,
                straight([(0.3, 0.05)], start=(0.3, 0.0)).poses,  # tangent: never nearer
            ]
        ),
        t,
    )
    critic = GroupCritic(evaluation="max_over_time", illegal_inside=True)
    np.testing.assert_array_equal(
        critic.score(moves, inside).illegal["ospace_intrusion"], [False, False, True, False]
    )
    outside = make_ctx(ctx.social, pose=(1.5, 0.0, 0.0))
    entering = straight([(0.3, 0.0), (2.5, 0.0)], start=(1.5, 0.0))
    np.testing.assert_array_equal(
        critic.score(entering, outside).illegal["ospace_intrusion"], [True, False]
    )


def test_inside_an_activity_space_only_going_deeper_is_illegal():
    ctx = art_ctx()  # viewer 2 m in front of the artwork: the space between them
    inside = make_ctx(ctx.social, pose=(0.0, 1.0, 0.0))
    t = np.linspace(0.0, 1.0, 5)
    still = stationary((0.0, 1.0), t)
    leaving = straight([(3.0, 1.0)], start=(0.0, 1.0))
    deeper = straight([(0.5, 1.0)], start=(0.95, 1.0))
    critic = ActivitySpaceCritic(illegal_inside=True)
    for trajs, expected in ((still, False), (leaving, False)):
        assert critic.score(trajs, inside).illegal["activity_space_intrusion"][0] == expected
    edge = make_ctx(ctx.social, pose=(0.95, 1.0, 0.0))
    assert critic.score(deeper, edge).illegal["activity_space_intrusion"][0]

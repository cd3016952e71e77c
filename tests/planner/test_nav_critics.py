"""Navigation critics (path/goal distance, occupancy, heading) on analytic maps."""

from __future__ import annotations

import numpy as np
import pytest
from _planner_helpers import blank, context, straight

from socialnav.core.robot import PIONEER, PR2, RobotModel, rectangle
from socialnav.core.scene import Person, SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner.critics import (
    CRITICS,
    CriticUnavailable,
    GoalDistanceCritic,
    HeadingCritic,
    OccupancyCritic,
    PathDistanceCritic,
)
from socialnav.planner.critics.map_grid import bfs_distance, local_plan_cells
from socialnav.planner.rollout import RolloutParams, rollout
from socialnav.world.costmap import add_obstacle_discs
from socialnav.world.grid import INSCRIBED, LETHAL, UNKNOWN, Costmap, GridGeometry
from socialnav.world.inflation import circumscribed_cost, inflate
from socialnav.world.raster import rasterize

TINY = RobotModel("tiny", True, rectangle(0.04, 0.04), 0.5, -0.1, 0.3, 1.0, 2.5, 2.5, 3.2)


def test_registered_names():
    for name in ("path_distance", "goal_distance", "occupancy", "heading"):
        assert name in CRITICS


# ---- BFS --------------------------------------------------------------------------------


def test_bfs_is_manhattan_on_an_empty_grid():
    d = bfs_distance(np.ones((7, 9), dtype=bool), np.array([[3, 4]]))
    r, c = np.mgrid[0:7, 0:9]
    np.testing.assert_array_equal(d, np.abs(r - 3) + np.abs(c - 4))


def test_bfs_goes_around_a_wall_and_marks_enclosed_cells_unreachable():
    passable = np.ones((5, 5), dtype=bool)
    passable[0:4, 2] = False  # wall with a gap at row 4
    d = bfs_distance(passable, np.array([[0, 0]]))
    assert d[0, 1] == 1
    assert d[1, 3] == 4 + 3 + 3  # down to row 4, across to column 3, back up to row 1
    assert np.isinf(d[0, 2])
    enclosed = np.ones((5, 5), dtype=bool)
    enclosed[1:4, 1:4] = False
    enclosed[2, 2] = True
    assert np.isinf(bfs_distance(enclosed, np.array([[0, 0]]))[2, 2])


def _reference_bfs(passable, seeds):
    from collections import deque

    dist = np.full(passable.shape, np.inf)
    queue = deque()
    for r, c in seeds:
        dist[r, c] = 0
        queue.append((r, c))
    while queue:
        r, c = queue.popleft()
        for rr, cc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if (
                0 <= rr < passable.shape[0]
                and 0 <= cc < passable.shape[1]
                and passable[rr, cc]
                and np.isinf(dist[rr, cc])
            ):
                dist[rr, cc] = dist[r, c] + 1
                queue.append((rr, cc))
    return dist


@pytest.mark.parametrize("seed", range(12))
def test_bfs_matches_a_queue_bfs_on_random_maps(seed):
    rng = np.random.default_rng(seed)
    rows, cols = rng.integers(1, 40, 2)
    passable = rng.random((rows, cols)) > rng.uniform(0.0, 0.5)
    seeds = np.argwhere(rng.random((rows, cols)) < 0.03)  # seeds may sit on blocked cells
    seeds = seeds if seeds.size else np.array([[0, 0]])
    np.testing.assert_array_equal(bfs_distance(passable, seeds), _reference_bfs(passable, seeds))


def test_bfs_counts_past_255_steps():
    passable = np.ones((41, 41), dtype=bool)
    passable[1::4, :-1] = False  # a serpentine corridor
    passable[3::4, 1:] = False
    d = bfs_distance(passable, np.array([[0, 0]]))
    np.testing.assert_array_equal(d, _reference_bfs(passable, np.array([[0, 0]])))
    assert d[np.isfinite(d)].max() > 255


def test_bfs_early_stop_is_exact_inside_the_settled_region():
    rng = np.random.default_rng(3)
    passable = rng.random((40, 50)) > 0.25
    passable[20, 25] = True
    full = bfs_distance(passable, np.array([[20, 25]]))
    region = (slice(15, 26), slice(20, 31))
    part = bfs_distance(passable, np.array([[20, 25]]), settle=region)
    np.testing.assert_array_equal(part[region], full[region])


# ---- path / goal distance ---------------------------------------------------------------


def _corridor_ctx(robot=TINY):
    cm = blank(40, 100)  # 5 m × 2 m at 0.05
    path = np.array([[0.5, 1.0], [4.5, 1.0]])
    return context(cm, robot, pose=(0.5, 1.0, 0.0), path=path, goal=(4.5, 1.0, 0.0))


def test_path_and_goal_distance_in_metres():
    ctx = _corridor_ctx()
    ends = np.array([[2.025, 1.025], [2.025, 1.525], [4.475, 1.025]])
    tr = straight(ends, start=(0.5, 1.0))
    p = PathDistanceCritic().score(tr, ctx)
    g = GoalDistanceCritic().score(tr, ctx)
    np.testing.assert_allclose(p.cost, [0.0, 0.5, 0.0], atol=1e-9)
    # local goal cell (row 20, col 90) — the last plan cell — 4-connected steps × 0.05
    np.testing.assert_allclose(g.cost, [50 * 0.05, 60 * 0.05, 0.05], atol=1e-9)
    assert not any(m.any() for m in p.illegal.values())


def test_local_goal_is_the_last_plan_cell_inside_the_window():
    cm = blank(40, 40)  # 2 m × 2 m
    cells = local_plan_cells(cm, np.array([[0.5, 1.0], [5.0, 1.0]]))
    assert cells[-1, 1] == 39 and cells[0, 1] == 10


def test_end_on_obstacle_or_enclosed_cell_is_unreachable_and_off_map_is_illegal():
    ctx = _corridor_ctx()
    costs = ctx.costmap.costs.copy()
    costs[:, 60] = LETHAL  # wall across the corridor at x = 3.0..3.05
    cm = Costmap(costs, ctx.costmap.geometry)
    ctx = context(cm, TINY, pose=(0.5, 1.0, 0.0), path=ctx.global_path, goal=ctx.goal)
    tr = straight(np.array([[3.025, 1.0], [2.0, 1.0], [6.0, 1.0]]), start=(0.5, 1.0))
    g = GoalDistanceCritic().score(tr, ctx)
    assert g.illegal["unreachable"].tolist() == [True, True, False]  # goal is behind the wall
    assert g.illegal["off_map"].tolist() == [False, False, True]
    p = PathDistanceCritic().score(tr, ctx)
    assert p.illegal["unreachable"].tolist() == [True, False, False]
    assert np.isinf(p.cost[0]) and np.isfinite(p.cost[1])


def test_cells_under_the_current_footprint_let_the_wavefront_through():
    cm = blank(40, 100)
    costs = cm.costs.copy()
    costs[:, 8:13] = INSCRIBED  # the robot stands in an inscribed band
    cm = Costmap(costs, cm.geometry)
    ctx = context(
        cm,
        PIONEER,
        pose=(0.5, 1.0, 0.0),
        path=np.array([[0.5, 1.0], [4.5, 1.0]]),
        goal=(4.5, 1.0, 0.0),
    )
    tr = straight(np.array([[1.0, 1.0]]), start=(0.5, 1.0))
    assert np.isfinite(GoalDistanceCritic().score(tr, ctx).cost[0])
    far = context(cm, PIONEER, pose=(1.5, 1.0, 0.0), path=ctx.global_path, goal=ctx.goal)
    tr2 = straight(np.array([[0.3, 1.0]]), start=(1.5, 1.0))  # behind the band now
    assert GoalDistanceCritic().score(tr2, far).illegal["unreachable"][0]


def test_no_plan_in_window_is_unavailable():
    ctx = context(
        blank(20, 20), TINY, pose=(0.5, 0.5, 0.0), path=np.array([[5.0, 5.0], [6.0, 5.0]])
    )
    with pytest.raises(CriticUnavailable):
        PathDistanceCritic().prepare(ctx)


# ---- occupancy --------------------------------------------------------------------------


def _wall_world(robot):
    geom = GridGeometry((80, 120), 0.05)
    occ = np.zeros(geom.shape, dtype=bool)
    occ[:, 100] = True  # wall at x = 5.0..5.05
    return inflate(occ, geom, robot.inscribed_radius)


def test_occupancy_free_motion_costs_nothing():
    cm = _wall_world(PR2)
    ctx = context(cm, PR2, pose=(1.0, 2.0, 0.0))
    tr = straight(np.array([[2.0, 2.0]]), start=(1.0, 2.0))
    s = OccupancyCritic().score(tr, ctx)
    assert s.cost[0] == 0.0 and not s.illegal["collision"][0]


def test_occupancy_collision_centre_and_footprint():
    cm = _wall_world(PR2)
    ctx = context(cm, PR2, pose=(3.0, 2.0, 0.0))
    # centre ends 0.4 m from the wall: beyond the inscribed radius (0.325) but the square
    # footprint (half-width 0.325, corner 0.46) sticks into the wall only when rotated 45°.
    ends = np.array([[4.6, 2.0], [4.6, 2.0], [5.02, 2.0]])
    tr = straight(ends, start=(3.0, 2.0))
    poses = tr.poses.copy()
    poses[1, :, 2] = np.pi / 4
    tr = Trajectories(tr.twists, poses, tr.t)
    full = OccupancyCritic().score(tr, ctx)
    assert full.illegal["collision"].tolist() == [False, True, True]
    centre_only = OccupancyCritic(footprint=False).score(tr, ctx)
    assert centre_only.illegal["collision"].tolist() == [False, False, True]
    assert 0 < full.cost[0] <= 252 * 0.05
    raw = OccupancyCritic(meter_scoring=False).score(tr, ctx)
    assert raw.cost[0] == pytest.approx(full.cost[0] / 0.05)


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_bug_escape_in_an_inscribed_band_without_lethal_cells_in_the_window():
    """A local window can hold an obstacle's inflation but not the obstacle itself (cut off at
    the window's edge). Starting in that INSCRIBED band takes the escape rule, whose clearance
    field is then infinite everywhere: inf - inf compared as "closer" (with a RuntimeWarning),
    so every trajectory was illegal, even one driving out of the band."""
    cm = blank(40, 40)
    costs = cm.costs.copy()
    costs[:, :12] = INSCRIBED
    ctx = context(Costmap(costs, cm.geometry), PR2, pose=(0.3, 1.0, 0.0))
    tr = straight(np.array([[1.0, 1.0]]), start=(0.3, 1.0))
    s = OccupancyCritic().score(tr, ctx)
    assert not s.illegal["collision"][0]


def test_unknown_cells_are_illegal():
    cm = blank(40, 40)
    costs = cm.costs.copy()
    costs[:, 30:] = UNKNOWN
    ctx = context(Costmap(costs, cm.geometry), PR2, pose=(0.5, 1.0, 0.0))
    tr = straight(np.array([[1.0, 1.0], [1.6, 1.0]]), start=(0.5, 1.0))
    s = OccupancyCritic().score(tr, ctx)
    assert s.illegal["unknown"].tolist() == [False, True]


@pytest.mark.parametrize("robot", [PR2, PIONEER])
def test_shortcuts_agree_with_checking_every_pose(robot):
    cm = _wall_world(robot)
    rng = np.random.default_rng(0)
    starts = (3.9, 2.0)
    ends = np.column_stack([rng.uniform(4.0, 5.2, 200), rng.uniform(0.5, 3.5, 200)])
    tr = straight(ends, start=starts, steps=8)
    poses = tr.poses.copy()
    poses[..., 2] = rng.uniform(-np.pi, np.pi, (200, 1))
    tr = Trajectories(tr.twists, poses, tr.t)
    ctx = lambda: context(cm, robot, pose=(*starts, 0.0))  # noqa: E731 - fresh cache
    exhaustive = OccupancyCritic(circumscribed_cost=0).score(tr, ctx())
    masked = OccupancyCritic().score(tr, ctx())
    boxed_ctx = ctx()
    boxed_ctx.cache.reach = 0.6  # the mask is then only computed near the robot
    boxed = OccupancyCritic().score(tr, boxed_ctx)
    thr = circumscribed_cost(robot.circumscribed_radius, robot.inscribed_radius, resolution=0.05)
    threshold = OccupancyCritic(circumscribed_cost=thr).score(tr, ctx())
    for other in (masked, boxed, threshold):
        np.testing.assert_array_equal(other.cost, exhaustive.cost)
        for k in exhaustive.illegal:
            np.testing.assert_array_equal(other.illegal[k], exhaustive.illegal[k])
    assert 0 < exhaustive.illegal["collision"].sum() < 200
    assert np.isfinite(exhaustive.cost).sum() > 20


# ---- heading ----------------------------------------------------------------------------


def test_heading_difference_to_the_path_direction():
    cm = blank(60, 60)
    path = np.array([[0.5, 1.5], [2.5, 1.5]])
    ctx = context(cm, TINY, pose=(0.5, 1.5, 0.0), path=path, goal=(2.5, 1.5, 0.0))
    tr = straight(np.array([[1.0, 1.5]] * 3), start=(0.5, 1.5))
    poses = tr.poses.copy()
    poses[:, -1, 2] = [0.0, 0.5, -2.0]
    s = HeadingCritic().score(Trajectories(tr.twists, poses, tr.t), ctx)
    np.testing.assert_allclose(s.cost, [0.0, 0.5, 2.0], atol=1e-9)
    # beside the path the desired direction points at the look-ahead point on it
    side = straight(np.array([[1.0, 1.5 + 0.325]]), start=(0.5, 1.5))
    got = HeadingCritic().score(side, ctx).cost[0]
    assert got == pytest.approx(np.pi / 4, abs=0.05)


def test_heading_near_the_end_uses_the_tangent():
    cm = blank(60, 60)
    ctx = context(
        cm,
        TINY,
        pose=(0.5, 1.5, 0.0),
        path=np.array([[0.5, 1.5], [1.5, 2.5]]),
        goal=(1.5, 2.5, 0.0),
    )
    tr = straight(np.array([[1.5, 2.5]]), start=(0.5, 1.5), yaw=np.pi / 4)
    assert HeadingCritic().score(tr, ctx).cost[0] == pytest.approx(0.0, abs=1e-9)


def _hooked_plan_ctx(pose=(0.5, 1.45, 0.0), reach=None, robot=TINY, goal_yaw=0.0, **kw):
    """A plan whose last grid segment turns 90° (up) onto a goal at (1.5, 1.5, ``goal_yaw``);
    ``reach``: the metres the cycle's rollouts can travel (``ctx.cache.reach``)."""
    path = np.array([[0.5, 1.45], [1.5, 1.45], [1.5, 1.5]])
    ctx = context(blank(60, 60), robot, pose=pose, path=path, goal=(1.5, 1.5, goal_yaw), **kw)
    ctx.cache.reach = reach
    return ctx


def _ending(ends, start, yaws):
    """Straight rollouts from ``start`` to ``ends (N, 2)`` with end yaws ``yaws (N,)``."""
    tr = straight(np.asarray(ends, dtype=float), start=start)
    poses = tr.poses.copy()
    poses[:, -1, 2] = yaws
    return Trajectories(tr.twists, poses, tr.t)


def test_bug_the_plans_last_segment_sets_the_heading_at_the_goal_without_goal_align():
    # The grid's last segment (cell centre to goal) points anywhere: here 90° off the goal's
    # yaw. Without goal_align it is the desired heading of a rollout ending at the plan's end
    # (dev crowdnav_visible seed 1: it turned the PR2 1.4 rad away from the goal's yaw).
    end = _ending([[1.5, 1.45]], (0.5, 1.45), [0.0])
    assert HeadingCritic().score(end, _hooked_plan_ctx(reach=1.2)).cost[0] == pytest.approx(
        np.pi / 2
    )
    # goal_align, the goal 1.0 m away within the rollouts' 1.2 m reach: the goal's yaw counts
    aligned = HeadingCritic(goal_align=True)
    np.testing.assert_allclose(
        aligned.score(
            _ending([[1.5, 1.45]] * 2, (0.5, 1.45), [0.0, np.pi / 2]), _hooked_plan_ctx(reach=1.2)
        ).cost,
        [0.0, np.pi / 2],
        atol=1e-9,
    )


def test_goal_align_scores_every_rollout_of_the_cycle_alike_so_none_gains_by_stopping_short():
    # A goal facing back the way the robot came. Judging only the rollouts that reach the
    # plan's end by the goal's yaw made a PR2 slow down 1 m out (newcomer trial): the one
    # stopping short kept the plan's direction and cost nothing.
    ctx = _hooked_plan_ctx(reach=1.2, goal_yaw=np.pi)
    tr = _ending([[1.0, 1.45], [1.5, 1.45], [1.5, 1.5]], (0.5, 1.45), [0.0, 0.0, 0.0])
    np.testing.assert_allclose(HeadingCritic(goal_align=True).score(tr, ctx).cost, np.pi)


def test_goal_align_scores_the_goals_yaw_near_the_goal_and_the_plans_beyond_reach():
    near = _hooked_plan_ctx(pose=(1.2, 1.45, 0.0))  # 0.3 m from the goal: inside near_goal
    tr = _ending([[1.5, 1.5]] * 3, (1.2, 1.45), [0.0, 0.5, -2.0 * np.pi + 0.25])
    np.testing.assert_array_equal(HeadingCritic().score(tr, near).cost, [0.0, 0.0, 0.0])
    np.testing.assert_allclose(
        HeadingCritic(goal_align=True).score(tr, near).cost, [0.0, 0.5, 0.25], atol=1e-9
    )
    # 1.0 m from the goal, rollouts reaching 0.8 m: the plan's heading as without goal_align
    far = _hooked_plan_ctx(reach=0.8)
    ends = _ending([[1.0, 1.45], [1.0, 1.45]], (0.5, 1.45), [0.0, 1.0])
    np.testing.assert_array_equal(
        HeadingCritic(goal_align=True).score(ends, far).cost, HeadingCritic().score(ends, far).cost
    )


def test_goal_align_leaves_a_differential_drive_and_a_waypoint_alone():
    from socialnav.social.goals import SocialGoal

    tr = _ending([[1.5, 1.5]], (1.2, 1.45), [1.0])
    pioneer = _hooked_plan_ctx(pose=(1.2, 1.45, 0.0), robot=PIONEER)
    assert HeadingCritic(goal_align=True).score(tr, pioneer).cost[0] == 0.0
    waypoint = SocialGoal(np.array([1.5, 1.5, 0.0]), "waypoint", is_waypoint=True)
    near = _hooked_plan_ctx(pose=(1.2, 1.45, 0.0), social_goal=waypoint)
    assert HeadingCritic(goal_align=True).score(tr, near).cost[0] == 0.0


@pytest.mark.parametrize("value", ["no", "False", 1, 0, None, 2.5])
def test_goal_align_must_be_a_bool(value):
    with pytest.raises(ValueError, match="goal_align"):
        HeadingCritic(goal_align=value)
    assert HeadingCritic(goal_align=np.bool_(True)).goal_align is True


@pytest.mark.parametrize(
    "critic", [PathDistanceCritic(), GoalDistanceCritic(), OccupancyCritic(), HeadingCritic()]
)
def test_permutation_equivariance(critic):
    cm = _wall_world(PR2)
    rng = np.random.default_rng(1)
    ends = np.column_stack([rng.uniform(1.0, 5.5, 30), rng.uniform(0.5, 3.5, 30)])
    tr = straight(ends, start=(3.0, 2.0))
    path = np.array([[3.0, 2.0], [4.0, 2.0], [4.2, 3.8]])
    perm = rng.permutation(30)
    a = critic.score(tr, context(cm, PR2, pose=(3.0, 2.0, 0.0), path=path, goal=(4.2, 3.8, 0)))
    b = critic.score(
        tr.take(perm), context(cm, PR2, pose=(3.0, 2.0, 0.0), path=path, goal=(4.2, 3.8, 0))
    )
    np.testing.assert_array_equal(a.cost[perm], b.cost)
    for k in a.illegal:
        np.testing.assert_array_equal(np.asarray(a.illegal[k])[perm], b.illegal[k])


def _thin_wall(robot, y=3.025):
    """A wall line at ``y`` rasterized one cell thick (cells 3.00-3.05 m), inflated."""
    geom = GridGeometry((80, 120), 0.05)
    occ = rasterize(geom, segments=np.array([[[0.0, y], [6.0, y]]]))
    assert occ.any(axis=1).sum() == 1  # one row: the case of a costmap's thin wall
    return inflate(occ, geom, robot.inscribed_radius)


def _footprint_top(robot, poses):
    """Highest footprint point (m) of ``poses (..., 3)``."""
    c, s = np.cos(poses[..., 2:3]), np.sin(poses[..., 2:3])
    px, py = robot.polygon[:, 0], robot.polygon[:, 1]
    return (poses[..., 1:2] + s * px + c * py).max(axis=-1)


@pytest.mark.parametrize("robot", [PIONEER, PR2])
@pytest.mark.parametrize("overlap", [0.005, 0.02, 0.025, 0.04])
@pytest.mark.parametrize("yaw", [np.pi, 3.0, 2.6])
@pytest.mark.parametrize("leaning", [False, True])
def test_bug_escape_from_overlap_pushed_a_corner_through_a_thin_wall(robot, overlap, yaw, leaning):
    """Generated hallway dev seeds 24 and 78, Pioneer: the footprint touched a wall's LETHAL
    cells, so the escape rule applied (legal when the clearance never decreases), and its
    clearance, a signed distance from the LETHAL cells alone read per cell, is flat inside
    a cell one cell thick and rises again beyond it. Turning or driving pushed a corner 3 cm
    through the wall line. Whatever the robot does from there, no legal move crosses it, nor
    when someone leans on the same wall 2.5 m away (a newcomer trial: the person's cells had
    opened a way round to the far side, which then read as free)."""
    cm = _thin_wall(robot)
    social = SocialContext()
    if leaning:
        person = Person(1, (0.5, 3.0 - 0.25 - 0.005))
        grown = person.radius + 0.05 * np.sqrt(2.0) / 2.0
        cm = add_obstacle_discs(
            cm, np.array([[0.5, person.position[1], grown]]), robot.inscribed_radius
        )
        social = SocialContext((person,))
    pose = np.array([3.0, 0.0, yaw])
    pose[1] = 3.0 + overlap - (_footprint_top(robot, pose) - pose[1])  # overlaps the cell
    v, vy, w = np.meshgrid(
        np.linspace(robot.min_vel_x, robot.max_vel_x, 7),
        np.linspace(-robot.max_vel_y, robot.max_vel_y, 3),
        np.linspace(-robot.max_vel_theta, robot.max_vel_theta, 11),
    )
    twists = np.column_stack([v.ravel(), vy.ravel(), w.ravel()])
    tr = rollout(pose, np.zeros(3), twists, robot, RolloutParams(2.0, 0.025, 0.05))
    s = OccupancyCritic().score(tr, context(cm, robot, pose=tuple(pose), social=social))
    legal = ~s.illegal["collision"]
    assert legal.any()  # it can always move away
    # never across the wall line, nor deeper than at the start where already across it
    assert (_footprint_top(robot, tr.poses[legal]) <= max(3.025, 3.0 + overlap) + 1e-9).all()


def test_escape_from_overlap_lets_a_flush_differential_drive_turn_away():
    """A Pioneer whose side just touches a wall's LETHAL cell cannot turn without a corner
    swinging toward the wall; a shallow swing (short of the wall line) stays legal, else it
    would be pinned to the wall, able only to drive along it."""
    cm = _thin_wall(PIONEER)
    pose = np.array([3.0, 3.0 + 0.001 - 0.19, np.pi])  # facing -x, the wall on its right
    # A gentle arc away: the rear corner swings ~6 mm deeper before the arc lifts it; a spin.
    twists = np.array([[0.3, 0.0, 0.08], [0.0, 0.0, 1.0]])
    tr = rollout(pose, np.zeros(3), twists, PIONEER, RolloutParams(1.0, 0.025, 0.05))
    s = OccupancyCritic().score(tr, context(cm, PIONEER, pose=tuple(pose)))
    assert s.illegal["collision"].tolist() == [False, True]


def test_the_wall_floor_reads_people_as_no_walls_and_the_far_side_of_a_wall_as_inside():
    """The escape's wall check (``_above_wall_floor``) must leave the escape from people as it
    was (a person who steps into the footprint is left by the per-cell rule alone: recorded
    crowds lost 7 of 360 dev episodes to active contacts when people counted as walls), and
    must see the far side of a thin wall as inside it."""
    from socialnav.planner.critics.occupancy import _walls

    cm = _thin_wall(PR2)
    person = Person(1, (1.5, 2.0))
    grown = person.radius + 0.05 * np.sqrt(2.0) / 2.0
    cm = add_obstacle_discs(cm, np.array([[1.5, 2.0, grown]]), PR2.inscribed_radius)
    ctx = context(cm, PR2, pose=(3.0, 2.0, 0.0), social=SocialContext((person,)))
    walls = _walls(ctx, ctx.pose)
    rc = lambda x, y: tuple(cm.geometry.world_to_cell(np.array([x, y])))  # noqa: E731
    assert cm.costs[rc(1.5, 2.0)] == LETHAL and not walls[rc(1.5, 2.0)]  # the person's
    assert walls[rc(3.0, 3.02)] and walls[rc(3.0, 3.5)]  # the wall's cell and beyond it
    assert not walls[rc(3.0, 2.9)]  # this side of it


def test_the_wall_clearance_is_not_carried_to_a_cycle_with_other_people():
    """The prepared data a cycle leaves for the next with the same costmap and pose may not hold
    the walls' clearance: which LETHAL cells are walls depends on where the tracked people are
    (a costmap without people marks stays the same when they move; newcomer trial)."""
    from socialnav.planner.objectives import PreparedReuse

    cm = _thin_wall(PR2)
    pose = (3.0, 3.0 + 0.01 - 0.325, 0.0)
    critics = (OccupancyCritic(),)
    leaning = SocialContext((Person(1, (1.0, 2.77)),))
    first = context(cm, PR2, pose=pose, social=leaning)
    tr = straight(np.array([[2.8, pose[1]]]), start=pose[:2])  # along the wall, touching it
    assert not critics[0].score(tr, first).illegal["collision"][0]  # by the escape rule
    assert first.cache.occupancy_wall_sdf is not None
    reuse = PreparedReuse()
    reuse.keep(reuse.key(first, critics), first)
    second = context(cm, PR2, pose=pose, social=SocialContext())
    reuse.restore(second, critics)
    assert second.cache.occupancy_sdf is not None  # the same costmap's data is reused
    assert second.cache.occupancy_wall_sdf is None

"""The critics' fast paths agree exactly with brute-force versions of the same rules.

Occupancy: the clearance-bounded, early-exit outline check vs the full outline at every pose.
Interpersonal: the culled, shared ``(N, K)`` minimum distances vs the full ``(N, T, K)`` array.
"""

import numpy as np
import pytest

from socialnav.core.robot import PIONEER, PR2
from socialnav.core.scene import Person, SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.interpersonal import (
    InterpersonalCritic,
    capped_inverse_exp,
    footprint_radius,
    min_squared_distances,
)
from socialnav.planner.critics.occupancy import OccupancyCritic, footprint_outline
from socialnav.world.grid import INSCRIBED, LETHAL, UNKNOWN, Costmap, GridGeometry

# ---- occupancy ----------------------------------------------------------------------------


def _brute_force_occupancy(trajs, ctx, meter_scoring=True):
    """The documented rule, checking the whole outline at every pose of every trajectory whose
    centre cells are all legal."""
    geom, costs = ctx.costmap.geometry, ctx.costmap.costs
    rows, cols = geom.shape
    inv = 1.0 / geom.resolution
    outline = footprint_outline(ctx.robot.polygon, 0.5 * geom.resolution)
    n = len(trajs)
    collision, unknown, cost = np.zeros(n, bool), np.zeros(n, bool), np.zeros(n)

    def cell_codes(x, y):
        col = np.floor(x).astype(np.intp)
        row = np.floor(y).astype(np.intp)
        inside = (row >= 0) & (row < rows) & (col >= 0) & (col < cols)
        return np.where(
            inside, costs[np.clip(row, 0, rows - 1), np.clip(col, 0, cols - 1)], UNKNOWN
        )

    for i in range(n):
        poses = trajs.poses[i, 1:] if trajs.poses.shape[1] > 1 else trajs.poses[i]
        centre = cell_codes(
            (poses[:, 0] - geom.origin[0]) * inv, (poses[:, 1] - geom.origin[1]) * inv
        )
        unknown[i] = (centre == UNKNOWN).any()
        collision[i] = ((centre >= INSCRIBED) & (centre != UNKNOWN)).any()
        cost[i] = np.where(centre < INSCRIBED, centre, 0).max()
        if unknown[i] or collision[i]:
            continue
        o = outline.astype(poses.dtype)
        for p in poses:
            c, s = np.cos(p[2:3]), np.sin(p[2:3])
            x = (p[0:1] + c * o[:, 0] - s * o[:, 1] - geom.origin[0]) * inv
            y = (p[1:2] + s * o[:, 0] + c * o[:, 1] - geom.origin[1]) * inv
            codes = cell_codes(x, y)
            collision[i] |= (codes == LETHAL).any()
            unknown[i] |= (codes == UNKNOWN).any()
    if meter_scoring:
        cost = cost * geom.resolution
    cost = np.where(collision | unknown, np.inf, cost)
    return cost, collision, unknown & ~collision


def _random_world(rng, robot):
    """Sparse LETHAL/UNKNOWN specks and blobs on random sub-INSCRIBED costs (no inflation, so
    many centres are legal while outlines hit)."""
    res = float(rng.choice([0.05, 0.1]))
    shape = (int(rng.integers(40, 80)), int(rng.integers(40, 80)))
    origin = tuple(rng.uniform(-3.0, 3.0, 2))
    costs = rng.integers(0, INSCRIBED, shape).astype(np.uint8)
    costs[rng.random(shape) < 0.0015] = LETHAL
    costs[rng.random(shape) < 0.0005] = UNKNOWN
    for j in range(6):
        r, c = rng.integers(0, shape[0]), rng.integers(0, shape[1])
        costs[r : r + 3, c : c + 4] = (LETHAL, UNKNOWN)[j % 2]
    costs[rng.random(shape) < 0.0003] = INSCRIBED
    geom = GridGeometry(shape, res, origin)
    centre = np.array(origin) + 0.5 * res * np.array(shape[::-1])
    pose = np.array([*centre, rng.uniform(-np.pi, np.pi)])
    # The start pose itself is collision-free (a start in collision takes the escape rule).
    xs, ys = geom.cell_centers()
    near = np.hypot(xs - centre[0], ys - centre[1]) <= robot.circumscribed_radius + 2 * res
    costs[near & (costs >= INSCRIBED)] = 0
    return Costmap(costs, geom), pose


def _random_rollouts(rng, pose, n, t, spread, dtype):
    steps = rng.normal(0.0, spread / t, (n, t - 1, 2)).cumsum(axis=1)
    xy = np.concatenate([np.zeros((n, 1, 2)), steps], axis=1) + pose[:2]
    yaw = pose[2] + rng.normal(0.0, 0.3, (n, t - 1)).cumsum(axis=1)
    yaw = np.concatenate([np.full((n, 1), pose[2]), yaw], axis=1)
    poses = np.concatenate([xy, yaw[..., None]], axis=2).astype(dtype)
    return Trajectories(np.zeros((n, 3)), poses, np.linspace(0.0, 1.7, t))


def _ctx(costmap, robot, pose, **kw):
    return PlanningContext(pose, np.zeros(3), pose, np.array([pose[:2]]), costmap, robot, **kw)


@pytest.mark.parametrize("seed", range(8))
def test_occupancy_fast_path_matches_the_full_outline_at_every_pose(seed):
    rng = np.random.default_rng(seed)
    robot = (PR2, PIONEER)[seed % 2]
    costmap, pose = _random_world(rng, robot)
    dtype = (np.float64, np.float32)[(seed // 2) % 2]
    size = np.array(costmap.geometry.shape[::-1]) * costmap.geometry.resolution
    trajs = _random_rollouts(rng, pose, 150, int(rng.integers(2, 30)), 0.3 * size.min(), dtype)
    cost, collision, unknown = _brute_force_occupancy(trajs, _ctx(costmap, robot, pose))
    # the outline (not the centre) decides many rows, and some rows stay legal
    centre = OccupancyCritic(footprint=False).score(trajs, _ctx(costmap, robot, pose))
    centre_illegal = centre.illegal["collision"] | centre.illegal["unknown"]
    assert (collision | unknown).sum() >= centre_illegal.sum() + 4
    assert np.isfinite(cost).any()
    for critic, reach in (
        (OccupancyCritic(), None),
        (OccupancyCritic(), 0.3 * size.min()),
        (OccupancyCritic(circumscribed_cost=0), None),
    ):
        ctx = _ctx(costmap, robot, pose)
        if reach is not None:
            ctx.cache.reach = reach  # the clearance is then computed only near the robot
        got = critic.score(trajs, ctx)
        np.testing.assert_array_equal(got.cost, cost)
        np.testing.assert_array_equal(got.illegal["collision"], collision)
        np.testing.assert_array_equal(got.illegal["unknown"], unknown)


def test_occupancy_single_pose_batch_and_map_edge():
    # T = 1 (the pose itself is scored) and poses hugging the map edge: off-map outline points.
    rng = np.random.default_rng(11)
    costmap = Costmap(np.zeros((30, 30), np.uint8), GridGeometry((30, 30), 0.05))
    xy = rng.uniform(0.0, 1.5, (200, 1, 2))
    poses = np.concatenate([xy, rng.uniform(-np.pi, np.pi, (200, 1, 1))], axis=2)
    trajs = Trajectories(np.zeros((200, 3)), poses, np.zeros(1))
    pose = np.array([0.75, 0.75, 0.0])
    cost, collision, unknown = _brute_force_occupancy(trajs, _ctx(costmap, PIONEER, pose))
    assert 0 < unknown.sum() < 200 and not collision.any()
    got = OccupancyCritic().score(trajs, _ctx(costmap, PIONEER, pose))
    np.testing.assert_array_equal(got.cost, cost)
    np.testing.assert_array_equal(got.illegal["unknown"], unknown)


# ---- interpersonal ------------------------------------------------------------------------


def _brute_force_interpersonal(critic, trajs, ctx):
    """The critic's rule on the full ``(N, T, K)`` distance array, no culling."""
    people_now = ctx.social.positions()
    radii = ctx.social.radii()
    robot_r = footprint_radius(ctx, critic.footprint_disc)
    forecast = ctx.people_at(trajs.t)
    dx = trajs.xy[:, :, None, 0] - forecast[None, :, :, 0]
    dy = trajs.xy[:, :, None, 1] - forecast[None, :, :, 1]
    d2 = dx * dx + dy * dy
    if critic.evaluation == "last":
        d = np.linalg.norm(trajs.xy[:, -1, None, :] - people_now[None], axis=-1)
    else:
        d = np.sqrt(d2.min(axis=1))
    if critic.distance == "edge":
        d = np.maximum(d - radii - robot_r, 0.0)
    f = capped_inverse_exp(d, critic.threshold, critic.min_distance)
    if critic.person_slot is None:
        cost = f.max(axis=1)
    elif critic.person_slot < len(people_now):
        near = np.linalg.norm(people_now - ctx.pose[:2], axis=1)
        cost = f[:, np.argsort(near, kind="stable")[critic.person_slot]]
    else:
        cost = np.zeros(len(trajs))
    hit = (d2 < (radii + robot_r) ** 2).any(axis=(1, 2))
    return cost, hit


def _crowd(rng, k):
    people = []
    for i in range(k):
        speed = rng.uniform(0.0, 1.2) if rng.random() < 0.5 else 0.0
        heading = rng.uniform(-np.pi, np.pi)
        pos = rng.uniform(-6.0, 6.0, 2)
        people.append(
            Person(
                i,
                tuple(pos),
                (speed * np.cos(heading), speed * np.sin(heading)),
                radius=float(rng.uniform(0.2, 0.4)),
            )
        )
    return SocialContext(tuple(people))


CRITIC_VARIANTS = [
    InterpersonalCritic(),
    InterpersonalCritic(evaluation="max_over_time"),
    InterpersonalCritic(
        evaluation="max_over_time", distance="edge", footprint_disc="circumscribed"
    ),
    InterpersonalCritic(distance="edge", person_slot=0),
    InterpersonalCritic(person_slot=1),
    InterpersonalCritic(person_slot=2, threshold=3.0),
    InterpersonalCritic(evaluation="max_over_time", collision_check=False, threshold=0.8),
]


@pytest.mark.parametrize("seed", range(6))
def test_interpersonal_culling_and_sharing_match_the_full_array(seed):
    rng = np.random.default_rng(seed)
    social = _crowd(rng, int(rng.integers(1, 25)))
    pose = np.array([0.0, 0.0, 0.3])
    costmap = Costmap(np.zeros((4, 4), np.uint8), GridGeometry((4, 4), 1.0))
    dtype = (np.float64, np.float32)[seed % 2]
    trajs = _random_rollouts(rng, pose, 300, 20, 2.5, dtype)
    shared = _ctx(costmap, PR2, pose, social=social, predict_people=seed % 3 != 0)
    hits = 0
    for critic in CRITIC_VARIANTS:
        want_cost, want_hit = _brute_force_interpersonal(critic, trajs, shared)
        alone = critic.score(
            trajs, _ctx(costmap, PR2, pose, social=social, predict_people=shared.predict_people)
        )
        together = critic.score(trajs, shared)  # cache filled/extended by earlier critics
        for got in (alone, together):
            np.testing.assert_array_equal(got.cost, want_cost)
            if critic.collision_check:
                np.testing.assert_array_equal(got.illegal["person_collision"], want_hit)
        hits += int(want_hit.sum())
    assert hits > 0 or social.positions().shape[0] < 3
    # A different batch in the same context is not served from the cache.
    other = _random_rollouts(rng, pose, 50, 20, 2.5, dtype)
    want_cost, want_hit = _brute_force_interpersonal(CRITIC_VARIANTS[1], other, shared)
    got = CRITIC_VARIANTS[1].score(other, shared)
    np.testing.assert_array_equal(got.cost, want_cost)
    np.testing.assert_array_equal(got.illegal["person_collision"], want_hit)


def test_min_squared_distances_is_exact_within_reach_and_culls_only_far_people():
    rng = np.random.default_rng(3)
    social = _crowd(rng, 30)
    pose = np.array([0.0, 0.0, 0.0])
    costmap = Costmap(np.zeros((4, 4), np.uint8), GridGeometry((4, 4), 1.0))
    ctx = _ctx(costmap, PR2, pose, social=social)
    trajs = _random_rollouts(rng, pose, 100, 15, 2.0, np.float64)
    forecast = ctx.people_at(trajs.t)
    full = ((trajs.xy[:, :, None] - forecast[None]) ** 2).sum(-1).min(axis=1)
    reach = np.full(30, 1.0)
    got = min_squared_distances(trajs, ctx, reach)
    culled = np.isinf(got).all(axis=0)
    assert 0 < culled.sum() < 30  # the test covers both kinds of people
    # Exact wherever the distance is within reach; beyond it an entry is exact or inf (the
    # compiled path also culls single (trajectory, person) pairs, the reference whole people).
    within = np.sqrt(full) <= 1.0
    assert within[:, ~culled].any()
    np.testing.assert_allclose(got[within], full[within], rtol=0, atol=1e-12)
    kept = np.isfinite(got)
    np.testing.assert_allclose(got[kept], full[kept], rtol=0, atol=1e-12)
    assert (np.sqrt(full[~kept]) > 1.0).all()
    if not kernels.enabled():
        assert kept[:, ~culled].all()
    # a larger reach later extends the cache to the people it now needs
    everyone = min_squared_distances(trajs, ctx, np.full(30, np.inf))
    np.testing.assert_allclose(everyone, full, rtol=0, atol=1e-12)

"""The compiled kernels against the NumPy reference: bit-identical poses, critic costs, illegal
masks and selections on random scenes (``socialnav.planner.kernels``)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from itertools import pairwise

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.robot import PIONEER, PR2
from socialnav.core.scene import Group, Person, SocialContext
from socialnav.planner import kernels
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics import (
    GoalDistanceCritic,
    GroupCritic,
    HeadingCritic,
    InterpersonalCritic,
    OccupancyCritic,
    PathDistanceCritic,
)
from socialnav.planner.critics.base import CriticScore, CriticUnavailable
from socialnav.planner.local_planner import LocalPlannerParams
from socialnav.planner.presets import build_local_planner
from socialnav.planner.rollout import RolloutParams, rollout
from socialnav.world.costmap import add_obstacle_discs
from socialnav.world.grid import GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize

pytest.importorskip("numba")


@contextmanager
def compiled(flag: bool) -> Iterator[None]:
    previous = kernels.set_enabled(flag)
    try:
        yield
    finally:
        kernels.set_enabled(previous)


def scene(seed: int, n_people: int, robot=PR2):
    """A 4 m × 4 m window with random boxes and people; the robot somewhere free-ish (it may
    touch an obstacle or a person: the escape-from-overlap branches are exercised too)."""
    rng = np.random.default_rng(seed)
    geom = GridGeometry((80, 80), 0.05)
    boxes = []
    for _ in range(rng.integers(0, 6)):
        x, y = rng.uniform(0.0, 4.0, 2)
        w, h = rng.uniform(0.1, 0.8, 2)
        boxes.append(np.array([[x, y], [x + w, y], [x + w, y + h], [x, y + h]]))
    occ = rasterize(geom, polygons=boxes, thickness=0.1)
    costmap = inflate(occ, geom, robot.inscribed_radius)
    pose = np.array([*rng.uniform(0.8, 3.2, 2), rng.uniform(-np.pi, np.pi)])
    people = tuple(
        Person(
            i,
            tuple(pose[:2] + rng.uniform(-2.0, 2.0, 2)),
            tuple(rng.uniform(-1.5, 1.5, 2) * (rng.random() < 0.6)),
        )
        for i in range(n_people)
    )
    groups = (Group((0, 1, 2)),) if n_people >= 3 else ()
    social = SocialContext(people, groups)
    if people and rng.random() < 0.5:
        discs = np.column_stack([social.positions(), social.radii()])
        costmap = add_obstacle_discs(costmap, discs, robot.inscribed_radius)
    goal = np.array([*rng.uniform(0.2, 3.8, 2), 0.0])
    path = np.linspace(pose[:2], goal[:2], 40)
    vel = np.array([rng.uniform(0.0, 0.5), 0.0, rng.uniform(-0.3, 0.3)])
    return costmap, pose, vel, goal, path, social


def context(robot, costmap, pose, vel, goal, path, social, predict=True) -> PlanningContext:
    return PlanningContext(
        pose, vel, goal, path, costmap, robot, social=social, predict_people=predict
    )


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(1, 300),
    sim_time=st.floats(0.1, 3.0),
    gran=st.floats(0.01, 0.2),
    big=st.booleans(),
)
def test_rollout_bit_identical(seed: int, n: int, sim_time: float, gran: float, big: bool) -> None:
    rng = np.random.default_rng(seed)
    scale = 50.0 if big else 1.0  # angles far beyond pi exercise the wrap's fmod branch
    twists = rng.uniform(-1.0, 1.0, (n, 3)) * np.array([1.0, 1.0, scale])
    pose = np.array([*rng.uniform(-1e3, 1e3, 2), rng.uniform(-10.0, 10.0)])
    params = RolloutParams(sim_time, gran, max(gran, 0.05))
    with compiled(False):
        ref = rollout(pose, pose, twists, PR2, params)
    with compiled(True):
        fast = rollout(pose, pose, twists, PR2, params)
    assert fast.poses.dtype == ref.poses.dtype
    np.testing.assert_array_equal(fast.t, ref.t)
    assert np.array_equal(fast.poses, ref.poses)


@settings(max_examples=30)
@given(
    seed=st.integers(0, 2**31 - 1),
    counts=st.tuples(st.integers(1, 13), st.integers(1, 9), st.integers(1, 17)),
    signed_zero=st.booleans(),
)
def test_rollout_shared_headings_bit_identical(
    seed: int, counts: tuple[int, int, int], signed_zero: bool
) -> None:
    """A sampled grid shares each w across many rows (the kernel's per-w tables); -0.0 and
    0.0 are kept apart."""
    rng = np.random.default_rng(seed)
    axes = [np.sort(rng.uniform(-1.0, 1.0, c)) for c in counts]
    twists = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    if signed_zero:
        twists[::2, 2] = 0.0
        twists[1::2, 2] = -0.0
    pose = np.array([*rng.uniform(-5.0, 5.0, 2), 0.0 if signed_zero else rng.uniform(-4, 4)])
    params = RolloutParams(1.7, 0.025, 0.1)
    with compiled(False):
        ref = rollout(pose, pose, twists, PR2, params)
    with compiled(True):
        fast = rollout(pose, pose, twists, PR2, params)
    assert np.array_equal(fast.poses, ref.poses)
    assert np.array_equal(np.signbit(fast.poses), np.signbit(ref.poses))
    # The per-time box kept from the rollout pass is the reduction's.
    lo, hi = kernels.time_box(fast.poses)
    assert np.array_equal(lo, ref.xy.min(axis=0)) and np.array_equal(hi, ref.xy.max(axis=0))


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    people=st.integers(0, 12),
    footprint=st.booleans(),
    circumscribed=st.sampled_from([None, 1, 128, 252]),
    predict=st.booleans(),
)
def test_critics_bit_identical(
    seed: int, people: int, footprint: bool, circumscribed: int | None, predict: bool
) -> None:
    robot = PR2 if seed % 2 else PIONEER
    costmap, pose, vel, goal, path, social = scene(seed, people, robot)
    rng = np.random.default_rng(seed + 1)
    twists = rng.uniform(-1.0, 1.0, (150, 3)) * np.array([1.0, robot.max_vel_y, 1.5])
    critics = [
        OccupancyCritic(footprint=footprint, circumscribed_cost=circumscribed),
        InterpersonalCritic(evaluation="max_over_time"),
        # paccet's: partners, passing distances; then larger reaches extend the shared cache
        InterpersonalCritic(evaluation="max_over_time", partner_distance=True, hold_horizon=2.5),
        InterpersonalCritic(
            evaluation="max_over_time",
            partner_distance=True,
            hold_horizon=2.5,
            passage_distance=True,
        ),
        InterpersonalCritic(
            evaluation="max_over_time",
            distance="edge",
            footprint_disc="circumscribed",
            hold_horizon=1.0,
            approach_speed=0.0,
        ),
        InterpersonalCritic(evaluation="max_over_time", threshold=3.0, collision_check=False),
        InterpersonalCritic(distance="edge", person_slot=1),
        GroupCritic(),
        GroupCritic(evaluation="max_over_time", illegal_inside=True),
        GroupCritic(illegal_inside=True, influence_range=1.0),
        HeadingCritic(near_goal=0.0),
        PathDistanceCritic(),
        GoalDistanceCritic(),
    ]
    params = RolloutParams(1.7, 0.025, 0.1)
    results = {}
    for flag in (False, True):
        with compiled(flag):
            ctx = context(robot, costmap, pose, vel, goal, path, social, predict)
            ctx.cache.reach = 3.0
            trajs = rollout(pose, vel, twists, robot, params)
            scores = []
            for c in critics:
                try:
                    scores.append(c.score(trajs, ctx))
                except CriticUnavailable as exc:  # e.g. no plan cell in the window
                    scores.append(CriticScore(np.full(len(trajs), np.nan), {str(exc): None}))
            results[flag] = scores
    for ref, fast in zip(results[False], results[True], strict=True):
        assert np.array_equal(ref.cost, fast.cost, equal_nan=True)
        assert ref.illegal.keys() == fast.illegal.keys()
        for key in ref.illegal:
            assert np.array_equal(ref.illegal[key], fast.illegal[key]), key


@settings(max_examples=25)
@given(
    seed=st.integers(0, 2**31 - 1),
    people=st.integers(0, 10),
    preset=st.sampled_from(["traditional", "paccet", "paccet_paper", "weighted_social"]),
)
def test_planner_selections_identical(seed: int, people: int, preset: str) -> None:
    costmap, pose, vel, goal, path, social = scene(seed, people)
    params = LocalPlannerParams(5, 3, 7)
    out = {}
    for flag in (False, True):
        with compiled(flag):
            planner = build_local_planner(preset, PR2, social, params)
            results = []
            for k in range(3):  # a few cycles: stateful selection (PaCcET archive) too
                p = pose + np.array([0.02 * k, 0.0, 0.01 * k])
                ctx = context(PR2, costmap, p, vel, goal, path, social)
                results.append(planner.plan(ctx, record=True))
            out[flag] = results
    for ref, fast in zip(out[False], out[True], strict=True):
        assert ref.status == fast.status
        assert np.array_equal(ref.cmd, fast.cmd)
        assert ref.record is not None and fast.record is not None
        assert ref.record.chosen == fast.record.chosen
        assert np.array_equal(ref.record.F, fast.record.F)
        assert np.array_equal(ref.record.legal, fast.record.legal)


def test_environment_selects_reference(monkeypatch: pytest.MonkeyPatch) -> None:
    """``SOCIALNAV_KERNELS=reference`` turns the compiled path off at import."""
    import importlib

    was = kernels.enabled()
    monkeypatch.setenv("SOCIALNAV_KERNELS", "reference")
    module = importlib.reload(kernels)
    try:
        assert not module.enabled()
    finally:
        monkeypatch.undo()
        importlib.reload(kernels)
        kernels.set_enabled(was)


def test_warmup_compiles_ahead() -> None:
    """After :func:`warmup`, the planner's calls hit compiled signatures (no compile in a step)."""
    if not kernels.enabled():
        pytest.skip("reference path selected")
    kernels.warmup()
    fns = {
        "rollout": kernels._rollout_kernel,
        "occupancy": kernels._occupancy_kernel,
        "d2min": kernels._d2min_culled_kernel,
        "person_distances": kernels._person_distance_kernel,
        "approach": kernels._approach_kernel,
    }
    sigs = {k: len(f.signatures) for k, f in fns.items()}
    assert all(sigs.values())
    costmap, pose, vel, goal, path, social = scene(3, 5)
    planner = build_local_planner("paccet", PR2, social, LocalPlannerParams(5, 3, 7))
    planner.plan(context(PR2, costmap, pose, vel, goal, path, social))
    assert {k: len(f.signatures) for k, f in fns.items()} == sigs


def test_warmup_covers_selection_search_and_layers() -> None:
    """A navigator step that replans with the compiled search, draws the personal-space layer
    and selects with PaCcET hits only signatures compiled at construction."""
    from socialnav.moo import nondominated, paccet
    from socialnav.planner.presets import build_navigator

    if not kernels.enabled():
        pytest.skip("reference path selected")
    kernels.warmup()
    fns = {
        "astar": kernels._astar_kernel,
        "proxemic": kernels._proxemic_exponents,
        "meeting": kernels._meeting_exponents,
        "scatter": kernels._scatter_cost,
        "s_star": paccet._s_star_kernel,
        "front": nondominated._front_kernel,
    }
    before = {k: len(f.signatures) for k, f in fns.items()}
    assert all(before.values())  # compiled (or loaded) by the warm-up
    costmap, pose, vel, goal, _path, social = scene(5, 6)
    nav = build_navigator("paccet", PR2, costmap, goal, social, global_search="compiled")
    for k in range(2):
        nav.step(0.1 * k, pose, vel, social)
    assert {k: len(f.signatures) for k, f in fns.items()} == before


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    density=st.floats(0.0, 0.6),
    n_seeds=st.integers(1, 30),
    settle=st.booleans(),
)
def test_bfs_grid_identical(seed: int, density: float, n_seeds: int, settle: bool) -> None:
    """Identical step counts inside the settle region; outside it both paths are exact or inf
    (the compiled flood stops once the region is settled): every finite value is the exact one."""
    from socialnav.planner.critics.map_grid import bfs_distance

    rng = np.random.default_rng(seed)
    shape = tuple(rng.integers(5, 60, 2))
    passable = rng.random(shape) >= density
    seeds = np.column_stack(
        [rng.integers(0, shape[0], n_seeds), rng.integers(0, shape[1], n_seeds)]
    )
    box = (slice(shape[0] // 4, shape[0] // 2 + 1), slice(shape[1] // 4, shape[1] // 2 + 1))
    region = box if settle else None
    with compiled(False):
        ref = bfs_distance(passable, seeds, region)
    with compiled(True):
        fast = bfs_distance(passable, seeds, region)
    assert fast.dtype == ref.dtype
    if region is None:
        assert np.array_equal(ref, fast)
    else:
        with compiled(False):
            exact = bfs_distance(passable, seeds)
        assert np.array_equal(ref[region], fast[region])
        assert np.array_equal(exact[region], fast[region])
        finite = np.isfinite(fast)
        assert np.array_equal(exact[finite], fast[finite])


@settings(max_examples=60)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(2, 40),
    repeat=st.floats(0.0, 0.5),
    spacing=st.sampled_from([0.025, 0.05, 0.1, 0.3, 7.0]),
)
def test_plan_densify_and_cells_identical(seed: int, n: int, repeat: float, spacing: float) -> None:
    """The densified plan and its seed cells (first in-map non-UNKNOWN stretch) bit for bit,
    with repeated vertices (zero-length segments), plans leaving and re-entering the map and
    UNKNOWN cells."""
    from socialnav.planner.critics.map_grid import densify_path, local_plan_cells
    from socialnav.world.grid import Costmap

    rng = np.random.default_rng(seed)
    path = rng.uniform(-1.0, 5.0, (n, 2)) * rng.choice([1.0, 0.1])
    dup = rng.random(n) < repeat
    dup[0] = False
    path[dup] = path[np.flatnonzero(dup) - 1]
    costs = rng.integers(0, 253, (60, 70)).astype(np.uint8)
    costs[rng.random(costs.shape) < 0.1] = 255
    costmap = Costmap(costs, GridGeometry((60, 70), 0.05, (0.2, -0.1)))
    with compiled(False):
        ref_dense = densify_path(path, spacing)
        ref_cells = local_plan_cells(costmap, path)
    with compiled(True):
        fast_dense = densify_path(path, spacing)
        fast_cells = local_plan_cells(costmap, path)
    assert fast_dense.shape == ref_dense.shape
    assert np.array_equal(fast_dense, ref_dense)
    assert np.array_equal(fast_cells, ref_cells) and fast_cells.dtype == ref_cells.dtype
    same = np.repeat(path[:1], 3, axis=0)  # zero length: the first point only
    with compiled(True):
        assert np.array_equal(densify_path(same, spacing), same[:1])


@settings(max_examples=60)
@given(
    seed=st.integers(0, 2**31 - 1),
    density=st.floats(0.0005, 0.6),
    reach=st.one_of(st.none(), st.floats(0.05, 3.0)),
)
def test_occupancy_clearance_identical(seed: int, density: float, reach: float | None) -> None:
    """The occupancy critic's clearance levels (an exact distance transform, compiled, against
    SciPy's ``distance_transform_edt``) bit for bit, with the box at and off the map's edges."""
    from scipy.ndimage import distance_transform_edt

    from socialnav.planner.critics.occupancy import _prepare_clearance
    from socialnav.world.grid import Costmap

    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(3, 90, 2))
    free = rng.random(shape) >= density
    free[tuple(rng.integers(0, shape))] = False
    out = np.zeros((shape[0] - 1, shape[1] - 1), np.uint16)
    kernels.clearance_levels(free, 7.5, 1, 0, out)
    ref = np.floor(np.minimum(distance_transform_edt(free), 7.5)[1:, : shape[1] - 1] * 16.0)
    assert np.array_equal(out, ref)
    costs = np.where(rng.random(shape) < density, 254, 0).astype(np.uint8)
    costmap = Costmap(costs, GridGeometry(shape, 0.05))
    pose = np.array([*rng.uniform(0.0, 0.05 * np.array(shape[::-1])), 0.0])
    got = []
    for flag in (False, True):
        ctx = PlanningContext(pose, np.zeros(3), pose, pose[None, :2], costmap, PR2)
        ctx.cache.reach = reach
        with compiled(flag):
            _prepare_clearance(ctx)
        got.append((ctx.cache.occupancy_clearance, ctx.cache.occupancy_need))
    assert np.array_equal(got[0][0], got[1][0]) and np.array_equal(got[0][1], got[1][1])


@settings(max_examples=60)
@given(
    seed=st.integers(0, 2**31 - 1),
    x=st.floats(-0.5, 3.5),
    y=st.floats(-0.5, 3.5),
    yaw=st.floats(-4.0, 4.0),
    robot=st.sampled_from([PR2, PIONEER]),
)
def test_footprint_cells_identical(seed: int, x: float, y: float, yaw: float, robot) -> None:
    """The cells under the robot's footprint (and its centre cell) bit for bit, also when the
    footprint hangs over the map's edge or lies off it."""
    from socialnav.planner.critics.map_grid import footprint_cells
    from socialnav.world.grid import Costmap

    rng = np.random.default_rng(seed)
    res = float(rng.choice([0.025, 0.05, 0.1]))
    costmap = Costmap(np.zeros((60, 60), np.uint8), GridGeometry((60, 60), res, (0.0, 0.0)))
    pose = np.array([x, y, yaw])
    masks = []
    for flag in (False, True):
        ctx = PlanningContext(pose, np.zeros(3), pose, pose[None, :2], costmap, robot)
        with compiled(flag):
            masks.append(footprint_cells(ctx))
    assert np.array_equal(masks[0], masks[1])


@settings(max_examples=30)
@given(
    seed=st.integers(0, 2**31 - 1),
    density=st.floats(0.0, 0.5),
    neutral=st.floats(1.0, 100.0),
    factor=st.floats(0.0, 5.0),
)
def test_global_plan_identical(seed: int, density: float, neutral: float, factor: float) -> None:
    """Same graph weights bit for bit, hence the same Dijkstra plan and cost."""
    from socialnav.planner.global_planner import grid_graph, plan_path, traversable
    from socialnav.world.grid import Costmap

    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(3, 50, 2))
    costs = rng.integers(0, 253, shape).astype(np.uint8)
    costs[rng.random(shape) < density] = 254
    costs[rng.random(shape) < 0.05] = 255
    costmap = Costmap(costs, GridGeometry(shape, 0.1))
    passable = traversable(costs, allow_unknown=bool(seed % 2))
    start = rng.uniform(0.0, 0.1 * np.array(shape[::-1]), 2)
    goal = rng.uniform(0.0, 0.1 * np.array(shape[::-1]), 2)
    out = {}
    for flag in (False, True):
        with compiled(flag):
            g = grid_graph(costs, 0.1, passable, neutral, factor)
            plan = plan_path(costmap, start, goal, neutral, factor, tolerance=0.3)
            out[flag] = (g, plan)
    (g0, p0), (g1, p1) = out[False], out[True]
    assert np.array_equal(g0.data, g1.data)
    assert np.array_equal(g0.indices, g1.indices) and np.array_equal(g0.indptr, g1.indptr)
    assert p0.status == p1.status and p0.cost == p1.cost
    assert (p0.path is None) == (p1.path is None)
    if p0.path is not None:
        assert np.array_equal(p0.path, p1.path)


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    density=st.floats(0.0, 0.5),
    neutral=st.floats(1.0, 100.0),
    factor=st.floats(0.0, 5.0),
    levels=st.sampled_from([1, 4, 253]),
    tolerance=st.sampled_from([0.0, 0.3]),
)
def test_compiled_global_search_is_optimal(
    seed: int, density: float, neutral: float, factor: float, levels: int, tolerance: float
) -> None:
    """``search="compiled"`` (A*) against SciPy's Dijkstra: the same status, goal (substitute
    included) and cost; its path is a valid chain of moves whose weights sum to that cost
    (few cost levels = many equal-cost paths, where the two may choose differently)."""
    from socialnav.planner.global_planner import _OFFSETS, plan_path, traversable
    from socialnav.world.grid import Costmap

    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(3, 50, 2))
    costs = (rng.integers(0, levels, shape) * (252 // max(levels - 1, 1))).astype(np.uint8)
    costs[rng.random(shape) < density] = 254
    costs[rng.random(shape) < 0.05] = 255
    geo = GridGeometry(shape, 0.1)
    costmap = Costmap(costs, geo)
    start = rng.uniform(0.0, 0.1 * np.array(shape[::-1]), 2)
    goal = rng.uniform(0.0, 0.1 * np.array(shape[::-1]), 2)
    with compiled(True):
        ref = plan_path(costmap, start, goal, neutral, factor, tolerance=tolerance)
        fast = plan_path(
            costmap, start, goal, neutral, factor, tolerance=tolerance, search="compiled"
        )
    assert fast.status == ref.status
    assert (fast.path is None) == (ref.path is None)
    if ref.path is None:
        return
    assert np.array_equal(fast.goal, ref.goal)
    assert fast.cost == pytest.approx(ref.cost, rel=1e-12, abs=0.0)
    assert np.array_equal(fast.path[0], start) and np.array_equal(fast.path[-1], fast.goal)
    cells = [geo.world_to_cell(start)]
    cells += [geo.world_to_cell(p) for p in fast.path[1:-1]]
    cells += [geo.world_to_cell(fast.goal)]
    passable = traversable(costs)
    total = 0.0
    for (r0, c0), (r1, c1) in pairwise(cells):
        dr, dc = int(r1 - r0), int(c1 - c0)
        assert (dr, dc) in _OFFSETS
        assert passable[r1, c1]
        if dr and dc:
            assert passable[r0 + dr, c0] and passable[r0, c0 + dc]
        step = 0.1 * float(np.hypot(dr, dc))
        total += step * (neutral + factor * 0.5 * (float(costs[r0, c0]) + float(costs[r1, c1])))
    if len(cells) > 1 and cells[0].tolist() != cells[-1].tolist():
        assert total == pytest.approx(fast.cost, rel=1e-12, abs=0.0)


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    people=st.integers(0, 40),
    fast=st.sampled_from([0.0, 1.0, 3.0, 5.0, 30.0]),
    passing=st.booleans(),
    params=st.sampled_from([(77.0, 0.25, 10.0, 5.0), (250.0, 0.64, 5.0, 5.0), (40, 0.1, 39, 0)]),
)
def test_proxemic_layer_identical(
    seed: int, people: int, fast: float, passing: bool, params: tuple[float, ...]
) -> None:
    """The compiled personal-space layer equals the NumPy layer cell for cell: people on and
    off the grid, standing, walking, one fast (the lobe clipped to the grid)."""
    from socialnav.world.proxemic_layer import proxemic_costs

    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(5, 120, 2))
    geo = GridGeometry(shape, float(rng.choice([0.05, 0.1])), (float(rng.uniform(-2, 2)), 0.3))
    pos = rng.uniform(-3.0, 0.1 * max(shape) + 3.0, (people, 2))
    vel = rng.uniform(-1.3, 1.3, (people, 2)) * (rng.random((people, 1)) < 0.7)
    if people:
        vel[0] = [fast, -0.5 * fast]
    amplitude, variance, cutoff, factor = params
    args = (geo, pos, vel, amplitude, variance, cutoff, factor, passing)
    assert np.array_equal(kernels.proxemic_costs(*args), proxemic_costs(*args))


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    people=st.integers(0, 30),
    fast=st.sampled_from([0.0, 0.2, 1.0, 5.0, 30.0]),
    speed=st.sampled_from([0.1, 0.44, 1.0]),
    timing=st.sampled_from([(10.0, 1.0, 0.25), (4.0, 0.3, 0.0), (20.0, 2.0, 1.0)]),
)
def test_meeting_layer_identical(
    seed: int, people: int, fast: float, speed: float, timing: tuple[float, float, float]
) -> None:
    """The compiled meeting layer equals the NumPy layer cell for cell (its row culling drops
    only cells below the cutoff): walkers on and off the grid, standing, one fast, the robot
    anywhere."""
    from socialnav.world.meeting_layer import meeting_costs

    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(5, 160, 2))
    geo = GridGeometry(shape, float(rng.choice([0.05, 0.1])), (float(rng.uniform(-2, 2)), 0.3))
    pos = rng.uniform(-3.0, 0.1 * max(shape) + 3.0, (people, 2))
    vel = rng.uniform(-1.3, 1.3, (people, 2)) * (rng.random((people, 1)) < 0.8)
    if people:
        vel[0] = [fast, -0.5 * fast]
    start = rng.uniform(-1.0, 0.1 * max(shape) + 1.0, 2)
    horizon, tau0, tau_rate = timing
    args = (geo, pos, vel, start, speed, 250.0, 0.64, 5.0, horizon, tau0, tau_rate)
    assert np.array_equal(kernels.meeting_costs(*args), meeting_costs(*args))


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    discs=st.integers(0, 60),
    res=st.sampled_from([0.025, 0.05, 0.1, 0.3, 0.25]),
)
def test_disc_raster_identical(seed: int, discs: int, res: float) -> None:
    """The compiled disc rasterizer marks the reference's cells: discs on, across and off the
    grid's edges, radius 0 to larger than the grid, cell-aligned centres (ties at ``r²``)."""
    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(1, 90, 2))
    # A binary resolution and origin make exact ties at r² (centre on a cell centre, radius
    # a whole number of cells).
    origin = rng.integers(-12, 12, 2) * 0.25 if res == 0.25 else rng.uniform(-3, 3, 2)
    geo = GridGeometry(shape, res, (float(origin[0]), float(origin[1])))
    lo = np.array(geo.origin) - 1.0
    hi = np.array(geo.origin) + res * np.array(shape[::-1]) + 1.0
    d = np.column_stack([rng.uniform(lo, hi, (discs, 2)), rng.exponential(0.4, discs)])
    if discs:
        d[: discs // 3, :2] = (
            np.array(geo.origin) + (rng.integers(0, 20, (discs // 3, 2)) + 0.5) * res
        )
        d[: discs // 4, 2] = res * rng.integers(0, 5, discs // 4)
    out = {}
    for flag in (False, True):
        with compiled(flag):
            out[flag] = rasterize(geo, discs=d)
    assert out[True].dtype == np.bool_
    assert np.array_equal(out[False], out[True])


@settings(max_examples=25)
@given(seed=st.integers(0, 2**31 - 1), searches=st.integers(2, 6))
def test_kept_search_workspace_equals_fresh_arrays(seed: int, searches: int) -> None:
    """A* on the thread's kept arrays (only the last search's entries reset) returns exactly
    the arrays of a fresh search, over a sequence of maps, sizes, goals and exhaustive runs;
    two threads searching at once each get their own results."""
    from concurrent.futures import ThreadPoolExecutor

    from socialnav.planner.global_planner import _OFFSETS, traversable

    if not kernels.enabled():
        pytest.skip("reference path selected")
    rng = np.random.default_rng(seed)
    steps = np.array([0.1 * float(np.hypot(dr, dc)) for dr, dc in _OFFSETS])
    cases = []
    sizes = [tuple(int(v) for v in rng.integers(3, 40, 2)) for _ in range(2)]
    for k in range(searches):
        shape = sizes[0] if k < 2 else sizes[int(rng.integers(2))]  # same size: kept arrays
        costs = rng.integers(0, 253, shape).astype(np.uint8)
        costs[rng.random(shape) < rng.uniform(0.0, 0.4)] = 254
        n = costs.size
        goal = int(rng.integers(-1, n))
        cases.append((costs, traversable(costs), int(rng.integers(n)), goal))

    def run(case, reuse):
        costs, passable, start, goal = case
        dist, pred = kernels.astar(costs, passable, start, goal, steps, 50.0, 3.0, 0.1, reuse=reuse)
        return dist.copy(), pred.copy()

    fresh = [run(case, False) for case in cases]
    for case, (d0, p0) in zip(cases, fresh, strict=True):
        d1, p1 = run(case, True)
        assert np.array_equal(d0, d1) and np.array_equal(p0, p1)
    with ThreadPoolExecutor(2) as pool:
        both = list(pool.map(lambda case: run(case, True), cases * 2))
    for (d0, p0), (d1, p1) in zip(fresh * 2, both, strict=True):
        assert np.array_equal(d0, d1) and np.array_equal(p0, p1)


@settings(max_examples=80)
@given(
    seed=st.integers(0, 2**31 - 1),
    n_vertices=st.integers(1, 40),
    lattice=st.booleans(),
    special=st.sampled_from([None, np.nan, np.inf, 1e200]),
)
def test_nearest_vertex_is_argmin(
    seed: int, n_vertices: int, lattice: bool, special: float | None
) -> None:
    """The split-accumulator nearest-vertex search returns ``argmin``'s index: first of equal
    distances (repeated vertices, points on a lattice), NaN first, all-inf rows 0."""
    rng = np.random.default_rng(seed)
    vertices = rng.uniform(-3.0, 3.0, (n_vertices, 2))
    points = rng.uniform(-4.0, 4.0, (60, 2))
    if lattice:  # many exact ties
        vertices, points = np.round(vertices), np.round(points)
    vertices = vertices[rng.integers(0, n_vertices, n_vertices)]  # repeated vertices
    if special is not None:
        points[rng.integers(0, 60, 5), rng.integers(0, 2, 5)] = special
        if rng.random() < 0.5:
            vertices[rng.integers(0, n_vertices), rng.integers(0, 2)] = special
    with np.errstate(invalid="ignore", over="ignore"):  # inf - inf, 1e200 squared
        d2 = (points[:, None, 0] - vertices[None, :, 0]) ** 2 + (
            points[:, None, 1] - vertices[None, :, 1]
        ) ** 2
        want = np.argmin(d2, axis=1)
    np.testing.assert_array_equal(kernels.nearest_vertex(points, vertices), want)


@settings(max_examples=30)
@given(seed=st.integers(0, 2**31 - 1), people=st.integers(0, 6))
def test_occupancy_hit_codes_identical(seed: int, people: int) -> None:
    """The padded hit-code map of the occupancy critic (LETHAL 1, UNKNOWN or off the map 2)."""
    from socialnav.planner.critics.occupancy import _prepare_outline

    costmap, pose, vel, goal, path, social = scene(seed, people)
    costs = costmap.costs.copy()
    rng = np.random.default_rng(seed)
    costs[rng.random(costs.shape) < 0.05] = 255  # some UNKNOWN cells too
    costmap = type(costmap)(costs, costmap.geometry)
    maps = []
    for flag in (False, True):
        with compiled(flag):
            ctx = context(PR2, costmap, pose, vel, goal, path, social)
            _prepare_outline(ctx)
            assert ctx.cache.occupancy_codes is not None
            maps.append(ctx.cache.occupancy_codes)
    assert maps[0][1] == maps[1][1]
    assert maps[0][0].dtype == maps[1][0].dtype == np.uint8
    assert np.array_equal(maps[0][0], maps[1][0])


@settings(max_examples=60)
@given(
    seed=st.integers(0, 2**31 - 1),
    steps=st.integers(1, 13),
    reach=st.sampled_from([0.3, 1.0, np.inf]),
    special=st.sampled_from([None, np.nan, np.inf, -np.inf]),
)
def test_culled_distance_minimum_matches_np_min(
    seed: int, steps: int, reach: float, special: float | None
) -> None:
    """The four-accumulator, pair-culled minimum: ``np.min``'s value (NaN sticking) for every
    pair within ``reach`` or with a non-finite point; only pairs truly beyond ``reach`` may be
    ``inf`` instead."""
    rng = np.random.default_rng(seed)
    poses = rng.uniform(-2.0, 2.0, (30, steps, 3))
    forecast = rng.uniform(-2.0, 2.0, (steps, 5, 2))
    if special is not None:
        poses[rng.integers(0, 30, 3), rng.integers(0, steps, 3), rng.integers(0, 2, 3)] = special
        forecast[rng.integers(0, steps), rng.integers(0, 5), rng.integers(0, 2)] = special
    with np.errstate(invalid="ignore"):
        want = ((poses[:, :, None, :2] - forecast[None]) ** 2).sum(-1).min(axis=1)  # (N, K)
    people = np.arange(5, dtype=np.intp)
    got = np.full((30, 5), -1.0)
    kernels.min_squared_distances_culled(poses, forecast, people, np.full(5, reach), got)
    plain = np.full((30, 5), -1.0)
    kernels.min_squared_distances(poses, forecast, people, plain)
    assert np.array_equal(plain, want, equal_nan=True)
    culled = ~np.isnan(want) & np.isinf(got) & ~np.isinf(want)
    assert (np.sqrt(want[culled]) > reach).all()
    assert np.array_equal(got[~culled], want[~culled], equal_nan=True)


@settings(max_examples=40)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(1, 60),
    reach=st.sampled_from([None, 0.0, 0.5, 3.0]),
    repeat=st.booleans(),
)
def test_heading_plan_identical(seed: int, n: int, reach: float | None, repeat: bool) -> None:
    """The heading critic's densified plan ahead: vertices, arc lengths and tangents."""
    rng = np.random.default_rng(seed)
    path = np.cumsum(rng.uniform(-0.4, 0.4, (n, 2)), axis=0) + 2.0
    if repeat and n > 2:
        path[1] = path[0]  # a repeated vertex: a zero-length segment
    costmap, pose, vel, goal, _, social = scene(seed, 0)
    plans = []
    for flag in (False, True):
        with compiled(flag):
            ctx = context(PR2, costmap, pose, vel, goal, path, social)
            ctx.cache.reach = reach
            HeadingCritic().prepare(ctx)
            plans.append(ctx.cache.heading_plan)
    ref, fast = plans
    assert ref is not None and fast is not None
    for name in ("dense", "s", "tangent"):
        assert np.array_equal(getattr(ref, name), getattr(fast, name)), name


@settings(max_examples=60)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(1, 400),
    scale=st.sampled_from([0.05, 0.4, 2.0]),
    shape=st.sampled_from(["pr2", "pioneer", "random", "degenerate"]),
)
def test_signed_distance_to_polygon_identical(seed: int, n: int, scale: float, shape: str) -> None:
    """The footprint's signed distance to points bit for bit, vertices and edges included
    (the footprint approach rule's inner loop), for the robots' footprints and random ones."""
    from socialnav.core.geometry import signed_distance_to_polygon

    rng = np.random.default_rng(seed)
    polygon = {
        "pr2": PR2.polygon,
        "pioneer": PIONEER.polygon,
        "random": rng.normal(size=(int(rng.integers(3, 9)), 2)),
        "degenerate": np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]),
    }[shape]
    points = rng.normal(scale=scale, size=(n, 2))
    k = min(n, 4)
    points[:k] = polygon[rng.integers(0, len(polygon), k)]  # on vertices exactly
    if n > k:  # on an edge's midpoint
        points[k] = 0.5 * (polygon[0] + polygon[1])
    expected = signed_distance_to_polygon(points, polygon)
    got = kernels.signed_distance_to_polygon(points, polygon)
    assert got.shape == expected.shape and np.array_equal(got, expected)
    grid = points.reshape(1, n, 2)  # leading dimensions are kept
    assert kernels.signed_distance_to_polygon(grid, polygon).shape == (1, n)

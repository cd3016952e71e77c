"""The compiled BFS map grids (GridGraph / bfs_distance) against a plain queue BFS.

Contract: values inside the settle region are exact; every other cell is exact or ``inf``.
"""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest
from _planner_helpers import blank, context

from socialnav.core.robot import PR2
from socialnav.planner.critics import GoalDistanceCritic, PathDistanceCritic
from socialnav.planner.critics.map_grid import (
    GridGraph,
    bfs_distance,
    local_plan_cells,
    passable_cells,
    settle_region,
)
from socialnav.world.grid import LETHAL


def queue_bfs(passable: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """Textbook FIFO BFS: seeds at 0 whatever their cell, only passable cells are entered."""
    rows, cols = passable.shape
    dist = np.full(passable.shape, np.inf)
    queue: deque[tuple[int, int]] = deque()
    for r, c in seeds.tolist():
        if dist[r, c] != 0:
            dist[r, c] = 0
            queue.append((r, c))
    while queue:
        r, c = queue.popleft()
        for rr, cc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if 0 <= rr < rows and 0 <= cc < cols and passable[rr, cc] and np.isinf(dist[rr, cc]):
                dist[rr, cc] = dist[r, c] + 1
                queue.append((rr, cc))
    return dist


def assert_contract(got: np.ndarray, ref: np.ndarray, settle) -> None:
    assert got.dtype == np.float32
    if settle is not None:
        np.testing.assert_array_equal(got[settle], ref[settle])
    else:
        np.testing.assert_array_equal(got, ref)
    np.testing.assert_array_equal(got[np.isfinite(got)], ref[np.isfinite(got)])


def random_box(rng, rows: int, cols: int, at_edge: bool) -> tuple[slice, slice]:
    h, w = rng.integers(1, rows + 1), rng.integers(1, cols + 1)
    r0, c0 = rng.integers(0, rows - h + 1), rng.integers(0, cols - w + 1)
    if at_edge:  # flush with a random side of the map
        side = rng.integers(4)
        r0 = 0 if side == 0 else rows - h if side == 1 else r0
        c0 = 0 if side == 2 else cols - w if side == 3 else c0
    return slice(r0, r0 + h), slice(c0, c0 + w)


def random_plan(rng, rows: int, cols: int) -> np.ndarray:
    """A 4/8-connected random walk of cells (like a rasterised plan), possibly self-crossing."""
    k = int(rng.integers(1, 3 * (rows + cols)))
    steps = rng.integers(-1, 2, (k, 2))
    walk = np.cumsum(steps, axis=0) + np.array([rng.integers(rows), rng.integers(cols)])
    return np.clip(walk, 0, [rows - 1, cols - 1])


def maze(rng, rows: int, cols: int) -> np.ndarray:
    """Long walls with one gap each, alternating sides: forces long detours."""
    passable = rng.random((rows, cols)) > rng.uniform(0.0, 0.15)
    for i, r in enumerate(range(2, rows - 1, 3)):
        passable[r, :] = False
        gap = int(rng.integers(0, max(1, cols // 4)))
        passable[r, gap if i % 2 else cols - 1 - gap] = True
    return passable


@pytest.mark.parametrize("seed", range(40))
def test_random_maps_seeds_and_regions_match_a_queue_bfs(seed):
    rng = np.random.default_rng(seed)
    rows, cols = (int(v) for v in rng.integers(1, 48, 2))
    passable = (
        maze(rng, rows, cols) if seed % 3 == 0 else rng.random((rows, cols)) > rng.uniform(0.0, 0.5)
    )
    graph = GridGraph(passable)
    # Several searches on one graph: the seed rows enabled for one search must not leak.
    for trial in range(4):
        if trial % 2:
            seeds = random_plan(rng, rows, cols)  # may run over blocked cells
        else:
            seeds = np.array([[rng.integers(rows), rng.integers(cols)]])
        settle = None if trial == 3 else random_box(rng, rows, cols, at_edge=trial == 1)
        ref = queue_bfs(passable, seeds)
        assert_contract(graph.distance(seeds, settle), ref, settle)
        assert_contract(bfs_distance(passable, seeds, settle), ref, settle)


@pytest.mark.parametrize("multi", [False, True])
def test_long_detour_to_a_region_at_the_map_edge(multi):
    rows, cols = 61, 40
    passable = np.ones((rows, cols), dtype=bool)
    passable[1::4, :-1] = False  # serpentine corridor: distances far above the region size
    passable[3::4, 1:] = False
    seeds = np.array([[0, 0], [0, 1]]) if multi else np.array([[0, 0]])
    settle = (slice(rows - 4, rows), slice(cols - 6, cols))
    ref = queue_bfs(passable, seeds)
    got = bfs_distance(passable, seeds, settle)
    assert_contract(got, ref, settle)
    assert np.nanmax(np.where(np.isfinite(ref[settle]), ref[settle], np.nan)) > 600


def test_blocked_seed_emits_only_in_its_own_search():
    passable = np.ones((5, 7), dtype=bool)
    passable[:, 3] = False  # a full wall; (2, 3) is a blocked seed in the wall
    graph = GridGraph(passable)
    across = graph.distance(np.array([[2, 3], [0, 0]]))
    assert across[2, 4] == 1 and across[2, 3] == 0
    alone = graph.distance(np.array([[2, 2]]))  # the wall cell no longer emits
    assert np.isinf(alone[:, 4:]).all()
    np.testing.assert_array_equal(alone, queue_bfs(passable, np.array([[2, 2]])))


def test_unreachable_cells_in_the_region_stay_unreachable():
    passable = np.ones((9, 9), dtype=bool)
    passable[3:6, 3:6] = False
    passable[4, 4] = True  # an enclosed free cell inside the region
    for seeds in (np.array([[0, 0]]), np.array([[0, 0], [8, 8]])):
        got = bfs_distance(passable, seeds, (slice(2, 7), slice(2, 7)))
        assert np.isinf(got[4, 4])
        assert np.isinf(got[3, 3])


def test_empty_seeds_give_an_unreached_grid():
    assert np.isinf(bfs_distance(np.ones((3, 4), dtype=bool), np.zeros((0, 2), int))).all()


def test_critic_grids_share_one_graph_and_are_exact_in_the_reach_box():
    rng = np.random.default_rng(7)
    cm = blank(80, 90)
    cm.costs[rng.random(cm.costs.shape) < 0.2] = LETHAL
    cm.costs[30:50, 20:70] = LETHAL  # a block the plan must go round
    path = np.array([[2.2, 2.0], [0.4, 3.6], [4.3, 3.9], [4.4, 0.2]])
    ctx = context(cm, PR2, pose=(2.2, 2.0, 0.0), path=path, goal=(4.4, 0.2, 0.0))
    ctx.cache.reach = 0.6
    PathDistanceCritic().prepare(ctx)
    GoalDistanceCritic().prepare(ctx)
    cells = local_plan_cells(ctx.costmap, ctx.global_path)
    box = settle_region(ctx)
    passable = passable_cells(ctx)
    assert_contract(ctx.cache.path_distance_grid, queue_bfs(passable, cells), box)
    assert_contract(ctx.cache.goal_distance_grid, queue_bfs(passable, cells[-1:]), box)
    assert ctx.cache.grid_graph is not None

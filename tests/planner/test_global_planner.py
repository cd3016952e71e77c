"""navfn-style Dijkstra global planner on small analytic maps."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socialnav.planner.global_planner import plan_path
from socialnav.world.grid import INSCRIBED, LETHAL, UNKNOWN, Costmap, GridGeometry

RES = 0.1


def free_map(rows: int = 20, cols: int = 40) -> Costmap:
    return Costmap(np.zeros((rows, cols), np.uint8), GridGeometry((rows, cols), RES))


def centre(r: int, c: int) -> np.ndarray:
    return np.array([(c + 0.5) * RES, (r + 0.5) * RES])


def assert_valid_path(plan, costmap, start, goal):
    assert plan.status == "OK"
    path = plan.path
    np.testing.assert_allclose(path[0], start)
    np.testing.assert_allclose(path[-1], goal)
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    assert np.all(steps <= RES * math.sqrt(2) + 1e-9)  # dense: one point per cell
    assert np.all(costmap.cost_at(path[1:-1]) < INSCRIBED)


def test_straight_line_in_free_space_is_cost_optimal():
    cm = free_map()
    start, goal = centre(10, 2), centre(10, 32)
    plan = plan_path(cm, start, goal)
    assert_valid_path(plan, cm, start, goal)
    assert plan.cost == pytest.approx(50.0 * 3.0)  # neutral 50 × 3.0 m
    np.testing.assert_allclose(plan.path[:, 1], start[1])
    assert len(plan.path) == 31


def test_diagonal_and_knight_moves_cost_octile_distance():
    cm = free_map()
    plan = plan_path(cm, centre(2, 2), centre(12, 12))
    assert plan.cost == pytest.approx(50.0 * 10 * RES * math.sqrt(2))
    plan = plan_path(cm, centre(2, 2), centre(6, 14))  # 4 diagonal + 8 straight
    assert plan.cost == pytest.approx(50.0 * RES * (4 * math.sqrt(2) + 8))


def test_exact_start_and_goal_points_off_cell_centres():
    cm = free_map()
    start, goal = np.array([0.23, 1.01]), np.array([3.37, 0.88])
    plan = plan_path(cm, start, goal)
    assert_valid_path(plan, cm, start, goal)


def test_wall_with_gap_routes_through_the_gap():
    cm = free_map(30, 30)
    costs = cm.costs.copy()
    costs[:, 15] = LETHAL
    costs[22:24, 15] = 0  # gap at rows 22-23
    cm = Costmap(costs, cm.geometry)
    start, goal = centre(5, 3), centre(5, 27)
    plan = plan_path(cm, start, goal)
    assert_valid_path(plan, cm, start, goal)
    crossing = cm.geometry.world_to_cell(plan.path)
    at_wall = crossing[crossing[:, 1] == 15]
    assert len(at_wall) >= 1 and np.all((at_wall[:, 0] >= 22) & (at_wall[:, 0] <= 23))
    assert plan.cost > 50 * 2.4  # longer than the blocked straight line


def test_cost_factor_trades_length_for_low_cost():
    cm = free_map(30, 40)
    costs = cm.costs.copy()
    costs[10:20, 10:30] = 200  # an expensive (not blocked) band across the straight line
    cm = Costmap(costs, cm.geometry)
    start, goal = centre(15, 2), centre(15, 37)
    cheap = plan_path(cm, start, goal, cost_factor=0.0)
    assert cheap.cost == pytest.approx(50 * 3.5)  # straight through
    careful = plan_path(cm, start, goal, cost_factor=3.0)
    assert np.all(cm.cost_at(careful.path) < 200)  # detours around the band
    length = np.linalg.norm(np.diff(careful.path, axis=0), axis=1).sum()
    assert length > 3.5 + 0.3  # the detour is longer than the straight line...
    assert careful.cost < 50 * 3.5 + 3 * 200 * 2.0  # ...but cheaper than crossing the band


def test_diagonal_cannot_cut_a_blocked_corner():
    cm = free_map(3, 3)
    costs = cm.costs.copy()
    costs[0, 1] = LETHAL
    costs[1, 0] = LETHAL
    costs[1, 2] = LETHAL
    costs[2, 1] = LETHAL
    cm = Costmap(costs, cm.geometry)
    assert plan_path(cm, centre(0, 0), centre(1, 1)).status == "NO_PATH"


def test_fully_blocked_is_no_path():
    cm = free_map()
    costs = cm.costs.copy()
    costs[:, 20] = INSCRIBED
    cm = Costmap(costs, cm.geometry)
    plan = plan_path(cm, centre(5, 5), centre(5, 35))
    assert plan.status == "NO_PATH" and plan.path is None and plan.cost == math.inf


def test_unknown_blocks_unless_allowed():
    cm = free_map()
    costs = cm.costs.copy()
    costs[:, 20] = UNKNOWN
    cm = Costmap(costs, cm.geometry)
    assert plan_path(cm, centre(5, 5), centre(5, 35)).status == "NO_PATH"
    plan = plan_path(cm, centre(5, 5), centre(5, 35), allow_unknown=True)
    assert plan.status == "OK"


def test_blocked_start_and_goal_statuses():
    cm = free_map()
    costs = cm.costs.copy()
    costs[5, 5] = LETHAL
    costs[6, 6] = INSCRIBED
    costs[7, 7] = INSCRIBED
    cm = Costmap(costs, cm.geometry)
    assert plan_path(cm, centre(5, 5), centre(10, 30)).status == "START_BLOCKED"
    assert plan_path(cm, [-1.0, 0.5], centre(10, 30)).status == "START_BLOCKED"
    assert plan_path(cm, centre(10, 30), centre(6, 6)).status == "GOAL_BLOCKED"
    assert plan_path(cm, centre(10, 30), [100.0, 0.0]).status == "GOAL_BLOCKED"
    # An inscribed start cell is the robot's own cell: allowed, as ROS clears it.
    assert plan_path(cm, centre(7, 7), centre(10, 30)).status == "OK"


def test_same_cell_and_bad_input():
    cm = free_map()
    plan = plan_path(cm, [0.52, 0.51], [0.58, 0.55])
    assert plan.status == "OK" and plan.path.shape == (2, 2) and plan.cost == 0.0
    with pytest.raises(ValueError):
        plan_path(cm, [np.nan, 0.0], [1.0, 1.0])
    with pytest.raises(ValueError):
        plan_path(cm, [0.0, 0.0, 0.0], [1.0, 1.0])
    with pytest.raises(ValueError):
        plan_path(cm, [0.5, 0.5], [1.0, 1.0], neutral_cost=0.0)


def test_symmetric_costs():
    rng = np.random.default_rng(3)
    costs = rng.integers(0, 200, size=(15, 25)).astype(np.uint8)
    cm = Costmap(costs, GridGeometry((15, 25), RES))
    a, b = centre(1, 1), centre(13, 22)
    assert plan_path(cm, a, b).cost == pytest.approx(plan_path(cm, b, a).cost)

"""The meeting layer: a walker's personal space where and when the robot can meet them."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.core.errors import InvalidInputError
from socialnav.world.grid import GridGeometry
from socialnav.world.meeting_layer import meeting_costs

GEO = GridGeometry((280, 280), 0.05, (-7.0, -7.0))  # 14 m square around the origin


def cost_at(costs: np.ndarray, xy: tuple[float, float]) -> int:
    row, col = GEO.world_to_cell(np.asarray(xy, dtype=float))
    return int(costs[row, col])


def test_head_on_walker_costs_at_the_meeting_point_not_where_they_are():
    """Robot at the origin cruising at 0.5 m/s, a walker 6 m ahead coming at 1 m/s: they
    meet at t = 4 s, 2 m ahead (robot 2 m in 4 s, walker 4 m). There E = 0, so the cost is
    the amplitude's floor; at the walker's place now (T = 12 s against t = 0) it is nothing."""
    costs = meeting_costs(GEO, [[6.0, 0.0]], [[-1.0, 0.0]], [0.0, 0.0], 0.5)
    assert cost_at(costs, (2.0, 0.0)) >= 249
    assert cost_at(costs, (6.0, 0.0)) == 0
    assert cost_at(costs, (2.0, 0.0)) == costs.max()


def test_walker_beside_the_robot_keeps_personal_space_where_they_are():
    """Where the robot is (T = 0) the walker's space now: 1 m from a walker the cost is at
    least the standing Gaussian's there, 250 · exp(-1 / (2 · 0.64)) = 114."""
    costs = meeting_costs(GEO, [[1.0, 0.0]], [[0.0, 1.0]], [0.0, 0.0], 0.5)
    static = int(np.floor(250.0 * np.exp(-1.0 / 1.28)))
    row, col = GEO.world_to_cell(np.array([0.0, 0.0]))
    xs, ys = GEO.cell_centers()
    d2 = (xs[row, col] - 1.0) ** 2 + ys[row, col] ** 2  # the cell centre, not the robot point
    assert cost_at(costs, (0.0, 0.0)) >= int(np.floor(250.0 * np.exp(-d2 / 1.28))) - 1
    assert static == 114


def test_walker_walking_away_faster_than_the_robot_is_never_met():
    """A walker 4 m ahead walking away at 1.2 m/s from a robot at 0.5 m/s: nowhere is the
    cost above what the layer's cutoff lets through."""
    costs = meeting_costs(GEO, [[4.0, 0.0]], [[1.2, 0.0]], [0.0, 0.0], 0.5, tau0=0.5)
    assert costs.max() == 0


def test_crossing_walker_leaves_the_way_behind_them_free():
    """A walker crossing from the right, 3 m ahead: the robot (0.5 m/s) reaches the crossing
    at 6 s, after the walker (1 m/s, 3 m away: 3 s) has passed: the crossing costs less than
    the walker's space farther along their lane, where they will be then."""
    costs = meeting_costs(GEO, [[3.0, 3.0]], [[-1.0, 0.0]], [0.0, 0.0], 0.5)
    assert cost_at(costs, (0.0, 3.0)) < cost_at(costs, (-2.5, 3.0))


@given(
    st.floats(-5.0, 5.0),
    st.floats(-5.0, 5.0),
    st.floats(-2.0, 2.0),
    st.floats(-2.0, 2.0),
    st.floats(0.1, 1.0),
)
def test_bounded_window_misses_nothing_and_people_combine_by_maximum(px, py, vx, vy, speed):
    """The per-walker window holds every cell above the cutoff (the same layer as the
    unwindowed formula evaluated on the whole grid), and two walkers give the cell-wise max."""
    start = np.array([0.5, -1.0])
    one = meeting_costs(GEO, [[px, py]], [[vx, vy]], start, speed)
    xs, ys = GEO.cell_centers()
    v = np.array([vx, vy])
    h = 10.0
    arrive = np.hypot(xs - start[0], ys - start[1]) / speed
    inv_tau2 = 1.0 / (1.0 + 0.25 * arrive) ** 2
    dx, dy = xs - px, ys - py
    if np.hypot(*v) > 0:
        t = ((dx * vx + dy * vy) / 0.64 + arrive * inv_tau2) / (
            (vx * vx + vy * vy) / 0.64 + inv_tau2
        )
    else:
        t = np.zeros_like(xs)
    t = np.clip(t, 0.0, h)
    e = ((dx - t * vx) ** 2 + (dy - t * vy) ** 2) / 1.28 + 0.5 * (arrive - t) ** 2 * inv_tau2
    a = 250.0 * np.exp(-e)
    full = np.where(a >= 5.0, np.floor(a), 0).astype(np.uint8)
    assert np.abs(one.astype(int) - full.astype(int)).max() <= 1  # floor at the cutoff edge
    assert np.count_nonzero(one != full) <= max(3, full.size // 10000)
    two = meeting_costs(GEO, [[px, py], [-px, -py]], [[vx, vy], [-vx, vy]], start, speed)
    other = meeting_costs(GEO, [[-px, -py]], [[-vx, vy]], start, speed)
    assert np.array_equal(two, np.maximum(one, other))


def test_bad_input_is_named():
    with pytest.raises(InvalidInputError, match="speed"):
        meeting_costs(GEO, [[0.0, 0.0]], [[1.0, 0.0]], [0.0, 0.0], 0.0)
    with pytest.raises(InvalidInputError, match="must match"):
        meeting_costs(GEO, [[0.0, 0.0]], [[1.0, 0.0], [0.0, 1.0]], [0.0, 0.0], 0.5)
    assert meeting_costs(GEO, np.zeros((0, 2)), np.zeros((0, 2)), [0.0, 0.0], 0.5).max() == 0

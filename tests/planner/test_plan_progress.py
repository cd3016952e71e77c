"""The plan-progress critic: the plan's length still to go, so following a bent plan is progress.

A plan that approaches the goal from the side (someone stands near the goal and the global
planner keeps their personal space) made the free-space goal distance grow along the plan while
the path distance grew off it; the Pioneer turned on the spot short of the goal until the time
limit (generated crowdnav_visible and gallery_pass, dev seeds).
"""

from __future__ import annotations

import numpy as np
import pytest
from _planner_helpers import blank, context, straight
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import PIONEER
from socialnav.planner.critics import (
    CRITICS,
    CriticUnavailable,
    GoalDistanceCritic,
    PlanProgressCritic,
)
from socialnav.planner.local_planner import LocalPlannerParams, traditional_objectives

COSTMAP = blank(120, 120, origin=(-3.0, -3.0))


def _score(path, ends, reach=None, start=(0.0, 0.0)):
    ctx = context(COSTMAP, PIONEER, pose=(*start, 0.0), path=path, goal=(*path[-1], 0.0))
    ctx.cache.reach = reach
    return PlanProgressCritic().score(straight(ends, start=start), ctx).cost


def test_on_a_straight_plan_it_is_the_length_to_go_plus_the_offset():
    cost = _score([(0.0, 0.0), (4.0, 0.0)], [(1.0, 0.0), (1.0, 0.3), (4.0, 0.0), (5.0, 0.0)])
    np.testing.assert_allclose(cost, [3.0, 3.3, 0.0, 1.0], atol=1e-9)


def test_following_a_plan_that_bends_away_from_the_goal_is_progress():
    # Goal at (0, 2) reached around the right: (0, 0) → (1, 0) → (1, 2) → (0, 2). Driving along
    # the plan raises the straight-line (and BFS) distance to the goal but lowers the plan's
    # length to go; standing still or cutting across does not.
    path = [(0.0, 0.0), (1.0, 0.0), (1.0, 2.0), (0.0, 2.0)]
    ends = [(0.0, 0.0), (0.3, 0.0), (0.0, 0.3)]
    cost = _score(path, ends)
    np.testing.assert_allclose(cost, [4.0, 3.7, 4.3], atol=1e-9)
    ctx = context(COSTMAP, PIONEER, path=path, goal=(0.0, 2.0, 0.0))
    bfs = GoalDistanceCritic().score(straight(ends), ctx).cost
    assert bfs[1] > bfs[0] > bfs[2]  # the free-space measure ranks them the other way


def test_a_plan_that_loops_back_is_searched_only_near_its_start():
    # Out 10 m and back 0.5 m to the side: the end point (0.5, 0.45) is 5 cm from the way back
    # but that vertex lies 20 m along the plan, beyond the reach + 2 m searched.
    path = [(0.0, 0.0), (10.0, 0.0), (10.0, 0.5), (0.0, 0.5)]
    cost = _score(path, [(0.5, 0.45)], reach=1.0)
    np.testing.assert_allclose(cost, [20.5 - 0.5 + 0.45], atol=1e-9)


@given(
    st.lists(
        st.tuples(st.floats(-2.5, 2.5), st.floats(-2.5, 2.5)), min_size=2, max_size=6, unique=True
    ),
    st.tuples(st.floats(-2.5, 2.5), st.floats(-2.5, 2.5)),
)
@settings(max_examples=60, deadline=None)
def test_it_is_never_below_the_straight_line_to_the_goal_nor_above_the_plan_via_its_start(
    path, end
):
    # The triangle inequality along the plan: from any vertex, the rest of the plan is at
    # least the straight line to its end; the start vertex is one candidate of the minimum.
    path = np.asarray(path)
    length = float(np.hypot(*np.diff(path, axis=0).T).sum())
    cost = float(_score(path, [end], start=tuple(path[0]))[0])
    assert cost >= float(np.hypot(*(np.asarray(end) - path[-1]))) - 1e-6
    assert cost <= length + float(np.hypot(*(np.asarray(end) - path[0]))) + 1e-6


def test_an_empty_plan_makes_it_unavailable():
    ctx = context(COSTMAP, PIONEER, path=np.zeros((0, 2)))
    with pytest.raises(CriticUnavailable):
        PlanProgressCritic().score(straight([(1.0, 0.0)]), ctx)


def test_the_goal_distance_measure_chooses_the_critic():
    assert CRITICS.get("plan_progress") is PlanProgressCritic

    def goal_terms(params):
        return [type(c) for c, _ in traditional_objectives(params)[0].terms]

    assert GoalDistanceCritic in goal_terms(LocalPlannerParams())
    along = goal_terms(LocalPlannerParams(goal_distance_measure="along_plan"))
    assert PlanProgressCritic in along and GoalDistanceCritic not in along
    with pytest.raises(ConfigurationError, match="goal_distance_measure"):
        LocalPlannerParams(goal_distance_measure="euclidean")

"""Prepared map grids reused across cycles (``objectives.PreparedReuse``) give exactly what a
fresh preparation gives, and are not reused when any input changed."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.robot import PR2
from socialnav.planner import objectives
from socialnav.planner.context import PlanningContext
from socialnav.planner.local_planner import LocalPlannerParams, traditional_planner
from socialnav.world.grid import Costmap, GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize


def _costmap(seed: int) -> Costmap:
    rng = np.random.default_rng(seed)
    geom = GridGeometry((80, 80), 0.05)
    boxes = []
    for _ in range(4):
        x, y = rng.uniform(0.0, 4.0, 2)
        boxes.append(np.array([[x, y], [x + 0.4, y], [x + 0.4, y + 0.4], [x, y + 0.4]]))
    return inflate(rasterize(geom, polygons=boxes, thickness=0.1), geom, PR2.inscribed_radius)


def _ctx(costmap: Costmap, pose: np.ndarray) -> PlanningContext:
    goal = np.array([3.8, 3.5, 0.0])
    path = np.linspace(pose[:2], goal[:2], 30)
    return PlanningContext(pose, np.array([0.2, 0.0, 0.0]), goal, path, costmap, PR2)


def _plan(planner, ctx: PlanningContext):
    rec = planner.plan(ctx, record=True).record
    assert rec is not None
    return rec.chosen, rec.F, rec.legal


@settings(max_examples=15)
@given(seed=st.integers(0, 2**31 - 1), change=st.sampled_from(["none", "cost", "pose", "plan"]))
def test_reuse_matches_fresh_preparation(seed: int, change: str) -> None:
    costmap = _costmap(seed)
    pose = np.array([0.6, 0.6, 0.3])
    params = LocalPlannerParams(4, 3, 5)
    planner = traditional_planner(PR2, params)
    planner.plan(_ctx(costmap, pose))  # fills the reuse memo
    if change == "cost":
        costs = costmap.costs.copy()
        costs[40:44, 10:70] = 254  # a new wall across the window
        costmap = Costmap(costs, costmap.geometry)
    elif change == "pose":
        pose = pose + np.array([0.05, 0.0, 0.0])
    ctx = _ctx(costmap, pose)
    if change == "plan":
        ctx = PlanningContext(
            ctx.pose, ctx.velocity, ctx.goal, ctx.global_path[::-1].copy(), costmap, PR2
        )
    reused = _plan(traditional_planner(PR2, params), ctx)
    saved, objectives._REUSE = objectives._REUSE, objectives.PreparedReuse()  # nothing to reuse
    try:
        fresh_ctx = PlanningContext(
            ctx.pose, ctx.velocity, ctx.goal, ctx.global_path, ctx.costmap, PR2
        )
        fresh = _plan(traditional_planner(PR2, params), fresh_ctx)
    finally:
        objectives._REUSE = saved
    assert reused[0] == fresh[0]
    assert np.array_equal(reused[1], fresh[1])
    assert np.array_equal(reused[2], fresh[2])


def test_identical_inputs_reuse_the_grids() -> None:
    costmap = _costmap(1)
    pose = np.array([0.6, 0.6, 0.3])
    planner = traditional_planner(PR2, LocalPlannerParams(4, 3, 5))
    first = _ctx(costmap, pose)
    planner.plan(first)
    second = _ctx(Costmap(costmap.costs.copy(), costmap.geometry), pose.copy())
    planner.plan(second)
    assert second.cache.path_distance_grid is first.cache.path_distance_grid
    third = _ctx(costmap, pose + np.array([0.01, 0.0, 0.0]))
    planner.plan(third)
    assert third.cache.path_distance_grid is not first.cache.path_distance_grid

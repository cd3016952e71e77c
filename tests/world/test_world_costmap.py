"""Rolling-window crop and max-combination of layers."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.world.costmap import add_obstacle_discs, combine_max, crop
from socialnav.world.grid import LETHAL, UNKNOWN, Costmap, GridGeometry
from socialnav.world.inflation import inflate


def ramp_costmap() -> Costmap:
    geo = GridGeometry((20, 30), 0.1, (1.0, 2.0))
    costs = (np.arange(600) % 250).astype(np.uint8).reshape(20, 30)
    return Costmap(costs, geo)


def test_crop_inside_is_aligned_subarray():
    cm = ramp_costmap()
    win = crop(cm, [2.5, 3.0], 0.8)
    assert win.geometry.shape == (8, 8)
    assert win.geometry.resolution == 0.1
    # costmap_2d updateOrigin: origin = centre - size/2, snapped down to the parent grid.
    np.testing.assert_allclose(win.geometry.origin, (2.1, 2.6))
    np.testing.assert_array_equal(win.costs, cm.costs[6:14, 11:19])
    # Every window cell reads the same cost as the parent at its centre.
    centres = win.geometry.cell_to_world(np.indices((8, 8)).transpose(1, 2, 0))
    np.testing.assert_array_equal(cm.cost_at(centres), win.costs)


def test_crop_rectangular_and_off_map_is_unknown():
    cm = ramp_costmap()
    win = crop(cm, [1.0, 2.0], (1.0, 0.6))
    assert win.geometry.shape == (6, 10)
    assert np.all(win.costs[:3, :] == UNKNOWN)
    assert np.all(win.costs[:, :5] == UNKNOWN)
    np.testing.assert_array_equal(win.costs[3:, 5:], cm.costs[:3, :5])
    far = crop(cm, [100.0, 100.0], 1.0)
    assert np.all(far.costs == UNKNOWN)


@pytest.mark.parametrize(("center", "size"), [([np.nan, 0.0], 1.0), ([0.0, 0.0], -1.0), ([0.0], 1)])
def test_crop_bad_input(center, size):
    with pytest.raises(ValueError):
        crop(ramp_costmap(), center, size)


def test_combine_max_semantics():
    geo = GridGeometry((1, 5), 0.1)
    base = Costmap(np.array([[0, 100, UNKNOWN, LETHAL, 50]], np.uint8), geo)
    layer = np.array([[77, 50, 77, 10, UNKNOWN]], np.uint8)
    out = combine_max(base, layer)
    np.testing.assert_array_equal(out.costs, [[77, 100, UNKNOWN, LETHAL, 50]])
    out2 = combine_max(base, layer, overwrite_unknown=True)
    np.testing.assert_array_equal(out2.costs, [[77, 100, 77, LETHAL, 50]])
    # inputs untouched
    np.testing.assert_array_equal(base.costs, [[0, 100, UNKNOWN, LETHAL, 50]])
    with pytest.raises(ValueError):
        combine_max(base, layer.astype(np.int32))
    with pytest.raises(ValueError):
        combine_max(base, np.zeros((2, 5), np.uint8))


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    resolution=st.sampled_from([0.05, 0.1, 0.025, 0.07]),
    radii=st.sampled_from(
        [(0.325, 0.55, 10.0), (0.17, 0.55, 10.0), (0.3, 1.0, 3.0), (0.2, 0.2, 1.0)]
    ),
    people=st.integers(1, 25),
    unknown=st.booleans(),
)
def test_discs_on_a_kept_static_inflation_are_identical(seed, resolution, radii, people, unknown):
    """``reuse_static=True`` gives the full re-inflation's costmap cell for cell (discs on and
    off the map, overlapping each other and walls, UNKNOWN cells), also when called again on
    the same map with other discs (the kept part)."""
    from socialnav.world.raster import rasterize

    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in rng.integers(10, 90, 2))
    geo = GridGeometry(shape, resolution, (float(rng.uniform(-1, 1)), 0.0))
    size = np.array(shape[::-1]) * resolution
    walls = rng.uniform(0, 1, (4, 2, 2)) * size
    occ = rasterize(geo, segments=walls, thickness=0.1)
    r_ins, r_inf, k = radii
    base = inflate(
        occ, geo, r_ins, r_inf, k, unknown=(rng.random(shape) < 0.1) if unknown else None
    )
    for _ in range(2):
        discs = np.column_stack(
            [rng.uniform(-0.5, 1.0, (people, 2)) * size, rng.uniform(0.0, 0.4, people)]
        )
        ref = add_obstacle_discs(base, discs, r_ins, r_inf, k)
        fast = add_obstacle_discs(base, discs, r_ins, r_inf, k, reuse_static=True)
        assert np.array_equal(fast.costs, ref.costs)


def test_kept_static_inflation_applies_to_the_planner_maps():
    """The exactness condition holds for the robots' inflation on the suite's 5 cm maps."""
    from socialnav.core.robot import PIONEER, PR2
    from socialnav.world.costmap import _cost_by_squared_offset

    for robot in (PR2, PIONEER):
        assert _cost_by_squared_offset(0.05, robot.inscribed_radius, 10.0, 0.55) is not None

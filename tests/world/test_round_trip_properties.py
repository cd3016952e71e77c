"""Whole kinds, as properties: map files read back to the same grid, and adding a person to a
costmap changes costs only near that person."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.world.costmap import add_obstacle_discs
from socialnav.world.grid import GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.mapio import OccupancyMap, load_map, save_map
from socialnav.world.proxemic_layer import get_radius, proxemic_costs

_shape = st.tuples(st.integers(1, 40), st.integers(1, 40))


@settings(max_examples=25, deadline=None)
@given(
    shape=_shape,
    seed=st.integers(0, 2**31 - 1),
    res=st.sampled_from([0.025, 0.05, 0.1, 0.5]),
    origin=st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0)),
    fmt=st.sampled_from(["pgm", "png"]),
)
def test_a_saved_trinary_map_loads_back_to_the_same_grid(tmp_path_factory, shape, seed, res,
                                                         origin, fmt):  # fmt: skip
    rng = np.random.default_rng(seed)
    occupied = rng.random(shape) < 0.3
    unknown = rng.random(shape) < 0.2
    geo = GridGeometry(shape, res, origin)
    omap = OccupancyMap.from_masks(occupied, geo, unknown)
    path = tmp_path_factory.mktemp("map") / "m.yaml"
    save_map(omap, path, image_format=fmt)
    back = load_map(path)
    np.testing.assert_array_equal(back.occupancy, omap.occupancy)
    assert back.geometry.shape == geo.shape
    assert back.geometry.resolution == res
    np.testing.assert_allclose(back.geometry.origin, geo.origin, rtol=0, atol=1e-9)


def _room(seed: int) -> tuple[np.ndarray, GridGeometry]:
    rng = np.random.default_rng(seed)
    geo = GridGeometry((60, 80), 0.05, (0.0, 0.0))
    occ = np.zeros(geo.shape, dtype=bool)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = True
    occ[rng.random(geo.shape) < 0.01] = True
    return occ, geo


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 1000),
    others=st.lists(st.tuples(st.floats(0.0, 4.0), st.floats(0.0, 3.0)), max_size=4),
    new=st.tuples(st.floats(-1.0, 5.0), st.floats(-1.0, 4.0)),
    radius=st.floats(0.1, 0.4),
)
def test_adding_a_person_to_the_costmap_changes_costs_only_near_them(seed, others, new, radius):
    occ, geo = _room(seed)
    base = inflate(occ, geo, 0.3)
    discs = np.array([[x, y, 0.25] for x, y in others]).reshape(-1, 3)
    before = add_obstacle_discs(base, discs, 0.3)
    after = add_obstacle_discs(base, np.vstack([discs, [[*new, radius]]]), 0.3)
    changed = np.argwhere(before.costs != after.costs)
    if changed.size:
        d = np.hypot(*(geo.cell_to_world(changed) - np.asarray(new)).T)
        # the disc, then the inflation radius (0.55 m), plus a cell diagonal of rasterization
        assert d.max() <= radius + 0.55 + geo.resolution * np.sqrt(2.0) + 1e-9
    # and nowhere does a cost go down
    assert np.all(after.costs[before.costs != 255] >= before.costs[before.costs != 255])


@settings(max_examples=30, deadline=None)
@given(
    others=st.lists(
        st.tuples(st.floats(-2.0, 6.0), st.floats(-2.0, 5.0), st.floats(-2.0, 2.0)), max_size=4
    ),
    new=st.tuples(st.floats(-3.0, 7.0), st.floats(-3.0, 6.0)),
    velocity=st.tuples(st.floats(-12.0, 12.0), st.floats(-12.0, 12.0)),
    passing=st.booleans(),
)
def test_adding_a_person_to_the_proxemic_layer_changes_costs_only_near_them(
    others, new, velocity, passing
):
    geo = GridGeometry((60, 80), 0.05, (0.0, 0.0))
    pos = np.array([[x, y] for x, y, _ in others]).reshape(-1, 2)
    vel = np.array([[v, 0.0] for _, _, v in others]).reshape(-1, 2)
    before = proxemic_costs(geo, pos, vel, passing=passing)
    after = proxemic_costs(
        geo, np.vstack([pos, [new]]), np.vstack([vel, [velocity]]), passing=passing
    )
    changed = np.argwhere(before != after)
    assert np.all(after >= before)
    if changed.size:
        speed = float(np.hypot(*velocity))
        reach = get_radius(10.0, 77.0, 0.25 * (1.0 + 5.0 * speed))
        d = np.hypot(*(geo.cell_to_world(changed) - np.asarray(new)).T)
        assert d.max() <= reach + geo.resolution


def test_a_glitching_person_gets_a_lobe_clipped_to_the_grid():
    # A person at 1000 m/s (a tracker glitch) and one 1e7 m away: planned, not an error.
    geo = GridGeometry((60, 80), 0.05, (0.0, 0.0))
    out = proxemic_costs(geo, [[2.0, 1.5], [1e7, -1e7]], [[1000.0, 0.0], [1e9, 0.0]])
    row = int(geo.world_to_cell(np.array([2.0, 1.5]))[0])
    assert out[row, -1] > 0  # the lobe reaches the grid's far edge ahead of the person
    behind = get_radius(10.0, 77.0, 0.25) + geo.resolution
    xs, _ = geo.cell_centers()
    assert np.all(out[xs < 2.0 - behind] == 0)  # and only the plain Gaussian behind
    assert out.max() <= 77


@settings(max_examples=200, deadline=None)
@given(
    x=st.floats(-1e16, 1e16) | st.floats(-10.0, 10.0),
    y=st.floats(-1e16, 1e16) | st.floats(-10.0, 10.0),
    res=st.sampled_from([0.025, 0.05, 0.1, 0.3]),
    origin=st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0)),
)
def test_one_point_maps_to_the_cell_of_the_batch_lookup(x, y, res, origin):
    """The single-point fast path of ``world_to_cell`` gives the batch path's cell."""
    geo = GridGeometry((5, 5), res, origin)
    one = geo.world_to_cell(np.array([x, y]))
    batch = geo.world_to_cell(np.array([[x, y]]))[0]
    assert one.dtype == batch.dtype and one.tolist() == batch.tolist()

"""Rasterization of segments, polygons and discs."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.geometry import point_segment_distance
from socialnav.world.grid import GridGeometry
from socialnav.world.raster import rasterize

GEO = GridGeometry((40, 50), 0.1, (-1.0, -2.0))


def brute_force(geo, segments=(), polygons=(), discs=(), thickness=0.0):
    """Per-cell reference (slow, obvious)."""
    from socialnav.core.geometry import points_in_polygon

    half = max(thickness / 2, geo.resolution * np.sqrt(2) / 2)
    out = np.zeros(geo.shape, bool)
    for r in range(geo.shape[0]):
        for c in range(geo.shape[1]):
            p = geo.cell_to_world(np.array([r, c]))
            hit = any(point_segment_distance(p, a[None], b[None])[0] <= half for a, b in segments)
            hit |= any(bool(points_in_polygon(p, poly)) for poly in polygons)
            hit |= any(np.hypot(*(p - d[:2])) <= d[2] for d in discs)
            out[r, c] = hit
    return out


def test_horizontal_wall_thickness():
    seg = np.array([[[0.0, 0.0], [2.0, 0.0]]])
    occ = rasterize(GEO, segments=seg, thickness=0.4)
    xs, ys = GEO.cell_centers()
    expected = (np.abs(ys) <= 0.2 + 1e-12) & (xs >= -0.2) & (xs <= 2.2)
    # Interior of the wall (away from the rounded caps) is exactly the band |y| <= 0.2.
    band = (xs > 0.0) & (xs < 2.0)
    np.testing.assert_array_equal(occ[band], expected[band])
    assert occ.sum() > 0


@pytest.mark.parametrize("end_y", [2.5, 0.7, -0.4, 6.0])
def test_thin_wall_across_the_grid_separates_8_connected_free_space(end_y):
    from scipy.ndimage import label

    seg = np.array([[[-2.0, -1.5], [5.0, end_y]]])
    occ = rasterize(GEO, segments=seg)
    _, n = label(~occ, structure=np.ones((3, 3)))
    assert n == 2


def test_polygon_and_disc():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    occ = rasterize(GEO, polygons=[square])
    assert occ.sum() == 100  # 10 × 10 cell centres inside
    disc = rasterize(GEO, discs=np.array([[1.0, 0.0, 0.5]]))
    xs, ys = GEO.cell_centers()
    np.testing.assert_array_equal(disc, (xs - 1.0) ** 2 + ys**2 <= 0.25)


def test_off_grid_shapes_are_clipped_and_empty_inputs():
    occ = rasterize(GEO, segments=np.array([[[-50.0, -50.0], [-40.0, -40.0]]]))
    assert not occ.any()
    assert not rasterize(GEO).any()
    assert not rasterize(GEO, segments=np.zeros((0, 2, 2)), discs=np.zeros((0, 3))).any()


@pytest.mark.parametrize(
    "kwargs",
    [
        {"segments": np.zeros((2, 3))},
        {"segments": np.array([[[0.0, np.nan], [1.0, 1.0]]])},
        {"polygons": [np.zeros((2, 2))]},
        {"discs": np.array([[0.0, 0.0, -1.0]])},
        {"thickness": -0.1},
    ],
)
def test_bad_input_raises(kwargs):
    with pytest.raises(ValueError):
        rasterize(GEO, **kwargs)


@settings(max_examples=25, deadline=None)
@given(
    seg=st.lists(st.floats(-2, 5), min_size=4, max_size=4),
    disc=st.lists(st.floats(-1, 4), min_size=3, max_size=3),
    thickness=st.floats(0, 0.6),
)
def test_matches_per_cell_reference(seg, disc, thickness):
    geo = GridGeometry((12, 15), 0.25, (-1.0, -1.0))
    segments = np.array(seg).reshape(1, 2, 2)
    discs = np.array([[disc[0], disc[1], abs(disc[2]) / 2]])
    tri = np.array([[0.0, 0.0], [2.0, 0.3], [0.7, 1.8]])
    fast = rasterize(geo, segments=segments, polygons=[tri], discs=discs, thickness=thickness)
    slow = brute_force(geo, segments, [tri], discs, thickness)
    np.testing.assert_array_equal(fast, slow)

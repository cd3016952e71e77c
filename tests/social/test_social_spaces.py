"""Social spaces: circle fits, o-space, activity space, queue bands, segment distances."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import points_in_polygon, signed_distance_to_polygon
from socialnav.social.proxemics import ZONES, distances, edge_distances, hall_zone
from socialnav.social.spaces import (
    activity_space_polygon,
    fit_circle,
    fit_circle_detailed,
    o_space,
    queue_band_polygons,
    segment_polygon_distance,
)


def on_circle(center, radius, degrees):
    a = np.radians(np.asarray(degrees, dtype=float))
    return np.asarray(center) + radius * np.column_stack([np.cos(a), np.sin(a)])


def test_kasa_fit_recovers_exact_circle():
    fit = fit_circle_detailed(on_circle((12.5, 12.5), 0.9, [90, 180, 270]))
    assert fit.method == "kasa"
    np.testing.assert_allclose(fit.center, [12.5, 12.5], atol=1e-9)
    assert fit.radius == pytest.approx(0.9)
    assert fit.rms == pytest.approx(0.0, abs=1e-9)


@settings(max_examples=40, deadline=None)
@given(
    cx=st.floats(-1e4, 1e4),
    cy=st.floats(-1e4, 1e4),
    r=st.floats(0.3, 5.0),
    start=st.floats(0, 360),
)
def test_kasa_fit_is_translation_robust(cx, cy, r, start):
    pts = on_circle((cx, cy), r, [start, start + 70, start + 160, start + 250])
    c, radius = fit_circle(pts)
    np.testing.assert_allclose(c, [cx, cy], atol=1e-6 * max(1.0, r))
    assert radius == pytest.approx(r, rel=1e-6)


def test_degenerate_fits():
    single = fit_circle_detailed([[1.0, 2.0], [1.0, 2.0]])
    assert single.method == "single" and single.radius == 0.0
    np.testing.assert_allclose(single.center, [1, 2])
    pair = fit_circle_detailed([[0.0, 0.0], [2.0, 0.0]])
    assert pair.method == "diameter_pair"
    np.testing.assert_allclose(pair.center, [1, 0])
    assert pair.radius == pytest.approx(1.0)
    row = fit_circle_detailed([[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]])
    assert row.method == "collinear"
    np.testing.assert_allclose(row.center, [1.5, 1.5])
    assert row.radius == pytest.approx(np.hypot(3, 3) / 2)
    nearly = fit_circle_detailed([[0.0, 0.0], [1.0, 1e-4], [2.0, 0.0]])
    assert nearly.method == "collinear"


@pytest.mark.parametrize(
    "bad", [np.zeros((0, 2)), [[np.nan, 0.0]], np.zeros((3, 3)), [[np.inf, 1.0], [0.0, 0.0]]]
)
def test_fit_rejects_bad_input(bad):
    with pytest.raises(InvalidInputError):
        fit_circle(bad)


def test_o_space_radius():
    c, r = o_space(on_circle((12.5, 12.5), 1.2, [150, 180, 210]))
    np.testing.assert_allclose(c, [12.5, 12.5], atol=1e-9)
    assert r == pytest.approx(0.9)
    assert o_space([[0.0, 0.0], [0.4, 0.0]])[1] == 0.0


def test_activity_space_polygon_gallery_activity():
    poly = activity_space_polygon((13, 25), 1.2, -np.pi / 2, (13, 22.5), shoulder=0.3)
    expected = {(13.3, 22.5), (12.7, 22.5), (13.6, 25.0), (12.4, 25.0)}
    assert {tuple(np.round(v, 9)) for v in poly} == expected
    inside = points_in_polygon(
        np.array([[13.0, 23.8], [12.5, 24.9], [13.0, 22.0], [14.0, 24]]), poly
    )
    np.testing.assert_array_equal(inside, [True, True, False, False])
    # area of the trapezoid: (0.6 + 1.2) / 2 * 2.5
    x, y = poly[:, 0], poly[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert area == pytest.approx(2.25)


def test_activity_space_off_centre_viewer_is_simple():
    poly = activity_space_polygon((0, 0), 1.0, np.pi / 2, (3.0, 2.0))
    x, y = poly[:, 0], poly[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert area > 0.5  # a self-intersecting (bow-tie) order would nearly cancel
    assert points_in_polygon(np.array([1.5, 1.0]), poly)


def test_queue_bands():
    members = np.array([[12.5, 19.4], [12.5, 18.6], [12.5, 17.8]])
    bands = queue_band_polygons(members, width=0.5)
    assert len(bands) == 2
    mids = 0.5 * (members[:-1] + members[1:])
    for band, mid in zip(bands, mids, strict=True):
        assert points_in_polygon(mid, band)
        assert not points_in_polygon(mid + np.array([0.3, 0.0]), band)
        assert signed_distance_to_polygon(mid, band) == pytest.approx(-0.25)
    square = queue_band_polygons([[0.0, 0.0], [0.0, 0.0]], width=0.5)[0]
    assert points_in_polygon(np.array([0.0, 0.0]), square)


def test_segment_polygon_distance():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    assert segment_polygon_distance([-1, 0.5], [2, 0.5], square) == 0.0  # crosses
    assert segment_polygon_distance([0.2, 0.2], [0.3, 0.3], square) == 0.0  # inside
    assert segment_polygon_distance([-1, 1.5], [2, 1.5], square) == pytest.approx(0.5)
    assert segment_polygon_distance([2, 2], [3, 3], square) == pytest.approx(np.sqrt(2))


def test_proxemics_helpers():
    d = distances(np.array([[0.0, 0.0], [3.0, 4.0]]), np.array([[0.0, 1.0], [3.0, 0.0]]))
    np.testing.assert_allclose(d, [[1.0, 3.0], [np.hypot(3, 3), 4.0]])
    e = edge_distances(np.zeros(2), np.array([[1.0, 0.0], [0.3, 0.0]]), [0.25, 0.25], 0.3)
    np.testing.assert_allclose(e, [0.45, 0.0])
    zones = hall_zone([0.2, 0.45, 1.0, 2.0, 5.0])
    assert [ZONES[z] for z in zones] == ["intimate", "personal", "personal", "social", "public"]

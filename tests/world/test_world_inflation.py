"""costmap_2d inflation: the cost formula, the distance transform, unknown cells."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.world.grid import INSCRIBED, LETHAL, UNKNOWN, GridGeometry
from socialnav.world.inflation import circumscribed_cost, inflate, inflation_cost


def formula(d: float, r_ins: float, k: float = 10.0, r_inf: float = 0.55) -> int:
    if d == 0:
        return 254
    if d <= r_ins:
        return 253
    if d <= r_inf:
        return int(252 * math.exp(-k * (d - r_ins)))
    return 0


@pytest.mark.parametrize("d", [0.0, 0.05, 0.3, 0.3000001, 0.35, 0.4, 0.5, 0.55, 0.5501, 2.0])
def test_inflation_cost_matches_costmap_2d_formula(d):
    assert int(inflation_cost(d, 0.3)) == formula(d, 0.3)


def test_known_values():
    # 252·e^(-10·0.1) = 92.7 → 92; 252·e^(-10·0.25) = 20.68 → 20.
    np.testing.assert_array_equal(
        inflation_cost(np.array([0.0, 0.2, 0.4, 0.55, 0.6]), 0.3), [254, 253, 92, 20, 0]
    )
    assert inflation_cost(np.zeros((2, 3)), 0.1).shape == (2, 3)
    assert inflation_cost(1.0, 0.1).dtype == np.uint8


@settings(max_examples=50, deadline=None)
@given(
    d=st.lists(st.floats(0, 3), min_size=2, max_size=20),
    r_ins=st.floats(0, 0.5),
    extra=st.floats(0, 1),
    k=st.floats(0, 20),
)
def test_cost_is_non_increasing_in_distance(d, r_ins, extra, k):
    dist = np.sort(np.array(d))
    cost = inflation_cost(dist, r_ins, k, r_ins + extra).astype(int)
    assert np.all(np.diff(cost) <= 0)
    assert np.all((cost == LETHAL) == (dist == 0))


def test_circumscribed_cost():
    assert circumscribed_cost(0.46, 0.3) == formula(0.46, 0.3)
    # Rounded up to whole cells: 0.46 → 0.5 at 0.05 m.
    assert circumscribed_cost(0.46, 0.3, resolution=0.05) == formula(0.5, 0.3)
    assert circumscribed_cost(0.8, 0.3) == 0  # beyond the inflation radius: never a shortcut
    with pytest.raises(ValueError):
        circumscribed_cost(0.2, 0.3)


def test_inflate_single_obstacle_uses_cell_centre_distances():
    geo = GridGeometry((41, 41), 0.05)
    occ = np.zeros(geo.shape, bool)
    occ[20, 20] = True
    cm = inflate(occ, geo, inscribed_radius=0.2, inflation_radius=0.55)
    rr, cc = np.indices(geo.shape)
    dist = 0.05 * np.hypot(rr - 20, cc - 20)
    expected = np.array([formula(d, 0.2) for d in dist.ravel()]).reshape(geo.shape)
    np.testing.assert_array_equal(cm.costs, expected)
    assert cm.costs[20, 20] == LETHAL
    assert cm.costs[20, 24] == INSCRIBED  # 0.2 m exactly
    assert cm.costs[20, 25] == formula(0.25, 0.2)
    assert cm.geometry == geo


def test_inflate_empty_and_unknown():
    geo = GridGeometry((5, 30), 0.1)
    assert not inflate(np.zeros(geo.shape, bool), geo, 0.2).costs.any()
    occ = np.zeros(geo.shape, bool)
    occ[:, 0] = True
    unknown = np.zeros(geo.shape, bool)
    unknown[:, [0, 1, 4, 20]] = True
    cm = inflate(occ, geo, 0.2, 0.55, unknown=unknown)
    row = cm.costs[2]
    assert row[0] == LETHAL  # occupied wins
    assert row[1] == INSCRIBED  # unknown within the inscribed radius takes the inscribed cost
    assert row[4] == UNKNOWN  # 0.4 m: positive cost, but unknown is kept
    assert row[20] == UNKNOWN
    assert row[3] == formula(0.3, 0.2)
    cm2 = inflate(occ, geo, 0.2, 0.55, unknown=unknown, inflate_unknown=True)
    assert cm2.costs[2, 4] == formula(0.4, 0.2)
    assert cm2.costs[2, 20] == UNKNOWN  # zero cost never overwrites unknown


@pytest.mark.parametrize(
    "args",
    [
        (np.array([-0.1]), 0.3),
        (np.array([np.nan]), 0.3),
        (np.array([0.1]), -0.3),
    ],
)
def test_bad_inputs_raise(args):
    with pytest.raises(ValueError):
        inflation_cost(*args)
    with pytest.raises(ValueError, match="inflation_radius"):
        inflation_cost(0.1, 0.3, inflation_radius=0.2)
    geo = GridGeometry((3, 3), 0.1)
    with pytest.raises(ValueError, match="shape"):
        inflate(np.zeros((2, 2), bool), geo, 0.1)

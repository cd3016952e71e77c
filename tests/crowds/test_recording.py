"""Interpolation of a recording: analytic tracks give exact positions, velocities, headings and
presence; absent people read NaN."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.crowds import Recording, Track, open_space_costmap
from socialnav.crowds.recording import Area
from socialnav.world.grid import FREE, LETHAL


def line_track(pid: int, t0: float, n: int, start, velocity, dt: float = 0.4) -> Track:
    times = t0 + dt * np.arange(n)
    return Track(pid, times, np.asarray(start) + np.outer(times - t0, velocity))


@given(
    vx=st.floats(-2, 2),
    vy=st.floats(-2, 2),
    t=st.floats(0, 4.0),
)
def test_constant_velocity_interpolates_exactly(vx: float, vy: float, t: float) -> None:
    rec = Recording((line_track(7, 0.0, 11, (1.0, 2.0), (vx, vy)),), 0.04)
    s = rec.state_at(t)
    np.testing.assert_allclose(s.positions[0, 0], [1.0 + vx * t, 2.0 + vy * t], atol=1e-9)
    np.testing.assert_allclose(s.velocities[0, 0], [vx, vy], atol=1e-9)
    if math.hypot(vx, vy) >= 0.1:
        err = math.remainder(s.headings[0, 0] - math.atan2(vy, vx), math.tau)
        assert abs(err) < 1e-9
    assert s.present[0, 0]


def test_presence_and_nan_outside_the_track() -> None:
    rec = Recording(
        (line_track(1, 0.0, 6, (0, 0), (1, 0)), line_track(2, 1.0, 3, (5, 5), (0, -1))), 0.04
    )
    s = rec.states(np.array([0.5, 1.2, 1.9]))
    assert s.present[:, 0].tolist() == [True, True, True]  # person 1: 0 … 2.0 s
    assert s.present[:, 1].tolist() == [False, True, False]  # person 2: 1.0 … 1.8 s
    assert np.isnan(s.positions[0, 1]).all() and np.isnan(s.headings[2, 1])
    assert rec.active_ids(1.9, 3.0).tolist() == [1]


def test_gap_longer_than_max_gap_is_absence() -> None:
    times = np.array([0.0, 0.4, 3.6, 4.0])
    rec = Recording((Track(1, times, np.c_[times, 0 * times]),), 0.04, max_gap=2.0)
    s = rec.states(np.array([0.2, 2.0, 3.6, 3.8]))
    assert s.present[:, 0].tolist() == [True, False, True, True]


def test_heading_is_held_while_standing() -> None:
    # Walks north for 1.2 s, then stands: the heading stays north, not atan2(0, 0) = 0.
    pos = np.array([[0, 0], [0, 0.4], [0, 0.8], [0, 1.2], [0, 1.2], [0, 1.2], [0, 1.2]], float)
    rec = Recording((Track(3, 0.4 * np.arange(7), pos),), 0.04)
    s = rec.states(np.array([0.1, 2.3]))
    assert s.headings[:, 0] == pytest.approx([math.pi / 2, math.pi / 2])
    assert np.hypot(*s.velocities[1, 0]) == pytest.approx(0.0)


def test_heading_wraps_across_pi() -> None:
    # Heading from 179° to -179°: the interpolated heading stays near ±180°, never 0.
    a, b = math.radians(179), math.radians(-179)
    pos = np.cumsum([[0, 0], [math.cos(a), math.sin(a)], [math.cos(b), math.sin(b)]], axis=0)
    rec = Recording((Track(1, np.array([0.0, 1.0, 2.0]), pos),), 0.04)
    h = rec.state_at(1.5).headings[0, 0]
    assert abs(abs(h) - math.pi) < math.radians(3)


def test_main_flow_and_destination() -> None:
    tracks = tuple(line_track(i, 0.0, 10, (i, 0), (0, 1 if i % 2 else -1)) for i in range(6))
    rec = Recording(tracks, 0.04)
    assert rec.main_flow() == pytest.approx([0.0, 1.0])
    assert rec.destination(1) == pytest.approx([1.0, 3.6])


def test_bad_tracks_are_refused() -> None:
    with pytest.raises(ValueError, match="strictly increasing"):
        Track(1, np.array([0.0, 0.0]), np.zeros((2, 2)))
    with pytest.raises(ValueError, match="duplicate"):
        Recording((line_track(1, 0, 2, (0, 0), (1, 0)),) * 2, 0.04)


def test_open_space_costmap_is_bounded_by_the_area() -> None:
    area = Area(0.0, 0.0, 10.0, 6.0)
    cm = open_space_costmap(area, inscribed_radius=0.3, resolution=0.1)
    assert cm.cost_at(np.array([5.0, 3.0])) == FREE
    for border in ([0.0, 3.0], [10.0, 3.0], [5.0, 0.0], [5.0, 6.0]):
        assert cm.cost_at(np.array(border)) == LETHAL
    assert cm.cost_at(np.array([0.2, 3.0])) >= 253  # within the inscribed radius
    assert 0 < cm.cost_at(np.array([0.45, 3.0])) < 253  # inflated, not lethal
    assert area.border_distance(np.array([1.0, 3.0])) == pytest.approx(1.0)


def test_repr_summarizes_instead_of_printing_every_sample() -> None:
    # the dataclass repr printed every track's samples (300 000 characters for ETH hotel)
    tracks = tuple(line_track(pid, 0.0, 500, (0.0, pid), (1.0, 0.0)) for pid in range(1, 40))
    text = repr(Recording(tracks, frame_period=0.4, groups=((1, 2),)))
    assert len(text) < 200
    assert "39 tracks" in text and "1 groups" in text and "0–199.6 s" in text

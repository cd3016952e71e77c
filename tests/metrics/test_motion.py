"""Motion-quality metrics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socialnav.metrics import METRICS


def m(name, record):
    return METRICS.get(name)(record)


def test_cumulative_heading_change_wraps(make_record):
    yaw = np.array([0.0, 0.5, 0.2, 0.2])
    assert m("cumulative_heading_change", make_record(np.zeros((4, 2)), yaw=yaw)) == (
        pytest.approx(0.8)
    )
    across = np.array([3.1, -3.1])  # a 0.083 rad turn across ±pi, not 6.2 rad
    rec = make_record(np.zeros((2, 2)), yaw=across)
    assert m("cumulative_heading_change", rec) == pytest.approx(2 * math.pi - 6.2)


def test_path_irregularity_is_turning_beyond_net_change(make_record, seg):
    xy = seg((0, 0), (2, 0), 4)
    yaw = np.array([0.0, 0.1, -0.1, 0.1, 0.3])  # total 0.1+0.2+0.2+0.2 = 0.7, net 0.3
    rec = make_record(xy, yaw=yaw)
    assert m("path_irregularity", rec) == pytest.approx((0.7 - 0.3) / 2.0)
    assert math.isnan(m("path_irregularity", make_record(np.zeros((3, 2)))))


def test_constant_speed_has_no_acceleration(make_record, seg):
    rec = make_record(seg((0, 0), (3, 4), 50))  # 5 m in 5 s
    assert m("mean_speed", rec) == pytest.approx(1.0)
    assert m("max_speed", rec) == pytest.approx(1.0)
    assert m("max_acceleration", rec) == pytest.approx(0.0, abs=1e-9)
    assert m("max_jerk", rec) == pytest.approx(0.0, abs=1e-6)


def test_constant_acceleration_from_second_differences(make_record):
    t = np.arange(30) * 0.1
    rec = make_record(np.column_stack([0.5 * 0.8 * t**2, np.zeros_like(t)]))
    assert m("mean_acceleration", rec) == pytest.approx(0.8)
    assert m("max_acceleration", rec) == pytest.approx(0.8)
    assert m("mean_jerk", rec) == pytest.approx(0.0, abs=1e-6)
    assert m("max_speed", rec) == pytest.approx(0.8 * (t[-1] + t[-2]) / 2)


def test_cubic_motion_has_constant_jerk(make_record):
    t = np.arange(20) * 0.1
    rec = make_record(np.column_stack([np.zeros_like(t), 0.5 * t**3]))
    assert m("mean_jerk", rec) == pytest.approx(3.0)


def test_short_record_gives_nan_rates(make_record):
    rec = make_record(np.zeros((2, 2)))
    assert math.isnan(m("mean_acceleration", rec))
    assert math.isnan(m("max_jerk", rec))
    assert m("mean_speed", rec) == 0.0


def test_oscillation_count_with_deadband(make_record):
    # omega (rad/s): +1, 0, +1, -1, -1, 0.01, +1, -1  -> sign changes: + -> - -> + -> - = 3
    omega = np.array([1.0, 0.0, 1.0, -1.0, -1.0, 0.01, 1.0, -1.0])
    yaw = np.concatenate([[0.0], np.cumsum(omega * 0.1)])
    rec = make_record(np.zeros((9, 2)), yaw=yaw)
    assert m("oscillation_count", rec) == 3

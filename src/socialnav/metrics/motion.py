"""Motion quality (metrics.md): heading change, irregularity, speed, acceleration, jerk,
oscillations — all over the whole record.

Speed, acceleration and jerk are magnitudes of the first, second and third forward finite
differences of the robot *position* (not the commanded twist): v_t = (p_{t+1} - p_t)/dt,
a_t = (v_{t+1} - v_t)/dt, j_t = (a_{t+1} - a_t)/dt. NaN when the record is too short.
Angular velocity is the finite difference of the recorded yaw, ω_t = wrap(θ_{t+1} - θ_t)/dt.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import wrap_angle
from socialnav.metrics.base import metric
from socialnav.metrics.task import path_length

NAN = float("nan")
OSCILLATION_DEADBAND = 0.05  # rad/s: |ω| below this is "not turning" and breaks no sign run


def _differences(record: EpisodeRecord, order: int) -> np.ndarray:
    """|order-th forward difference of position| / dt**order, shape ``(T - order,)``."""
    return np.linalg.norm(np.diff(record.robot_xy, n=order, axis=0), axis=1) / record.dt**order


def _stat(values: np.ndarray, how: str) -> float:
    if values.size == 0:
        return NAN
    return float(values.max() if how == "max" else values.mean())


def _heading_steps(record: EpisodeRecord) -> np.ndarray:
    return wrap_angle(np.diff(record.robot_poses[:, 2]))


@metric("cumulative_heading_change", unit="rad", direction="min")
def cumulative_heading_change(record: EpisodeRecord) -> float:
    """Σ_t |wrap(θ_{t+1} - θ_t)| over the record."""
    return float(np.abs(_heading_steps(record)).sum())


@metric("path_irregularity", unit="rad/m", direction="min", reference="Guzzi et al. 2013")
def path_irregularity(record: EpisodeRecord) -> float:
    """Unnecessary turning per metre: (Σ_t |wrap(Δθ_t)| - |wrap(θ_T - θ_0)|) / L, i.e. the
    rotation beyond the net heading change, divided by the path length L. NaN when L == 0."""
    length = path_length(record)
    if length < 1e-9:
        return NAN
    net = abs(float(wrap_angle(record.robot_poses[-1, 2] - record.robot_poses[0, 2])))
    return (cumulative_heading_change(record) - net) / length


@metric("mean_speed", unit="m/s", direction="max")
def mean_speed(record: EpisodeRecord) -> float:
    """mean_t |p_{t+1} - p_t| / dt (first forward difference of position)."""
    return _stat(_differences(record, 1), "mean")


@metric("max_speed", unit="m/s", direction="max")
def max_speed(record: EpisodeRecord) -> float:
    """max_t |p_{t+1} - p_t| / dt (first forward difference of position)."""
    return _stat(_differences(record, 1), "max")


@metric("mean_acceleration", unit="m/s^2", direction="min")
def mean_acceleration(record: EpisodeRecord) -> float:
    """mean_t |p_{t+2} - 2p_{t+1} + p_t| / dt² (second forward difference of position)."""
    return _stat(_differences(record, 2), "mean")


@metric("max_acceleration", unit="m/s^2", direction="min")
def max_acceleration(record: EpisodeRecord) -> float:
    """max_t |p_{t+2} - 2p_{t+1} + p_t| / dt² (second forward difference of position)."""
    return _stat(_differences(record, 2), "max")


@metric("mean_jerk", unit="m/s^3", direction="min")
def mean_jerk(record: EpisodeRecord) -> float:
    """mean_t |Δ³p_t| / dt³ (third forward difference of position)."""
    return _stat(_differences(record, 3), "mean")


@metric("max_jerk", unit="m/s^3", direction="min")
def max_jerk(record: EpisodeRecord) -> float:
    """max_t |Δ³p_t| / dt³ (third forward difference of position)."""
    return _stat(_differences(record, 3), "max")


@metric("oscillation_count", unit="1", direction="min")
def oscillation_count(record: EpisodeRecord) -> float:
    """Number of sign changes of the angular velocity ω_t = wrap(Δθ_t)/dt, ignoring samples with
    |ω| < 0.05 rad/s (a pause between two turns the same way is not an oscillation)."""
    omega = _heading_steps(record) / record.dt
    signs = np.sign(omega[np.abs(omega) >= OSCILLATION_DEADBAND])
    return float(np.count_nonzero(signs[1:] != signs[:-1]))

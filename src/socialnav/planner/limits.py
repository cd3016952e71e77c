"""Command limits and the control loop's clock: what every command of every status obeys.

- :func:`enforce_limits` clips a body twist to the robot's velocity box and to the
  acceleration window around the measured velocity (ROS ``dwa_local_planner``'s dynamic window
  with ``acc_lim_*`` over one ``controller_period``). When odometry reports a speed outside the
  box, the box wins: the command is the box edge nearest the measured speed (a robot cannot be
  commanded beyond its limits to respect an acceleration it already exceeds). A
  differential-drive robot is never commanded lateral velocity.
- :class:`CycleClock` turns the caller's timestamps into monotonic elapsed time for the
  time budgets (progress window, patience, replan period): a step backwards counts as no time
  and a jump forward counts as at most ``max_gap`` s, so one bad timestamp cannot expire (or
  freeze) any budget.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel


def velocity_box(robot: RobotModel) -> tuple[FloatArray, FloatArray]:
    """``(lo (3,), hi (3,))`` body-twist limits ``(vx, vy, wz)`` in m/s and rad/s."""
    vy = robot.max_vel_y if robot.holonomic else 0.0
    lo = np.array([robot.min_vel_x, -vy, -robot.max_vel_theta])
    hi = np.array([robot.max_vel_x, vy, robot.max_vel_theta])
    return lo, hi


def acceleration_limits(robot: RobotModel) -> FloatArray:
    """``(3,)`` ``acc_lim_x, acc_lim_y, acc_lim_theta`` (m/s², m/s², rad/s²)."""
    return np.array([robot.acc_lim_x, robot.acc_lim_y, robot.acc_lim_theta])


def acceleration_window(
    velocity: FloatArray, robot: RobotModel, period: float
) -> tuple[FloatArray, FloatArray]:
    """``(lo (3,), hi (3,))``: the body twists reachable from the measured ``velocity (3,)``
    within ``period`` s, inside the velocity box. Where the measured speed is beyond the box
    (an empty window), both bounds are the box edge nearest it."""
    lo, hi = velocity_box(robot)
    acc = acceleration_limits(robot) * period
    w_lo, w_hi = np.maximum(lo, velocity - acc), np.minimum(hi, velocity + acc)
    empty = w_lo > w_hi
    w_lo[empty] = w_hi[empty] = np.clip(velocity[empty], lo[empty], hi[empty])
    return w_lo, w_hi


def enforce_limits(
    cmd: ArrayLike, velocity: ArrayLike, robot: RobotModel, period: float
) -> FloatArray:
    """``cmd (3,)`` body twist clipped to the velocity box and to ``velocity ± acc_lim · period``.

    ``velocity (3,)`` is the measured body twist; a non-finite one (or command) gives a zero
    command. Never raises on a ``(3,)`` input. Sources: ROS ``max_vel_x``/``min_vel_x``/
    ``max_vel_y``/``max_vel_theta``/``acc_lim_*`` semantics of ``base_local_planner``.
    """
    c = np.asarray(cmd, dtype=float).reshape(3)
    v = np.asarray(velocity, dtype=float).reshape(3)
    if not (np.all(np.isfinite(c)) and np.all(np.isfinite(v))):
        return np.zeros(3)
    out = np.clip(c, *acceleration_window(v, robot, period))
    if not robot.holonomic:
        out[1] = 0.0
    return out


def within_limits(
    cmd: FloatArray, velocity: FloatArray, robot: RobotModel, period: float, tol: float = 1e-9
) -> bool:
    """True when ``cmd`` is what :func:`enforce_limits` would leave unchanged (up to ``tol``)."""
    return bool(np.all(np.abs(enforce_limits(cmd, velocity, robot, period) - cmd) <= tol))


class CycleClock:
    """Monotonic elapsed time (s) from caller timestamps; see the module docstring."""

    def __init__(self, max_gap: float = 1.0) -> None:
        self.max_gap = float(max_gap)
        self.reset()

    def reset(self) -> None:
        """Start again at elapsed time 0 with no previous timestamp."""
        self.now = 0.0
        self._last: float | None = None

    def tick(self, timestamp: float) -> float:
        """Advance to ``timestamp`` (s) and return the elapsed time."""
        t = float(timestamp)
        if self._last is not None and math.isfinite(t):
            dt = t - self._last
            self.now += min(max(dt, 0.0), self.max_gap)
        if math.isfinite(t):
            self._last = t
        return self.now

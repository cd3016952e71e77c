"""A walker's personal space where and when the robot can meet them (a space-time layer).

A global plan replanned every few seconds around each walker *where they are now* (the
proxemic Gaussian of :mod:`socialnav.world.proxemic_layer`) swings from side to side as a crowd
crosses: by the time the robot gets there, the walker has moved on. This layer instead costs a
cell ``x`` by how close the walker will be to ``x`` *at the time the robot would reach it*.

Model, per walker at ``p`` (m, world) with constant velocity ``v`` (m/s), the robot starting at
``r`` and cruising at ``s`` m/s (straight-line arrival time ``T(x) = |x - r| / s``, uncertain by
``τ(x) = τ0 + k · T(x)`` s), over the walker's lane ``q(t) = p + v t``, ``0 <= t <= H``::

    E(x, t) = |x - q(t)|² / (2 σ²) + (T(x) - t)² / (2 τ(x)²)
    cost(x) = floor(A · exp(-min_t E(x, t)))     (0 below ``cutoff``)

``E`` is a convex quadratic in ``t``, so its minimum is closed-form:
``t* = (v·(x - p) / σ² + T / τ²) / (|v|² / σ² + 1 / τ²)`` clipped to ``[0, H]``. Near the
robot (``T ≈ 0``) this is the walker's personal space where they are now; farther away it is
their space at the meeting point, and nothing on the stretch of lane the walker will have left
(or not yet reached) when the robot gets there. A walker walking away faster than the robot
is never met and costs nothing; one behind the robot costs only around themselves.

Source: the proxemic Gaussian (amplitude, variance, cutoff) of the ROS
``social_navigation_layers`` (D. V. Lu); the time-to-reach matching is this project's (the
space-time "meeting point" in the spirit of velocity obstacles, Fiorini & Shiller 1998).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import as_points
from socialnav.world.grid import LETHAL, GridGeometry


def meeting_costs(
    geometry: GridGeometry,
    positions: ArrayLike,
    velocities: ArrayLike,
    start_xy: ArrayLike,
    speed: float,
    amplitude: float = 250.0,
    variance: float = 0.64,
    cutoff: float = 5.0,
    horizon: float = 10.0,
    tau0: float = 1.0,
    tau_rate: float = 0.25,
    lane_step: float = 0.25,
) -> NDArray[np.uint8]:
    """Space-time personal-space layer ``(rows, cols)`` uint8 (module docstring) for walkers at
    ``positions (K, 2)`` m with ``velocities (K, 2)`` m/s, the robot at ``start_xy (2,)`` m
    cruising at ``speed`` m/s; ``horizon`` ``H`` (s), ``tau0`` (s) and ``tau_rate`` (s per s
    of arrival time) the timing uncertainty, ``variance`` ``σ²`` (m²). People combine by
    maximum; ``K = 0`` gives zeros. The work per walker is bounded by the window around the
    stretch of lane the robot can meet (clipped to the grid). Raises ``InvalidInputError`` on
    malformed or non-positive parameters. The NumPy reference of
    :func:`socialnav.planner.kernels.meeting_costs` (compiled, the same values).
    """
    start, windows, _ = meeting_windows(
        geometry, positions, velocities, start_xy, speed, amplitude, variance, cutoff,
        horizon, tau0, tau_rate, lane_step,
    )  # fmt: skip
    out = np.zeros(geometry.shape, dtype=np.uint8)
    if not windows:
        return out
    res = geometry.resolution
    rows_n, cols_n = geometry.shape
    ox, oy = geometry.origin
    depth = float(np.log(amplitude / cutoff))
    # The robot's arrival time and timing precision per cell, once for every walker.
    xc = ox + (np.arange(cols_n) + 0.5) * res
    yc = oy + (np.arange(rows_n) + 0.5) * res
    arrive_all = np.hypot(xc[None, :] - start[0], yc[:, None] - start[1]) / speed
    w_all = tau0 + tau_rate * arrive_all
    inv_tau2_all = 1.0 / (w_all * w_all)
    flat_out = out.reshape(-1)
    two_var = 2.0 * variance
    for w in windows:
        r0, r1, c0, c1 = w.r0, w.r1, w.c0, w.c1
        dx = xc[None, c0:c1] - w.x  # (1, W)
        dy = yc[r0:r1, None] - w.y  # (H, 1)
        arrive = arrive_all[r0:r1, c0:c1]
        inv_tau2 = inv_tau2_all[r0:r1, c0:c1]
        t = ((dx * w.vx + dy * w.vy) / variance + arrive * inv_tau2) / (w.den + inv_tau2)
        t = np.minimum(np.maximum(t, 0.0), w.h)
        ex, ey = dx - t * w.vx, dy - t * w.vy
        lag = arrive - t
        e = (ex * ex + ey * ey) / two_var + 0.5 * lag * lag * inv_tau2
        keep = e <= depth  # the rest is below the cutoff: no exp for it
        if not keep.any():
            continue
        a = amplitude * np.exp(-e[keep])
        ok = a >= cutoff
        rr, cc = np.divmod(np.flatnonzero(keep)[ok], c1 - c0)
        flat = (rr + r0) * cols_n + (cc + c0)
        flat_out[flat] = np.maximum(flat_out[flat], np.floor(a[ok]).astype(np.uint8))
    return out


class MeetingWindow(NamedTuple):
    """One walker's cell window ``[r0, r1) × [c0, c1)`` (clipped to the grid, non-empty),
    position ``x, y`` (m), velocity ``vx, vy`` (m/s), ``den = |v|² / σ²``, the lane's
    duration ``h`` (s), and the lane points ``[s0, s1)`` of :func:`meeting_windows`'s
    ``samples`` the robot can meet (every cell above the cutoff lies within ``radius`` m of
    one of them)."""

    r0: int
    r1: int
    c0: int
    c1: int
    x: float
    y: float
    vx: float
    vy: float
    den: float
    h: float
    s0: int
    s1: int
    radius: float


def meeting_windows(
    geometry: GridGeometry,
    positions: ArrayLike,
    velocities: ArrayLike,
    start_xy: ArrayLike,
    speed: float,
    amplitude: float = 250.0,
    variance: float = 0.64,
    cutoff: float = 5.0,
    horizon: float = 10.0,
    tau0: float = 1.0,
    tau_rate: float = 0.25,
    lane_step: float = 0.25,
) -> tuple[NDArray[np.float64], list[MeetingWindow], NDArray[np.float64]]:
    """The validated start ``(2,)``, per-walker windows of :func:`meeting_costs` (its
    arguments; raises ``InvalidInputError`` on bad ones) and the lane points ``(S, 2)`` (m)
    they index: every cell above ``cutoff`` is inside its walker's window and within the
    window's ``radius`` of one of its lane points. Walkers the robot cannot meet on the grid
    have none."""
    pos = as_points(positions, "positions").reshape(-1, 2)
    vel = as_points(velocities, "velocities").reshape(-1, 2)
    start = as_points(start_xy, "start_xy")
    if pos.shape != vel.shape or start.shape != (2,):
        raise InvalidInputError(
            f"positions {pos.shape} and velocities {vel.shape} must match; start_xy (2,)"
        )
    for name, value in (
        ("speed", speed),
        ("amplitude", amplitude),
        ("variance", variance),
        ("cutoff", cutoff),
        ("horizon", horizon),
        ("tau0", tau0),
        ("lane_step", lane_step),
    ):
        if not (np.isfinite(value) and value > 0):
            raise InvalidInputError(f"{name} must be finite and positive, got {value}")
    if not (np.isfinite(tau_rate) and tau_rate >= 0):
        raise InvalidInputError(f"tau_rate must be finite and >= 0, got {tau_rate}")
    if amplitude > LETHAL:
        raise InvalidInputError(f"amplitude must be <= {LETHAL} (a uint8 cost), got {amplitude}")
    out: list[MeetingWindow] = []
    samples: list[NDArray[np.float64]] = [np.zeros((0, 2))]
    count = 0
    if pos.shape[0] == 0 or cutoff >= amplitude:
        return start, out, samples[0]
    res = geometry.resolution
    rows_n, cols_n = geometry.shape
    ox, oy = geometry.origin
    depth = float(np.log(amplitude / cutoff))  # E above this is below the cutoff
    reach = float(np.sqrt(2.0 * variance * depth))  # spatial reach of the Gaussian (m)
    diagonal = float(np.hypot(rows_n, cols_n)) * res
    for k in range(pos.shape[0]):
        p, v = pos[k], vel[k]
        v_speed = float(np.hypot(v[0], v[1]))
        # The lane's duration, bounded by the grid (a tracker glitch at 10 m/s stays cheap).
        h = min(horizon, diagonal / v_speed) if v_speed > 0 else 0.0
        n = max(int(np.ceil(v_speed * h / lane_step)), 1)
        ts = np.linspace(0.0, h, n + 1)
        q = p[None] + ts[:, None] * v[None]  # (n+1, 2)
        tq = np.hypot(*(q - start).T) / speed
        # Lane points a cell can draw on: a cell d <= reach from q(t) arrives within d / speed
        # of q's arrival, with tau at most tau_far; minimising E over d leaves the bound
        # E >= (tq - t)² / (2 (tau_far² + σ² / speed²)). Half a lane step of slack.
        tau_far = tau0 + tau_rate * (tq + (reach + lane_step) / speed)
        slack = 0.5 * lane_step * (1.0 / speed + 1.0 / max(v_speed, 1e-9))
        gap = np.maximum(np.abs(tq - ts) - slack, 0.0)
        near = gap * gap <= 2.0 * depth * (tau_far * tau_far + variance / speed**2)
        if not near.any():
            continue
        lo = q[near].min(axis=0) - reach - res
        hi = q[near].max(axis=0) + reach + res
        c0 = max(int(np.floor((lo[0] - ox) / res)), 0)
        r0 = max(int(np.floor((lo[1] - oy) / res)), 0)
        c1 = min(int(np.ceil((hi[0] - ox) / res)) + 1, cols_n)
        r1 = min(int(np.ceil((hi[1] - oy) / res)) + 1, rows_n)
        if r0 >= r1 or c0 >= c1:
            continue
        den = v_speed * v_speed / variance
        kept = q[near]
        samples.append(kept)
        # A cell's best lane point is within half a lane step of a sample (a hair more).
        radius = (reach + 0.5 * lane_step) * (1.0 + 1e-6) + 1e-9
        cell_box = (r0, r1, c0, c1)
        walker = (float(p[0]), float(p[1]), float(v[0]), float(v[1]), den, h)
        out.append(MeetingWindow(*cell_box, *walker, count, count + len(kept), radius))
        count += len(kept)
    return start, out, np.concatenate(samples)

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
    malformed or non-positive parameters.
    """
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
    out = np.zeros(geometry.shape, dtype=np.uint8)
    if pos.shape[0] == 0 or cutoff >= amplitude:
        return out
    res = geometry.resolution
    rows_n, cols_n = geometry.shape
    ox, oy = geometry.origin
    depth = float(np.log(amplitude / cutoff))  # E above this is below the cutoff
    reach = float(np.sqrt(2.0 * variance * depth))  # spatial reach of the Gaussian (m)
    diagonal = float(np.hypot(rows_n, cols_n)) * res
    for k in range(pos.shape[0]):
        p, v = pos[k], vel[k]
        v_speed = float(np.hypot(*v))
        # The lane's duration, bounded by the grid (a tracker glitch at 10 m/s stays cheap).
        h = min(horizon, diagonal / v_speed) if v_speed > 0 else 0.0
        n = max(int(np.ceil(v_speed * h / lane_step)), 1)
        ts = np.linspace(0.0, h, n + 1)
        q = p[None] + ts[:, None] * v[None]  # (n+1, 2)
        tq = np.hypot(*(q - start).T) / speed
        tau = tau0 + tau_rate * tq
        # Lane points the robot can be near at the walker's time there: a cell within
        # ``reach`` of q differs in arrival time by at most reach / speed.
        near = np.abs(tq - ts) <= reach / speed + np.sqrt(2.0 * depth) * tau
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
        dx = ox + (np.arange(c0, c1)[None, :] + 0.5) * res - p[0]  # (1, W)
        dy = oy + (np.arange(r0, r1)[:, None] + 0.5) * res - p[1]  # (H, 1)
        arrive = np.hypot(dx + (p[0] - start[0]), dy + (p[1] - start[1])) / speed  # (H, W)
        inv_tau2 = 1.0 / (tau0 + tau_rate * arrive) ** 2
        t = ((dx * v[0] + dy * v[1]) / variance + arrive * inv_tau2) / (
            v_speed * v_speed / variance + inv_tau2
        )
        t = np.clip(t, 0.0, h)
        ex, ey = dx - t * v[0], dy - t * v[1]
        e = (ex * ex + ey * ey) / (2.0 * variance) + 0.5 * (arrive - t) ** 2 * inv_tau2
        a = amplitude * np.exp(-e)
        block = out[r0:r1, c0:c1]
        keep = a >= cutoff
        block[keep] = np.maximum(block[keep], np.floor(a[keep]).astype(np.uint8))
    return out

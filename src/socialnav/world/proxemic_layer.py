"""The ROS ``social_navigation_layers`` proxemic and passing layers (D. V. Lu), vectorized.

Proxemic layer, per person at ``p`` with velocity ``v`` (heading ``θ = atan2(vy, vx)``):
``a = A · exp(-(m_x² / (2 σ_x²) + m_y² / (2 σ²)))`` where ``(m_x, m_y)`` is the cell offset in
the person's heading frame, ``σ² = variance`` and ``σ_x² = variance · (1 + |v| · factor)``
in front of the person (``m_x > 0``) and ``variance`` behind. Cells with ``a < cutoff`` get 0;
others ``floor(a)`` (the original's ``unsigned char`` cast). Defaults are the package's:
A = 77, variance 0.25 m², cutoff 10, factor 5. People are combined by maximum.

Passing layer (``passing=True``): the same elongated lobe, but pointing to the person's *right*
(``θ - π/2``) and only on that half-plane — the cost sits on the side a keep-right robot
should not pass (head-on, the person's right is the robot's left, so the robot keeps right).

Deviations from the C++ package, on purpose:

- The package computes the passing direction as ``atan2(-v) + 1.51`` (it takes the velocity
  reversed, then adds ≈ π/2), i.e. ``θ - 1.63`` rad; here it is exactly ``θ - π/2``.
- A stationary person (``|v| = 0``) has no heading, so the passing layer writes the full
  symmetric Gaussian there (the package's lobe would point along world ``+y`` by accident).
- The bounding window per person is a square of half-size ``get_radius(cutoff, A, σ_x²)``
  (plus a cell), which contains every cell with ``a >= cutoff``, clipped to the grid, so the
  work per person is bounded by the grid whatever the person's speed or position; the
  package's window is shifted and can clip.
- UNKNOWN cells are not skipped here; :func:`socialnav.world.costmap.combine_max` keeps them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import as_points
from socialnav.world.grid import LETHAL, GridGeometry


def get_radius(cutoff: float, amplitude: float, variance: float) -> float:
    """Distance (m) at which ``A · exp(-d² / (2 var))`` falls to ``cutoff``."""
    return float(np.sqrt(-2.0 * variance * np.log(cutoff / amplitude)))


def proxemic_costs(
    geometry: GridGeometry,
    positions: ArrayLike,
    velocities: ArrayLike,
    amplitude: float = 77.0,
    variance: float = 0.25,
    cutoff: float = 10.0,
    velocity_factor: float = 5.0,
    passing: bool = False,
) -> NDArray[np.uint8]:
    """Social cost layer ``(rows, cols)`` uint8 for people at ``positions (K, 2)`` m with
    ``velocities (K, 2)`` m/s. ``K = 0`` gives an all-zero layer.

    Work is vectorized over the cells of each person's own bounding window, clipped to the grid
    (at most ``rows × cols`` cells per person, whatever their speed). The NumPy reference of
    :func:`socialnav.planner.kernels.proxemic_costs` (compiled, the same values).
    """
    out = np.zeros(geometry.shape, dtype=np.uint8)
    res = geometry.resolution
    cols_n = geometry.shape[1]
    ox, oy = geometry.origin
    flat_out = out.reshape(-1)
    for w in person_windows(
        geometry, positions, velocities, amplitude, variance, cutoff, velocity_factor, passing
    ):
        rows = np.arange(w.r0, w.r1)[:, None]
        cols = np.arange(w.c0, w.c1)[None, :]
        dx = ox + (cols + 0.5) * res - w.x  # (1, W)
        dy = oy + (rows + 0.5) * res - w.y  # (H, 1)
        mx = dx * w.cos + dy * w.sin  # (H, W) along the (lobe) heading
        my = dy * w.cos - dx * w.sin
        sx2 = np.where(mx > 0.0, w.var_front, variance)
        a = amplitude * np.exp(-(mx * mx / (2.0 * sx2) + my * my / (2.0 * variance)))
        if w.one_sided:
            a = np.where(mx < 0.0, 0.0, a)
        keep = a >= cutoff
        if not keep.any():
            continue
        flat = (rows * cols_n + cols)[keep]
        # Cells are unique within one window: a plain fancy-index max suffices.
        flat_out[flat] = np.maximum(flat_out[flat], np.floor(a[keep]).astype(np.uint8))
    return out


class PersonWindow(NamedTuple):
    """One person's cell window ``[r0, r1) × [c0, c1)`` (clipped to the grid, non-empty), the
    position ``x, y`` (m), the lobe heading's ``cos``/``sin``, the front variance (m²) and
    whether the lobe is one-sided (passing layer, a moving person)."""

    r0: int
    r1: int
    c0: int
    c1: int
    x: float
    y: float
    cos: float
    sin: float
    var_front: float
    one_sided: bool


def person_windows(
    geometry: GridGeometry,
    positions: ArrayLike,
    velocities: ArrayLike,
    amplitude: float = 77.0,
    variance: float = 0.25,
    cutoff: float = 10.0,
    velocity_factor: float = 5.0,
    passing: bool = False,
) -> list[PersonWindow]:
    """The validated per-person windows of :func:`proxemic_costs` (its arguments; raises
    ``InvalidInputError`` on bad ones): every cell with ``a >= cutoff`` is inside its
    person's window. People whose cost cannot reach the grid have none."""
    pos = as_points(positions, "positions").reshape(-1, 2)
    vel = as_points(velocities, "velocities").reshape(-1, 2)
    if pos.shape != vel.shape:
        raise InvalidInputError(
            f"positions {pos.shape} and velocities {vel.shape} must have the same shape"
        )
    for name, value in (("amplitude", amplitude), ("variance", variance), ("cutoff", cutoff)):
        if not (np.isfinite(value) and value > 0):
            raise InvalidInputError(f"{name} must be finite and positive, got {value}")
    if amplitude > LETHAL:
        raise InvalidInputError(f"amplitude must be <= {LETHAL} (a uint8 cost), got {amplitude}")
    if not (np.isfinite(velocity_factor) and velocity_factor >= 0):
        raise InvalidInputError(f"velocity_factor must be finite and >= 0, got {velocity_factor}")
    if pos.shape[0] == 0 or cutoff >= amplitude:
        return []

    speed = np.hypot(vel[:, 0], vel[:, 1])  # (K,)
    theta = np.arctan2(vel[:, 1], vel[:, 0])
    if passing:
        theta = theta - np.pi / 2.0
    with np.errstate(over="ignore"):
        var_front = variance * (1.0 + speed * velocity_factor)  # (K,)
    res = geometry.resolution
    rows_n, cols_n = geometry.shape
    ox, oy = geometry.origin
    # Per-person windows clipped to the grid: the work is bounded by the grid, whatever a
    # person's speed (a tracker glitch at 10 m/s) or position.
    diagonal = float(np.hypot(rows_n, cols_n)) * res
    out: list[PersonWindow] = []
    for k in range(pos.shape[0]):
        reach = min(get_radius(cutoff, amplitude, float(var_front[k])), diagonal) + res
        c0 = max(int(np.floor(max((pos[k, 0] - reach - ox) / res, -1.0))), 0)
        r0 = max(int(np.floor(max((pos[k, 1] - reach - oy) / res, -1.0))), 0)
        c1 = min(int(np.ceil(min((pos[k, 0] + reach - ox) / res, cols_n + 1.0))) + 1, cols_n)
        r1 = min(int(np.ceil(min((pos[k, 1] + reach - oy) / res, rows_n + 1.0))) + 1, rows_n)
        if r0 >= r1 or c0 >= c1:
            continue  # the person's cost cannot reach the grid
        out.append(
            PersonWindow(
                r0,
                r1,
                c0,
                c1,
                float(pos[k, 0]),
                float(pos[k, 1]),
                float(np.cos(theta[k])),
                float(np.sin(theta[k])),
                float(var_front[k]),
                bool(passing and speed[k] > 0.0),
            )
        )
    return out

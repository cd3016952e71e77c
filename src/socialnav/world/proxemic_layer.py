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
- The bounding window per person is a square of half-size ``get_radius(cutoff, A, σ_x²)``,
  which contains every cell with ``a >= cutoff``; the package's window is shifted and can clip.
- UNKNOWN cells are not skipped here; :func:`socialnav.world.costmap.combine_max` keeps them.
"""

from __future__ import annotations

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

    Work is vectorized over people × cells of a common-size bounding window per person.
    """
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

    out = np.zeros(geometry.shape, dtype=np.uint8)
    if pos.shape[0] == 0 or cutoff >= amplitude:
        return out

    speed = np.hypot(vel[:, 0], vel[:, 1])  # (K,)
    theta = np.arctan2(vel[:, 1], vel[:, 0])
    if passing:
        theta = theta - np.pi / 2.0
    var_front = variance * (1.0 + speed * velocity_factor)  # (K,)
    reach = get_radius(cutoff, amplitude, float(var_front.max()))
    res = geometry.resolution
    half = int(np.ceil(reach / res)) + 1
    offs = np.arange(-half, half + 1)

    centre = geometry.world_to_cell(pos)  # (K, 2) row, col
    rows = centre[:, 0, None, None] + offs[None, :, None]  # (K, W, 1)
    cols = centre[:, 1, None, None] + offs[None, None, :]  # (K, 1, W)
    ox, oy = geometry.origin
    dx = ox + (cols + 0.5) * res - pos[:, 0, None, None]  # (K, 1, W)
    dy = oy + (rows + 0.5) * res - pos[:, 1, None, None]  # (K, W, 1)
    c = np.cos(theta)[:, None, None]
    s = np.sin(theta)[:, None, None]
    mx = dx * c + dy * s  # (K, W, W) along the (lobe) heading
    my = dy * c - dx * s
    vf = var_front[:, None, None]
    front = mx > 0.0
    sx2 = np.where(front, vf, variance)
    a = amplitude * np.exp(-(mx * mx / (2.0 * sx2) + my * my / (2.0 * variance)))
    if passing:
        # One-sided lobe; the person's own cell and stationary people keep the full Gaussian.
        moving = (speed > 0.0)[:, None, None]
        a = np.where(moving & (mx < 0.0), 0.0, a)

    inside = (rows >= 0) & (rows < geometry.shape[0]) & (cols >= 0) & (cols < geometry.shape[1])
    keep = inside & (a >= cutoff)
    flat = np.broadcast_to(rows, a.shape) * geometry.shape[1] + np.broadcast_to(cols, a.shape)
    np.maximum.at(out.reshape(-1), flat[keep], np.floor(a[keep]).astype(np.uint8))
    return out

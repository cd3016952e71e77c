"""Angles, rigid transforms and vectorized planar geometry shared by all layers.

Conventions: SI units, radians, yaw counter-clockwise from +x (REP 103). Poses are ``(x, y, yaw)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core.errors import InvalidInputError

FloatArray = NDArray[np.float64]


def wrap_angle(angle: ArrayLike) -> FloatArray:
    """Wrap angles (rad, any shape) to ``[-pi, pi)``; same shape as ``angle``.

    >>> float(wrap_angle(3 * np.pi / 2))
    -1.5707963267948966
    >>> float(wrap_angle(np.pi))  # the half-open interval: +pi maps to -pi
    -3.141592653589793
    """
    a = np.asarray(angle, dtype=float)
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def as_points(points: ArrayLike, name: str = "points") -> FloatArray:
    """Validate an ``(..., 2)`` array of finite points and return it as float64."""
    p = np.asarray(points, dtype=float)
    if p.ndim == 0 or p.shape[-1] != 2:
        raise InvalidInputError(f"{name} must have shape (..., 2), got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InvalidInputError(f"{name} contains NaN or infinite values")
    return p


def as_pose(pose: ArrayLike, name: str = "pose") -> FloatArray:
    """Validate one finite ``(x, y, yaw)`` pose."""
    p = np.asarray(pose, dtype=float)
    if p.shape != (3,):
        raise InvalidInputError(f"{name} must be (x, y, yaw), got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InvalidInputError(f"{name} contains NaN or infinite values")
    return p


def rotation(yaw: float) -> FloatArray:
    """``(2, 2)`` rotation matrix for ``yaw`` (rad, counter-clockwise).

    >>> np.round(rotation(np.pi / 2) @ [1.0, 0.0], 12).tolist()
    [0.0, 1.0]
    """
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s], [s, c]])


def body_to_world(points: ArrayLike, pose: ArrayLike) -> FloatArray:
    """Map ``(..., 2)`` points (m) from the body frame of ``pose (3,)`` (world ``x, y, yaw``)
    to the world frame (x forward, y left in the body frame).

    >>> body_to_world([1.0, 0.0], [2.0, 3.0, np.pi / 2]).round(12).tolist()
    [2.0, 4.0]
    """
    x, y, yaw = np.asarray(pose, dtype=float)
    return np.asarray(points, dtype=float) @ rotation(yaw).T + np.array([x, y])


def world_to_body(points: ArrayLike, pose: ArrayLike) -> FloatArray:
    """Map ``(..., 2)`` world points (m) into the body frame of ``pose (3,)``; the inverse of
    :func:`body_to_world`.

    >>> world_to_body([2.0, 4.0], [2.0, 3.0, np.pi / 2]).round(12).tolist()
    [1.0, 0.0]
    """
    x, y, yaw = np.asarray(pose, dtype=float)
    return (np.asarray(points, dtype=float) - np.array([x, y])) @ rotation(yaw)


def world_to_body_frames(points: ArrayLike, poses: ArrayLike) -> FloatArray:
    """Map world points (m) into the body frames of many poses at once.

    ``poses (*S, 3)`` (world ``x, y, yaw``) and ``points (*S, *E, 2)``: the pose dimensions lead
    and each pose maps the points under it (``E`` may be empty); returns ``(*S, *E, 2)``.
    :func:`world_to_body` for one pose.

    >>> world_to_body_frames([[2.0, 4.0], [1.0, 0.0]], [[2.0, 3.0, np.pi / 2], [0, 0, 0]]).round(12)
    array([[1., 0.],
           [1., 0.]])
    """
    pts = np.asarray(points, dtype=float)
    q = np.asarray(poses, dtype=float)
    extra = (1,) * (pts.ndim - q.ndim)
    x, y = q[..., 0].reshape(*q.shape[:-1], *extra), q[..., 1].reshape(*q.shape[:-1], *extra)
    yaw = q[..., 2].reshape(*q.shape[:-1], *extra)
    c, s = np.cos(yaw), np.sin(yaw)
    dx, dy = pts[..., 0] - x, pts[..., 1] - y
    return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=-1)


def point_segment_distance(points: ArrayLike, seg_a: ArrayLike, seg_b: ArrayLike) -> FloatArray:
    """Distances from points ``(..., 2)`` to segments ``(S, 2)``–``(S, 2)``: shape ``(..., S)``.

    Degenerate segments (a == b) are points. Units are those of the inputs (m).

    >>> point_segment_distance([[0.0, 1.0], [3.0, 0.0]], [[-1.0, 0.0]], [[1.0, 0.0]]).tolist()
    [[1.0], [2.0]]
    >>> point_segment_distance([0.0, 1.0], [[0.0, 0.0]], [[0.0, 0.0]]).tolist()  # a point
    [1.0]
    """
    p = np.asarray(points, dtype=float)[..., None, :]
    a = np.asarray(seg_a, dtype=float)
    b = np.asarray(seg_b, dtype=float)
    ab = b - a
    denom = np.einsum("si,si->s", ab, ab)
    safe = np.where(denom > 0.0, denom, 1.0)
    t = np.clip(np.einsum("...si,si->...s", p - a, ab) / safe, 0.0, 1.0)
    closest = a + t[..., None] * ab
    return np.linalg.norm(p - closest, axis=-1)


def points_in_polygon(points: ArrayLike, polygon: ArrayLike) -> NDArray[np.bool_]:
    """Even-odd test of ``(..., 2)`` points against a simple polygon ``(V, 2)``: shape ``(...)``.

    >>> square = [[0, 0], [2, 0], [2, 2], [0, 2]]
    >>> points_in_polygon([[1.0, 1.0], [3.0, 1.0]], square).tolist()
    [True, False]
    """
    p = np.asarray(points, dtype=float)
    poly = np.asarray(polygon, dtype=float)
    x, y = p[..., 0, None], p[..., 1, None]
    x0, y0 = poly[:, 0], poly[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    crosses = (y0 > y) != (y1 > y)
    dy = np.where(y1 != y0, y1 - y0, 1.0)
    x_at = x0 + (y - y0) * (x1 - x0) / dy
    return np.count_nonzero(crosses & (x < x_at), axis=-1) % 2 == 1


def polygon_edges(polygon: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Edge start and end points ``(V, 2)`` of a closed polygon."""
    poly = np.asarray(polygon, dtype=float)
    return poly, np.roll(poly, -1, axis=0)


def signed_distance_to_polygon(points: ArrayLike, polygon: ArrayLike) -> FloatArray:
    """Distance (m) of ``(..., 2)`` points to the boundary of polygon ``(V, 2)``, negative inside
    (the penetration depth): shape ``(...)``.

    >>> square = [[0, 0], [2, 0], [2, 2], [0, 2]]
    >>> signed_distance_to_polygon([[1.0, 1.0], [3.0, 1.0]], square).tolist()
    [-1.0, 1.0]
    """
    a, b = polygon_edges(polygon)
    d = point_segment_distance(points, a, b).min(axis=-1)
    return np.where(points_in_polygon(points, polygon), -d, d)

"""Social spaces: group circles and o-spaces, activity spaces, queue bands.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach"
(section "Social Goal"): people in an O-formation are fitted with a circle; an artwork and its
viewer span an activity space; people waiting in line form a queue.

Deviations from / additions to the paper:
- The circle fit is the algebraic (Kåsa) least-squares fit on centred coordinates, so it is
  translation-invariant numerically; the paper does not say which fit it uses.
- Degenerate groups never raise: 1 member → radius 0 at the member; 2 members (or collinear
  members) → the circle with the two extreme members as diameter. The fit reports which rule fired.
- The o-space radius ``R - 0.3`` and the activity-space trapezoid (viewer's shoulders ±0.3 m to
  the artwork's ends) come from the project's scenario definitions, not from the paper.
- Queue bands (rectangles between consecutive members, width 2 × human radius) define "cutting in".
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import (
    FloatArray,
    as_points,
    point_segment_distance,
    points_in_polygon,
    polygon_edges,
)
from socialnav.core.scene import HUMAN_RADIUS

#: The o-space is the disc of radius ``R - OSPACE_MARGIN`` around the group centre (scenarios.md).
OSPACE_MARGIN = 0.3
#: Points closer than this (m) are treated as the same position.
COINCIDENT_TOL = 1e-6
#: A Kåsa circle bigger than this many times the group's span means "collinear" (fit unusable).
COLLINEAR_RADIUS_FACTOR = 10.0


@dataclass(frozen=True)
class CircleFit:
    """Result of :func:`fit_circle_detailed`: ``center (2,)``, ``radius`` (m), ``method``
    (``kasa`` | ``diameter_pair`` | ``single`` | ``collinear``) and the ``rms`` radial residual
    (m)."""

    center: FloatArray
    radius: float
    method: str
    rms: float


def _unique_points(p: FloatArray, tol: float = COINCIDENT_TOL) -> FloatArray:
    """Drop points within ``tol`` of an earlier point (order-independent result set)."""
    if p.shape[0] <= 1:
        return p
    d = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)
    dup = np.triu(d < tol, k=1).any(axis=0)
    return p[~dup]


def principal_axis(positions: FloatArray) -> tuple[FloatArray, FloatArray, float]:
    """Total-least-squares line through ``(K, 2)`` points: ``(centroid (2,), unit direction (2,),
    ratio)`` where ``ratio`` = minor / major singular value (0 for perfectly collinear points).

    The direction's sign is arbitrary (callers orient it).
    """
    centroid = positions.mean(axis=0)
    centred = positions - centroid
    _, s, vt = np.linalg.svd(centred, full_matrices=False)
    ratio = float(s[-1] / s[0]) if s.shape[0] > 1 and s[0] > 0 else 0.0
    return centroid, vt[0], ratio


def fit_circle_detailed(positions: ArrayLike) -> CircleFit:
    """Fit a circle to ``(K, 2)`` member positions; never raises on degenerate layouts.

    - ``K >= 3`` non-collinear unique points: Kåsa fit, i.e. least squares on
      ``x² + y² = 2ax + 2by + c`` (centred data), ``R = sqrt(c + a² + b²)``.
    - 2 unique points, or collinear points (minor/major spread < 1e-6, or a Kåsa radius above
      ``COLLINEAR_RADIUS_FACTOR`` × span): circle with the two extreme points (along the principal
      axis) as diameter; ``method`` says which.
    - 1 unique point: that point, radius 0.

    Raises :class:`InvalidInputError` on NaN, a wrong shape or no points.
    """
    p = as_points(positions, "positions")
    if p.ndim != 2 or p.shape[0] == 0:
        raise InvalidInputError(f"positions must be a non-empty (K, 2) array, got {p.shape}")
    u = _unique_points(p)
    if u.shape[0] == 1:
        return CircleFit(u[0].copy(), 0.0, "single", 0.0)
    centroid, axis, ratio = principal_axis(u)
    along = (u - centroid) @ axis
    lo, hi = u[np.argmin(along)], u[np.argmax(along)]
    span = float(np.linalg.norm(hi - lo))

    def pair_fit(method: str) -> CircleFit:
        c = 0.5 * (lo + hi)
        r = 0.5 * span
        rms = float(np.sqrt(np.mean((np.linalg.norm(p - c, axis=1) - r) ** 2)))
        return CircleFit(c, r, method, rms)

    if u.shape[0] == 2:
        return pair_fit("diameter_pair")
    if ratio < 1e-6:
        return pair_fit("collinear")
    q = u - centroid
    a = np.column_stack([2.0 * q, np.ones(q.shape[0])])
    rhs = np.einsum("ki,ki->k", q, q)
    sol, *_ = np.linalg.lstsq(a, rhs, rcond=None)
    r2 = sol[2] + sol[0] ** 2 + sol[1] ** 2
    radius = float(np.sqrt(max(r2, 0.0)))
    if not np.isfinite(radius) or radius > COLLINEAR_RADIUS_FACTOR * span:
        return pair_fit("collinear")
    center = centroid + sol[:2]
    rms = float(np.sqrt(np.mean((np.linalg.norm(p - center, axis=1) - radius) ** 2)))
    return CircleFit(center, radius, "kasa", rms)


def fit_circle(positions: ArrayLike) -> tuple[FloatArray, float]:
    """``(center (2,), radius)`` of the circle through ``(K, 2)`` positions
    (see :func:`fit_circle_detailed` for the degenerate rules)."""
    fit = fit_circle_detailed(positions)
    return fit.center, fit.radius


def o_space(positions: ArrayLike, margin: float = OSPACE_MARGIN) -> tuple[FloatArray, float]:
    """The o-space disc of a group: ``(center (2,), max(R - margin, 0))`` (m)."""
    center, radius = fit_circle(positions)
    return center, max(radius - margin, 0.0)


def _unit(v: FloatArray, fallback: FloatArray) -> FloatArray:
    n = float(np.linalg.norm(v))
    return v / n if n > COINCIDENT_TOL else fallback


def art_frame(art_facing: float) -> tuple[FloatArray, FloatArray]:
    """``(normal, tangent)`` unit vectors of an artwork: ``normal`` points into the room,
    ``tangent`` = normal rotated +90° (along the wall)."""
    n = np.array([np.cos(art_facing), np.sin(art_facing)])
    return n, np.array([-n[1], n[0]])


def activity_space_polygon(
    art_center: ArrayLike,
    art_width: float,
    art_facing: float,
    viewer_position: ArrayLike,
    shoulder: float = 0.3,
) -> FloatArray:
    """The activity space between a viewer and an artwork: a ``(4, 2)`` trapezoid.

    Vertices: the viewer's shoulders (``viewer ± shoulder`` perpendicular to the viewer→art
    direction) and the artwork's two ends (``center ± width/2`` along the wall), ordered
    counter-clockwise-or-clockwise without self-intersection (each shoulder is joined to the
    artwork end on its own side).
    """
    c = as_points(art_center, "art_center").reshape(2)
    v = as_points(viewer_position, "viewer_position").reshape(2)
    if not (np.isfinite(art_width) and np.isfinite(art_facing) and np.isfinite(shoulder)):
        raise InvalidInputError("art_width, art_facing and shoulder must be finite")
    n, t = art_frame(float(art_facing))
    look = _unit(c - v, -n)
    side = np.array([-look[1], look[0]])
    if side @ t < 0:  # pair each shoulder with the artwork end on the same side
        side = -side
    half = 0.5 * float(art_width)
    return np.array([v + shoulder * side, c + half * t, c - half * t, v - shoulder * side])


def queue_band_polygons(
    positions: ArrayLike, width: float = 2.0 * HUMAN_RADIUS
) -> list[FloatArray]:
    """Rectangles ``(4, 2)`` of the given ``width`` (m) joining consecutive queue members.

    A robot whose footprint enters one of them is cutting into the line. Coincident consecutive
    members give a ``width`` × ``width`` square around them.
    """
    p = as_points(positions, "positions")
    if p.ndim != 2:
        raise InvalidInputError(f"positions must be (K, 2), got {p.shape}")
    half = 0.5 * float(width)
    bands: list[FloatArray] = []
    for a, b in itertools.pairwise(p):
        d = _unit(b - a, np.array([1.0, 0.0]))
        nrm = np.array([-d[1], d[0]]) * half
        if np.linalg.norm(b - a) <= COINCIDENT_TOL:
            a, b = a - d * half, b + d * half
        bands.append(np.array([a + nrm, b + nrm, b - nrm, a - nrm]))
    return bands


def segment_segment_distance(
    p0: ArrayLike, p1: ArrayLike, q0: ArrayLike, q1: ArrayLike
) -> FloatArray:
    """Distances (m) between one segment ``p0–p1`` (each ``(2,)``) and segments ``q0–q1``
    ``(S, 2)``: shape ``(S,)``; 0 where they intersect."""
    p0 = np.asarray(p0, dtype=float)
    p1 = np.asarray(p1, dtype=float)
    q0 = np.asarray(q0, dtype=float)
    q1 = np.asarray(q1, dtype=float)
    d = np.minimum(point_segment_distance(p0, q0, q1), point_segment_distance(p1, q0, q1))
    d = np.minimum(d, point_segment_distance(q0, p0[None], p1[None])[:, 0])
    d = np.minimum(d, point_segment_distance(q1, p0[None], p1[None])[:, 0])

    def cross(o: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
        return (a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1]) - (a[..., 1] - o[..., 1]) * (
            b[..., 0] - o[..., 0]
        )

    d1, d2 = cross(p0, p1, q0), cross(p0, p1, q1)
    d3, d4 = cross(q0, q1, p0), cross(q0, q1, p1)
    proper = (d1 * d2 < 0) & (d3 * d4 < 0)
    return np.where(proper, 0.0, d)


def segment_polygon_distance(a: ArrayLike, b: ArrayLike, polygon: ArrayLike) -> float:
    """Distance (m) from the segment ``a–b`` to a simple polygon ``(V, 2)``; 0 when they meet."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    poly = np.asarray(polygon, dtype=float)
    if points_in_polygon(np.stack([a, b]), poly).any():
        return 0.0
    e0, e1 = polygon_edges(poly)
    return float(segment_segment_distance(a, b, e0, e1).min())

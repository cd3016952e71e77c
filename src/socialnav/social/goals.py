"""Social goals: where the robot should stand to join a group, queue up, present art or pass.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach",
section "Social Goal". All goals are computed from the people's geometry, never hand-placed.

Deviations from the paper (each also noted where it applies):
- O-formation: the paper writes ``θ_ij = acos((2R² − D_ij)/2R²)`` — ``D_ij`` must be squared
  (law of cosines with a = b = R); we use ``D_ij²``. The law of cosines only yields angles in
  [0, π], so it cannot tell a reflex gap (> π, e.g. 3 members squeezed on one side) from its
  complement; gaps are therefore measured from the sorted member bearings around the fitted
  centre, and the law-of-cosines values are reported in ``geometry`` for comparison.
- O-formation: the spot is the paper's circle–circle intersection (radius
  ``c = sqrt(2R²(1 − cos θ_a))`` around the gap's first member, CCW), keeping the solution inside
  the gap; "lead" mode uses the gap bisector directly (identical when members lie on the circle).
  When the spot is closer than ``min_member_distance`` to a member (narrow gaps, full circles,
  tight pairs), it slides outward along the bisector until clear (fallback ``widened``).
- Queue: the paper fits ``y = mx + c``, which fails for vertical queues (the ``queue_line``
  scenario is vertical); we fit the total-least-squares (principal-axis) line.
- Art gallery: the paper hand-selects the presenter spot; we compute it (rule in
  :func:`presenter_pose`). The passing waypoint behind the viewer is also computed.
- Optional ``free_fn`` (points ``(M, 2)`` → free ``(M,)`` bool, e.g. from a costmap) lets a caller
  reject spots inside walls; the functions then try the next candidate and report the fallback.
Degenerate inputs (one member, coincident or collinear members, no free spot) never raise: the
result carries ``fallback`` (a short tag) and ``reason`` (a sentence). NaN or wrong shapes raise
:class:`~socialnav.core.errors.InvalidInputError`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import FloatArray, as_points, signed_distance_to_polygon, wrap_angle
from socialnav.core.scene import SocialContext
from socialnav.social.spaces import (
    COINCIDENT_TOL,
    _unique_points,
    activity_space_polygon,
    art_frame,
    fit_circle_detailed,
    principal_axis,
    segment_polygon_distance,
)

#: built-in kinds: queue_tail, o_formation, o_formation_lead, presenter, waypoint; a structure
#: kind of :mod:`socialnav.social.structures` names its own
GoalKind = str
FreeFn = Callable[[FloatArray], NDArray[np.bool_]]

#: Default tolerances of a stopping social goal (the scenarios' success radius is 0.3 m).
POSITION_TOLERANCE = 0.25  # inside the 0.3 m success radius, loose enough for a diff drive
YAW_TOLERANCE = 0.25
#: A waypoint is passed, not reached exactly; it carries no heading requirement.
WAYPOINT_TOLERANCE = 0.5
#: Gaps whose widths differ by less than this (rad) are ties (broken by robot proximity).
GAP_TIE_TOL = 1e-3
#: The presenter spot's cost ``k·(ρ − social_distance)² + depth`` (:func:`presenter_pose`):
#: ``k`` (1/m). At 10 the spot keeps within ~0.07 m of the social distance while that circle
#: reaches beside the activity space, and moves at most ~1.4 m per metre the viewer moves
#: where it does not (a larger ``k`` approaches the exact circle and its steep tangent).
PRESENTER_STIFFNESS = 10.0
#: Slope of the presenter spot's drop cap near the distance range's end (``_presenter_spot``):
#: within ``r_max − h`` of it the spot drops at most 3× that far below the viewer's depth.
DROP_CAP_SLOPE = 3.0
#: Distance scale (m) over which the presenter's heading blends from the nearest viewer toward
#: a nearly-as-near one (:func:`presenter_pose`); a step at equal distances flipped the heading
#: by 0.64 rad for a robot 6 cm off the spot (generated gallery_present dev seed 28, PR2).
FACING_BLEND = 0.1


@dataclass(frozen=True, eq=False)
class SocialGoal:
    """A social goal pose and how it was obtained.

    - ``pose (3,)``: ``(x, y, yaw)`` in the world frame (m, rad).
    - ``kind``: ``queue_tail`` | ``o_formation`` | ``o_formation_lead`` | ``presenter`` |
      ``waypoint``.
    - ``position_tolerance`` (m) / ``yaw_tolerance`` (rad): when the goal counts as reached.
    - ``is_waypoint``: pass through it, then continue to the given goal.
    - ``geometry``: the construction (circle, gaps, line, polygon, candidates) for plots and tests.
    - ``fallback`` / ``reason``: which degenerate-case rule fired and why (``None`` when none).
    """

    pose: FloatArray
    kind: GoalKind
    position_tolerance: float = POSITION_TOLERANCE
    yaw_tolerance: float = YAW_TOLERANCE
    is_waypoint: bool = False
    geometry: dict[str, Any] = field(default_factory=dict)
    fallback: str | None = None
    reason: str | None = None

    @property
    def position(self) -> FloatArray:
        """``(2,)`` world position (m)."""
        return self.pose[:2]

    @property
    def yaw(self) -> float:
        """Goal heading (rad, world)."""
        return float(self.pose[2])


def interaction_distances(
    social: SocialContext, spot: ArrayLike, threshold: float, margin: float
) -> FloatArray:
    """Per person ``(K,)`` of ``social``: the distance (m) the robot keeps from them once it
    stands at the stopping social goal ``spot (2,)`` (world frame, m). The members of a
    structure (group member, queue member, artwork viewer) nearer ``spot`` than ``threshold``
    are the people the robot joins, queues behind or presents to (its interaction partners):
    theirs is the spot's own distance to them less ``margin`` (at least 1 mm); everyone else's
    is ``threshold``. Source: issue "one configuration" (partners at the interaction's own
    distance: the formation's member spacing, the queue spacing, the presenter's distance)."""
    out = np.full(len(social.people), float(threshold))
    if not social.people:
        return out
    members: set[int] = set()
    for g in social.groups:
        members.update(g.member_ids)
    for q in social.queues:
        members.update(q.member_ids)
    for a in social.artworks:
        members.update(a.viewer_ids)
    gaps = np.linalg.norm(social.positions() - np.asarray(spot, dtype=float)[:2], axis=1)
    for k, person in enumerate(social.people):
        if person.id in members and gaps[k] < threshold:
            out[k] = max(float(gaps[k]) - margin, 1e-3)
    return out


# ---------------------------------------------------------------------------------------------
# validation helpers


def _members(positions: ArrayLike) -> FloatArray:
    p = as_points(positions, "positions")
    if p.ndim != 2 or p.shape[0] == 0:
        raise InvalidInputError(f"positions must be a non-empty (K, 2) array, got {p.shape}")
    return p


def _point(value: ArrayLike | None, name: str) -> FloatArray | None:
    if value is None:
        return None
    p = as_points(value, name)
    if p.shape != (2,):
        raise InvalidInputError(f"{name} must have shape (2,), got {p.shape}")
    return p


def _scalar(value: float, name: str, positive: bool = False) -> float:
    v = float(value)
    if not np.isfinite(v) or (positive and v <= 0):
        raise InvalidInputError(f"{name} must be finite{' and positive' if positive else ''}")
    return v


def _face(position: FloatArray, target: FloatArray) -> float:
    d = target - position
    return float(np.arctan2(d[1], d[0]))


def _pose(position: FloatArray, yaw: float) -> FloatArray:
    return np.array([position[0], position[1], float(wrap_angle(yaw))])


def _first_free(candidates: FloatArray, free_fn: FreeFn | None) -> int | None:
    """Index of the first free candidate ``(M, 2)`` (0 when no ``free_fn``), ``None`` if none."""
    if free_fn is None:
        return 0
    free = np.asarray(free_fn(candidates), dtype=bool).reshape(-1)
    hits = np.flatnonzero(free)
    return int(hits[0]) if hits.size else None


def _rotate(v: FloatArray, angle: float) -> FloatArray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _fan(direction: FloatArray, max_angle: float = np.pi, step: float = np.pi / 12) -> FloatArray:
    """Unit directions ``(M, 2)``: ``direction`` first, then alternately ±step, ±2·step, …"""
    angles = [0.0]
    k = 1
    while k * step <= max_angle + 1e-9:
        angles += [k * step, -k * step]
        k += 1
    return np.array([_rotate(direction, a) for a in angles])


# ---------------------------------------------------------------------------------------------
# O-formation


def circle_intersections(c0: FloatArray, r0: float, c1: FloatArray, r1: float) -> FloatArray:
    """Intersection points ``(M, 2)``, M in {0, 1, 2}, of two circles."""
    delta = c1 - c0
    d = float(np.linalg.norm(delta))
    if d <= COINCIDENT_TOL or d > r0 + r1 + 1e-12 or d < abs(r0 - r1) - 1e-12:
        return np.zeros((0, 2))
    a = (r0**2 - r1**2 + d**2) / (2.0 * d)
    h = np.sqrt(max(r0**2 - a**2, 0.0))
    base = c0 + a * delta / d
    perp = np.array([-delta[1], delta[0]]) / d
    if h == 0.0:
        return base[None]
    return np.stack([base + h * perp, base - h * perp])


def _clear_radius(
    center: FloatArray, u: FloatArray, rho0: float, members: FloatArray, dmin: float
) -> float:
    """Smallest ``ρ >= rho0`` with ``|center + ρu − m| >= dmin`` for every member ``m``."""
    w = members - center
    b = w @ u
    disc = b**2 - (np.einsum("ki,ki->k", w, w) - dmin**2)
    lo = np.where(disc > 0, b - np.sqrt(np.maximum(disc, 0.0)), np.inf)
    hi = np.where(disc > 0, b + np.sqrt(np.maximum(disc, 0.0)), -np.inf)
    rho = rho0
    for _ in range(members.shape[0] + 1):  # each pass clears at least one blocking interval
        blocking = (lo < rho) & (rho < hi)
        if not blocking.any():
            break
        rho = float(hi[blocking].max())
    return rho


def o_formation_join_pose(
    positions: ArrayLike,
    mode: Literal["join", "lead"] = "join",
    robot_position: ArrayLike | None = None,
    *,
    min_member_distance: float = 0.75,
    single_distance: float = 1.2,
    free_fn: FreeFn | None = None,
) -> SocialGoal:
    """The spot to join (or lead) an O-formation of members ``(K, 2)``, facing the group centre.

    Construction (paper, with the deviations in the module docstring):
    1. fit the group circle ``(c, R)`` (Kåsa for >= 3 non-collinear members; the pair as
       diameter for 2; see :func:`~socialnav.social.spaces.fit_circle_detailed`);
    2. sort member bearings around ``c``; the widest angular gap ``g`` between angularly
       adjacent members gives the approach angle ``θ_a = g / 2``;
    3. ``join``: intersect the group circle with the circle of radius
       ``c_a = sqrt(2R²(1 − cos θ_a))`` around the gap's first (CCW) member and keep the
       solution inside the gap; ``lead``: the point of the circle on the gap bisector;
    4. slide outward along the bisector until every member is >= ``min_member_distance`` (m)
       away (default 0.75 = human radius 0.25 + PR2 circumscribed radius 0.46 + margin).

    Ties between gaps (within 1e-3 rad, e.g. the two half-circles of a pair) go to the gap whose
    spot is nearest ``robot_position``, else to the smaller bisector bearing (deterministic but
    not rotation-equivariant — pass ``robot_position`` when it matters).

    Degenerate cases (``fallback``): ``single_member`` — stand ``single_distance`` m from the
    person, on the robot's side (else +x); ``collinear`` — the centre is the middle of the row,
    the spot is in front of it on the robot's side (else the left of the principal axis);
    ``widened`` — step 4 moved the spot; ``next_gap`` / ``no_free_spot`` — ``free_fn`` rejected
    the best spot (used the next candidate / none was free: the best spot is returned anyway).
    """
    if mode not in ("join", "lead"):
        raise InvalidInputError(f"mode must be 'join' or 'lead', got {mode!r}")
    p = _members(positions)
    robot = _point(robot_position, "robot_position")
    dmin = _scalar(min_member_distance, "min_member_distance")
    single = _scalar(single_distance, "single_distance", positive=True)
    kind: GoalKind = "o_formation" if mode == "join" else "o_formation_lead"
    fit = fit_circle_detailed(p)
    center, radius = fit.center, fit.radius
    geometry: dict[str, Any] = {
        "center": center,
        "radius": radius,
        "fit": fit.method,
        "rms": fit.rms,
        "members": p,
    }
    fallback: str | None = None
    reason: str | None = None

    if fit.method == "single":
        toward = np.array([1.0, 0.0])
        if robot is not None and np.linalg.norm(robot - center) > COINCIDENT_TOL:
            toward = (robot - center) / np.linalg.norm(robot - center)
        dirs = _fan(toward)
        spots = center + single * dirs
        fallback = "single_member"
        reason = f"one distinct member: stand {single:.2f} m from them, " + (
            "on the robot's side" if robot is not None else "along +x (no robot position)"
        )
        geometry["candidates"] = spots
        return _pick_spot(spots, center, kind, geometry, fallback, reason, free_fn)

    if fit.method == "collinear":
        _, axis, _ = principal_axis(_unique_points(p))
        normal = np.array([-axis[1], axis[0]])
        if robot is not None and (robot - center) @ normal < 0:
            normal = -normal
        dirs = np.stack([normal, -normal])
        rhos = np.array([_clear_radius(center, u, radius, p, dmin) for u in dirs])
        spots = center + rhos[:, None] * dirs
        geometry["candidates"] = spots
        reason = "members are collinear: stand in front of the middle of the row"
        return _pick_spot(spots, center, kind, geometry, "collinear", reason, free_fn)

    # kasa or diameter_pair: gaps around the fitted centre
    u_members = _unique_points(p)
    rel = u_members - center
    order = np.argsort(np.arctan2(rel[:, 1], rel[:, 0]))
    by_bearing = u_members[order]  # members sorted CCW around the centre
    bearings = np.arctan2(rel[order, 1], rel[order, 0])
    gaps = np.diff(np.append(bearings, bearings[0] + 2.0 * np.pi))
    nxt = np.roll(np.arange(bearings.shape[0]), -1)
    # the paper's law of cosines (with D_ij squared), reported for comparison only
    chord = np.linalg.norm(by_bearing[nxt] - by_bearing, axis=1)
    cos_theta = (2 * radius**2 - chord**2) / (2 * radius**2) if radius > 0 else np.ones_like(chord)
    geometry["bearings"] = bearings
    geometry["gaps"] = gaps
    geometry["law_of_cosines_angles"] = np.arccos(np.clip(cos_theta, -1.0, 1.0))

    bisectors = bearings + gaps / 2.0
    dirs = np.column_stack([np.cos(bisectors), np.sin(bisectors)])
    base_spots = center + radius * dirs
    # rank gaps: widest first; ties by robot proximity, then bearing
    rounded = np.round(gaps / GAP_TIE_TOL)
    prox = np.zeros(gaps.shape[0]) if robot is None else np.linalg.norm(base_spots - robot, axis=1)
    rank = np.lexsort((wrap_angle(bisectors), prox, -rounded))
    widest = int(rank[0])
    theta_a = gaps[widest] / 2.0
    c_a = float(np.sqrt(2.0 * radius**2 * (1.0 - np.cos(theta_a))))
    edge = by_bearing[widest]
    geometry.update(
        widest_gap=float(gaps[widest]),
        approach_angle=float(theta_a),
        chord_radius=c_a,
        edge_member=edge,
    )
    spots_on_circle = base_spots[rank].copy()
    if mode == "join":
        sols = circle_intersections(center, radius, edge, c_a)
        geometry["intersections"] = sols
        if sols.shape[0]:
            rel_s = sols - center
            offs = np.mod(np.arctan2(rel_s[:, 1], rel_s[:, 0]) - bearings[widest], 2 * np.pi)
            inside = (offs > 0) & (offs < gaps[widest])
            if inside.any():
                best = np.flatnonzero(inside)[np.argmin(np.abs(offs[inside] - theta_a))]
                spots_on_circle[0] = sols[best]
            else:
                fallback, reason = "bisector", "no circle intersection inside the gap"
        else:
            fallback, reason = "bisector", "the construction circles do not intersect"
    ranked_dirs = dirs[rank]
    rho0 = np.linalg.norm(spots_on_circle - center, axis=1)
    rhos = np.array(
        [_clear_radius(center, u, r0, p, dmin) for u, r0 in zip(ranked_dirs, rho0, strict=True)]
    )
    spots = center + rhos[:, None] * ranked_dirs
    # keep the exact construction point when it is already clear of everyone
    unchanged = np.isclose(rhos, rho0)
    spots[unchanged] = spots_on_circle[unchanged]
    geometry["candidates"] = spots
    geometry["spot_on_circle"] = spots_on_circle[0]
    if not unchanged[0]:
        fallback = "widened"
        reason = (
            f"widest gap {np.degrees(gaps[widest]):.0f}° leaves less than "
            f"{dmin:.2f} m to a member on the circle (R = {radius:.2f} m): spot moved out to "
            f"{rhos[0]:.2f} m from the centre"
        )
    return _pick_spot(spots, center, kind, geometry, fallback, reason, free_fn)


def _pick_spot(
    spots: FloatArray,
    look_at: FloatArray,
    kind: GoalKind,
    geometry: dict[str, Any],
    fallback: str | None,
    reason: str | None,
    free_fn: FreeFn | None,
) -> SocialGoal:
    idx = _first_free(spots, free_fn)
    if idx is None:
        idx = 0
        fallback = "no_free_spot"
        reason = "no candidate spot is free (free_fn); returning the preferred spot anyway"
    elif idx > 0:
        fallback = "next_gap"
        reason = f"preferred spot not free (free_fn); used candidate {idx}"
    spot = spots[idx]
    return SocialGoal(
        _pose(spot, _face(spot, look_at)), kind, geometry=geometry, fallback=fallback, reason=reason
    )


# ---------------------------------------------------------------------------------------------
# Queue


def queue_tail_pose(
    positions: ArrayLike,
    service_point: ArrayLike,
    spacing: float = 0.8,
    *,
    robot_position: ArrayLike | None = None,
    free_fn: FreeFn | None = None,
    robot_front: float = 0.0,
    member_radius: float = 0.25,
) -> SocialGoal:
    """The tail slot of a queue whose members ``(K, 2)`` run head → tail.

    Fit the total-least-squares line through the members (the paper's ``y = mx + c`` fails on
    vertical queues), intersect it with the circle of radius ``spacing`` (m) around the last
    member and keep the solution farthest from ``service_point``. The robot faces the last member.

    A robot that reaches farther ahead of its centre than a person does (``robot_front`` m,
    the footprint's extent along its heading, against the last member's ``member_radius`` m)
    keeps the queue's own body gap (``spacing − 2·member_radius`` between people) from the
    last member's back: the circle's radius is ``spacing + max(0, robot_front −
    member_radius)``. At the people's centre spacing a PR2 (0.325 m) in a 0.6 m queue would
    stand 2.5 cm from a back, inside its own costmap's inscribed inflation of that person.
    The default ``robot_front = 0`` is the rule above (the paper's).

    Fallbacks: ``single_member`` (one distinct position: go ``spacing`` away from the service
    point; if the member stands on it, toward the robot, else +x); ``off_line`` (the last member
    is more than ``spacing`` from the fitted line: extend the line direction from the last
    member); ``rotated`` / ``no_free_spot`` (``free_fn`` rejected the slot: the slot is swung
    around the last member in 15° steps up to ±90°; none free → the nominal slot).
    """
    p = _members(positions)
    service = _point(service_point, "service_point")
    assert service is not None
    robot = _point(robot_position, "robot_position")
    s = _scalar(spacing, "spacing", positive=True)
    front = _scalar(robot_front, "robot_front")
    radius = _scalar(member_radius, "member_radius")
    s += max(0.0, front - radius)
    last = p[-1]
    geometry: dict[str, Any] = {"members": p, "service_point": service, "spacing": s}
    fallback: str | None = None
    reason: str | None = None
    unique = _unique_points(p)
    if unique.shape[0] == 1:
        away = last - service
        if np.linalg.norm(away) <= COINCIDENT_TOL:
            away = (robot - last) if robot is not None else np.array([1.0, 0.0])
            if np.linalg.norm(away) <= COINCIDENT_TOL:
                away = np.array([1.0, 0.0])
        direction = away / np.linalg.norm(away)
        tail = last + s * direction
        fallback, reason = "single_member", "one distinct member: line direction = away from desk"
    else:
        centroid, direction, ratio = principal_axis(unique)
        geometry.update(line_point=centroid, line_direction=direction, line_spread=ratio)
        foot = centroid + ((last - centroid) @ direction) * direction
        h = float(np.linalg.norm(last - foot))
        if h < s:
            half = np.sqrt(s**2 - h**2)
            sols = np.stack([foot + half * direction, foot - half * direction])
            geometry["intersections"] = sols
            tail = sols[np.argmax(np.linalg.norm(sols - service, axis=1))]
        else:
            if (last - service) @ direction < 0:
                direction = -direction
            tail = last + s * direction
            fallback = "off_line"
            reason = f"last member {h:.2f} m off the fitted line (> spacing {s:.2f} m)"
    offset = tail - last
    candidates = np.array(
        [
            last + _rotate(offset, a)
            for a in np.radians([0, 15, -15, 30, -30, 45, -45, 60, -60, 75, -75, 90, -90])
        ]
    )
    geometry["candidates"] = candidates
    idx = _first_free(candidates, free_fn)
    if idx is None:
        idx, fallback = 0, "no_free_spot"
        reason = "no slot around the last member is free (free_fn); returning the nominal slot"
    elif idx > 0:
        fallback, reason = "rotated", "nominal tail slot not free; swung around the last member"
    spot = candidates[idx]
    geometry["tail"] = spot
    return SocialGoal(
        _pose(spot, _face(spot, last)),
        "queue_tail",
        geometry=geometry,
        fallback=fallback,
        reason=reason,
    )


# ---------------------------------------------------------------------------------------------
# Art gallery


def _art_inputs(
    art_center: ArrayLike, art_width: float, art_facing: float, viewer_position: ArrayLike
) -> tuple[FloatArray, float, float, FloatArray]:
    c = _point(art_center, "art_center")
    v = _point(viewer_position, "viewer_position")
    assert c is not None and v is not None
    return c, _scalar(art_width, "art_width", True), _scalar(art_facing, "art_facing"), v


def presenter_pose(
    art_center: ArrayLike,
    art_width: float,
    art_facing: float,
    viewer_position: ArrayLike,
    viewer_yaw: float,
    social_distance: float = 1.2,
    *,
    robot_position: ArrayLike | None = None,
    distance_range: tuple[float, float] = (0.9, 1.6),
    art_clearance: float = 0.35,
    wall_clearance: float = 0.5,
    shoulder: float = 0.3,
    radius_stiffness: float = PRESENTER_STIFFNESS,
    other_viewers: ArrayLike | None = None,
    free_fn: FreeFn | None = None,
) -> SocialGoal:
    """Where a robot presents an artwork to its viewer (the paper hand-selects it).

    Work in the artwork frame: lateral ``l`` along the wall (tangent = facing + 90°) and depth
    ``d`` along the facing normal (into the room). The spot ``p`` lies

    - beside the artwork on side ``σ`` (the robot's side, else +tangent): ``σ·l >= L`` where
      ``L`` = the lateral extent on that side of the viewer's activity space (and of those of
      ``other_viewers (K, 2)``, the artwork's other viewers) + ``art_clearance`` (m), so it is
      outside every activity space,
    - at least ``wall_clearance`` (m) from the wall (``d >= wall_clearance``),
    - at a distance ``ρ = |p − viewer|`` within ``distance_range`` (m),

    and minimises ``k·(ρ − social_distance)² + d`` (``k`` = ``radius_stiffness``, 1/m): on the
    ``social_distance`` circle as close to the wall as possible ("beside the art") when that
    circle reaches the wall band beside the activity space, else the point of the edge
    ``σ·l = L`` that trades a slightly larger distance for a spot nearer the wall. The
    minimiser is unique and continuous in every input (a stepped search over radii moved it
    ~0.2 m for a 2 mm change of the viewer), so a noisy estimate of the viewer gives a spot
    near the true one (property test). It faces the nearest of the artwork's viewers (the
    presenter "faces the viewer", scenarios.md; the success check measures the nearest),
    blended toward another one nearly as near (``_face_nearest``).

    If the preferred side has no solution, or ``free_fn`` rejects its spot, the other side is
    used (fallback ``other_side``); with neither, the spot ``(σL, wall_clearance)`` is returned
    (``no_free_spot``). A viewer not in front of the wall (``d <= 0``: "in the wall") gives
    fallback ``viewer_not_in_front``. ``viewer_yaw`` is used only to report the spot's bearing
    from the viewer's gaze (``geometry['bearing_from_gaze']``). Raises
    :class:`~socialnav.core.errors.InvalidInputError` on NaN, wrong shapes, a non-positive
    ``radius_stiffness`` or a ``distance_range`` that does not hold ``social_distance``.
    """
    c, width, facing, v = _art_inputs(art_center, art_width, art_facing, viewer_position)
    gaze = _scalar(viewer_yaw, "viewer_yaw")
    r_nominal = _scalar(social_distance, "social_distance", positive=True)
    stiffness = _scalar(radius_stiffness, "radius_stiffness", positive=True)
    r_min, r_max = (_scalar(x, "distance_range") for x in distance_range)
    if not r_min <= r_nominal <= r_max:
        raise InvalidInputError(
            f"distance_range {distance_range} must hold social_distance {r_nominal}"
        )
    robot = _point(robot_position, "robot_position")
    others = (
        np.zeros((0, 2)) if other_viewers is None else as_points(other_viewers, "other_viewers")
    )
    others = others.reshape(-1, 2)
    n, t = art_frame(facing)
    poly = activity_space_polygon(c, width, facing, v, shoulder)
    polys = [poly] + [activity_space_polygon(c, width, facing, o, shoulder) for o in others]
    lv, dv = float((v - c) @ t), float((v - c) @ n)
    lat = np.concatenate([(p - c) @ t for p in polys])
    sides = [1.0, -1.0]
    if robot is not None and (robot - c) @ t < 0:
        sides = [-1.0, 1.0]
    geometry: dict[str, Any] = {
        "activity_space": poly,
        "normal": n,
        "tangent": t,
        "viewer_lateral": lv,
        "viewer_depth": dv,
    }
    fallback: str | None = None
    reason: str | None = None
    if dv <= 0:
        fallback, reason = "viewer_not_in_front", "the viewer is not in front of the artwork"
    chosen: FloatArray | None = None
    for k, sigma in enumerate(sides):
        lmin = float((sigma * lat).max()) + art_clearance
        best = _presenter_spot(sigma * lv, dv, r_nominal, lmin, wall_clearance, r_max, stiffness)
        if best is None:
            continue
        spot = c + sigma * best[0] * t + best[1] * n
        if _first_free(spot[None], free_fn) is None:
            continue
        chosen = spot
        geometry.update(side=sigma, radius=float(np.linalg.norm(spot - v)), lateral_min=lmin)
        if k > 0:
            fallback = "other_side"
            reason = "no valid spot on the preferred side; presenting from the other side"
        break
    if chosen is None:
        sigma = sides[0]
        lmin = float((sigma * lat).max()) + art_clearance
        chosen = c + sigma * lmin * t + wall_clearance * n
        fallback = "no_free_spot"
        reason = "no spot satisfies distance, activity-space and wall constraints"
    yaw = _face_nearest(chosen, np.vstack([v[None], others]))
    bearing = _face(v, chosen)
    geometry["bearing_from_gaze"] = float(wrap_angle(bearing - gaze))
    geometry["viewer_distance"] = float(np.linalg.norm(chosen - v))
    geometry["activity_space_distance"] = float(signed_distance_to_polygon(chosen, poly))
    return SocialGoal(
        _pose(chosen, yaw),
        "presenter",
        geometry=geometry,
        fallback=fallback,
        reason=reason,
    )


def _face_nearest(spot: FloatArray, viewers: FloatArray) -> float:
    """Heading (rad) from ``spot (2,)`` toward the nearest of ``viewers (K, 2)``, blended
    continuously: the mean of the unit bearings weighted ``exp(−(d − d_min)/FACING_BLEND)``.
    A viewer clearly nearest is faced (within a few degrees); two viewers equally near are
    split, so the heading is within half their angle of whichever is judged the nearest."""
    rel = viewers - spot
    dist = np.linalg.norm(rel, axis=1)
    if dist.min() <= COINCIDENT_TOL:
        return 0.0
    w = np.exp(-(dist - dist.min()) / FACING_BLEND)
    u = (w[:, None] * rel / dist[:, None]).sum(axis=0)
    if np.linalg.norm(u) <= COINCIDENT_TOL:  # opposite viewers at one distance: the first
        u = rel[int(np.argmin(dist))]
    return float(np.arctan2(u[1], u[0]))


def _presenter_spot(
    xv: float, dv: float, r: float, lmin: float, wc: float, r_max: float, k: float
) -> tuple[float, float] | None:
    """The minimiser ``(x, d)`` of ``k·(ρ − r)² + d`` over ``x >= lmin``, ``d >= wc`` and
    ``ρ = |(x, d) − (xv, dv)| <= r_max`` (lateral ``x`` mirrored so the side is +), or ``None``
    when that set is empty. ``xv < lmin`` (the viewer is inside its own activity space).

    The cost along the edge ``d = wc`` is least at ``ρ = r``; when that point lies beside the
    activity space (``x >= lmin``) it is the global minimum (cost ``wc``, and no point has
    ``d < wc``). Otherwise the minimum lies on the edge ``x = lmin``: with the drop
    ``s = dv − d`` below the viewer, ``ρ = hypot(h, s)`` (``h = lmin − xv``) and the cost's
    derivative ``2k(ρ − r)s/ρ − 1`` is negative up to its single root (past ``ρ = r``) and
    positive after it, so the minimiser is that root clipped to the feasible drops: at most
    ``dv − wc`` (the wall band), ``sqrt(r_max² − h²)`` (the distance range) and
    ``C·(r_max − h)`` (``C`` = ``DROP_CAP_SLOPE``), which moves the spot to the tangent point
    with a bounded slope as the edge recedes to ``r_max`` (where the other side takes over).
    """
    a = dv - wc
    if abs(a) <= r:
        x_wall = xv + np.sqrt(r**2 - a**2)
        if x_wall >= lmin:
            return float(x_wall), wc
    h = max(lmin - xv, 0.0)
    if h > r_max:
        return None
    reach = np.sqrt(r_max**2 - h**2)  # the largest drop the distance range allows
    if a < -reach:
        return None
    # near the range's end the bare reach is a tangent (infinitely steep in h): the drop is
    # also capped by C·(r_max − h), which falls to 0 there with slope C; C >= r/(r_max − r)
    # keeps that cap clear of every drop on the way to the corner (where ρ <= r, h <= r)
    cap = reach
    if r < r_max:
        cap = min(reach, max(DROP_CAP_SLOPE, r / (r_max - r)) * (r_max - h))
    s_max = min(a, cap)

    def slope(s: float) -> float:
        rho = float(np.hypot(h, s))
        return 2.0 * k * (rho - r) * s / rho - 1.0 if rho > 0 else -1.0

    s0 = np.sqrt(max(r**2 - h**2, 0.0))  # the drop where ρ = r: the slope is -1 there
    if s_max <= s0 or slope(s_max) <= 0.0:
        return lmin, dv - s_max
    return lmin, dv - float(brentq(slope, s0, s_max, xtol=1e-12))


def activity_space_waypoint(
    art_center: ArrayLike,
    art_width: float,
    art_facing: float,
    viewer_position: ArrayLike,
    robot_position: ArrayLike,
    goal_position: ArrayLike,
    *,
    clearance: float = 1.2,
    max_clearance: float = 4.0,
    margin: float = 0.4,
    shoulder: float = 0.3,
) -> SocialGoal:
    """A waypoint behind the viewer that keeps the artwork's activity space free.

    The waypoint is ``viewer − ρ·u`` with ``u`` the unit viewer→art direction and ``ρ`` the
    smallest value in ``[clearance, max_clearance]`` (0.1 m steps; default 1.2 m = Hall's
    personal-space boundary) for which both legs robot→waypoint and waypoint→goal stay at least
    ``margin`` (m) from the activity-space polygon. Its yaw points from the waypoint to the goal.
    Fallback ``no_clear_path`` when no ``ρ`` works (``max_clearance`` is returned).
    ``geometry['direct_crosses']`` tells whether the straight robot→goal segment came within
    ``margin`` of the activity space.
    """
    c, width, facing, v = _art_inputs(art_center, art_width, art_facing, viewer_position)
    start = _point(robot_position, "robot_position")
    goal = _point(goal_position, "goal_position")
    assert start is not None and goal is not None
    n, _ = art_frame(facing)
    poly = activity_space_polygon(c, width, facing, v, shoulder)
    look = c - v
    u = look / np.linalg.norm(look) if np.linalg.norm(look) > COINCIDENT_TOL else -n
    fallback: str | None = None
    reason: str | None = None
    rhos = np.arange(clearance, max_clearance + 1e-9, 0.1)
    if rhos.size == 0:
        rhos = np.array([clearance])
    chosen = None
    for rho in rhos:
        w = v - rho * u
        legs = min(
            segment_polygon_distance(start, w, poly), segment_polygon_distance(w, goal, poly)
        )
        if legs >= margin:
            chosen = (w, float(rho))
            break
    if chosen is None:
        chosen = (v - rhos[-1] * u, float(rhos[-1]))
        fallback, reason = "no_clear_path", "no waypoint behind the viewer keeps the space free"
    w, rho = chosen
    geometry = {
        "activity_space": poly,
        "behind_distance": rho,
        "direct_crosses": bool(segment_polygon_distance(start, goal, poly) < margin),
        "legs": np.stack([start, w, goal]),
    }
    return SocialGoal(
        _pose(w, _face(w, goal)),
        "waypoint",
        position_tolerance=WAYPOINT_TOLERANCE,
        yaw_tolerance=float(np.pi),
        is_waypoint=True,
        geometry=geometry,
        fallback=fallback,
        reason=reason,
    )

"""Derived time series and small geometry shared by the metrics (pure functions of a record).

Shapes: ``T`` samples, ``K`` people, ``V`` footprint vertices. Everything is vectorized over
time (and people); nothing here loops over samples in Python.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import (
    FloatArray,
    signed_distance_to_polygon,
    world_to_body_frames,
)


def person_distances(record: EpisodeRecord) -> FloatArray:
    """Centre-to-centre robot–person distances ``(T, K)`` in metres; ``+inf`` where a person is
    absent (``record.people_present``)."""
    d = np.linalg.norm(record.people_positions - record.robot_xy[:, None, :], axis=-1)
    return np.where(record.people_present, d, np.inf)


def footprint_gaps(record: EpisodeRecord) -> FloatArray:
    """Body-to-body gaps ``(T, K)`` (m): ``sd(h_{k,t}, footprint_t) - r_k`` with ``sd`` the signed
    distance from the person's centre to the robot's convex footprint (negative inside);
    negative on contact, ``+inf`` where a person is absent."""
    present = record.people_present
    body = world_to_body_frames(
        np.where(present[..., None], record.people_positions, 0.0), record.robot_poses
    )
    sd = signed_distance_to_polygon(body, convex_footprint(record))
    return np.where(present, sd - record.people_radii[None, :], np.inf)


def closest_distance(record: EpisodeRecord) -> FloatArray:
    """Distance to the closest person at each sample ``(T,)`` (``+inf`` with no people)."""
    d = person_distances(record)
    if d.shape[1] == 0:
        return np.full(record.num_steps, np.inf)
    return d.min(axis=1)


def closest_person(record: EpisodeRecord) -> int | None:
    """Index of the person who came closest to the robot over the episode (None if K == 0)."""
    d = person_distances(record)
    if d.shape[1] == 0:
        return None
    return int(np.argmin(d.min(axis=0)))


def goal_reached_index(record: EpisodeRecord, tolerance: float | None = None) -> int | None:
    """First sample from which the robot stays within ``tolerance`` of ``record.target`` (xy)
    until the end of the record; None when the last sample is outside.

    ``tolerance`` defaults to ``record.goal_tolerance`` (m).
    """
    tol = record.goal_tolerance if tolerance is None else tolerance
    inside = np.linalg.norm(record.robot_xy - record.target[:2], axis=1) <= tol
    if not inside[-1]:
        return None
    outside = np.flatnonzero(~inside)
    return 0 if outside.size == 0 else int(outside[-1] + 1)


def reached_within_limit(record: EpisodeRecord, tolerance: float | None = None) -> bool:
    """The goal is reached (and held, see :func:`goal_reached_index`) no later than
    ``record.time_limit`` after the first sample."""
    k = goal_reached_index(record, tolerance)
    return k is not None and bool(record.times[k] - record.times[0] <= record.time_limit + 1e-9)


def step_lengths(record: EpisodeRecord) -> FloatArray:
    """``|p_{t+1} - p_t|`` for each of the ``T - 1`` steps (m)."""
    return np.linalg.norm(np.diff(record.robot_xy, axis=0), axis=1)


def robot_velocity(record: EpisodeRecord) -> FloatArray:
    """World robot velocity ``(T, 2)`` from forward differences of position (m/s): the velocity
    executed over ``[t, t + dt]``; the last sample repeats the previous one (zero if T == 1)."""
    if record.num_steps < 2:
        return np.zeros((record.num_steps, 2))
    v = np.diff(record.robot_xy, axis=0) / record.dt
    return np.vstack([v, v[-1:]])


def line_frame(record: EpisodeRecord) -> tuple[FloatArray, FloatArray, FloatArray] | None:
    """Origin, unit direction ``u`` and left normal ``n`` of the start→goal line, or None when
    start and goal coincide. Uses ``record.start`` and the given ``record.goal``."""
    origin = np.asarray(record.start[:2], dtype=float)
    delta = np.asarray(record.goal[:2], dtype=float) - origin
    length = float(np.hypot(*delta))
    if length < 1e-9:
        return None
    u = delta / length
    return origin, u, np.array([-u[1], u[0]])


def convex_footprint(record: EpisodeRecord) -> FloatArray:
    """The footprint's convex hull ``(V, 2)``, counter-clockwise, body frame. The overlap tests
    below need convex shapes; for a non-convex footprint the hull is the conservative choice."""
    fp = np.asarray(record.robot_footprint, dtype=float)
    hull = ConvexHull(fp)
    return fp[hull.vertices]


def footprint_world(record: EpisodeRecord) -> FloatArray:
    """Convex footprint at every recorded pose, world frame ``(T, V, 2)``."""
    fp = convex_footprint(record)
    yaw = record.robot_poses[:, 2]
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    x = record.robot_poses[:, 0, None] + c * fp[None, :, 0] - s * fp[None, :, 1]
    y = record.robot_poses[:, 1, None] + s * fp[None, :, 0] + c * fp[None, :, 1]
    return np.stack([x, y], axis=-1)


def footprint_disc_depth(record: EpisodeRecord, center: FloatArray, radius: float) -> FloatArray:
    """Penetration depth ``(T,)`` (m, 0 when apart) of the disc ``(center, radius)`` into the
    footprint: ``max(0, radius - sd(center, footprint))`` with ``sd`` the signed distance
    (negative inside) — the minimum translation separating the two shapes."""
    c_body = world_to_body_frames(
        np.broadcast_to(center, (record.num_steps, 2)), record.robot_poses
    )
    sd = signed_distance_to_polygon(c_body, convex_footprint(record))
    return np.maximum(radius - sd, 0.0)


def convex_overlap_depth(a: FloatArray, b: FloatArray) -> FloatArray:
    """Separating-axis penetration depth between convex polygons ``a (..., V, 2)`` and
    ``b (..., W, 2)`` (broadcast over leading axes): the minimum translation distance (m) that
    separates them, 0 when they are apart or only touch. Vertex order may be CW or CCW."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    lead = np.broadcast_shapes(a.shape[:-2], b.shape[:-2])
    a = np.broadcast_to(a, (*lead, *a.shape[-2:]))
    b = np.broadcast_to(b, (*lead, *b.shape[-2:]))
    edges = np.concatenate([np.roll(a, -1, axis=-2) - a, np.roll(b, -1, axis=-2) - b], axis=-2)
    normals = np.stack([-edges[..., 1], edges[..., 0]], axis=-1)
    norms = np.linalg.norm(normals, axis=-1, keepdims=True)
    normals = normals / np.where(norms > 0, norms, 1.0)
    # (..., axes, vertices) projections.
    pa = normals @ np.swapaxes(a, -1, -2)
    pb = normals @ np.swapaxes(b, -1, -2)
    push = np.minimum(pa.max(-1) - pb.min(-1), pb.max(-1) - pa.min(-1))
    # Degenerate (zero-length) edges give a zero axis whose projections all vanish: ignore them.
    push = np.where(norms[..., 0] > 0, push, np.inf)
    return np.maximum(push.min(axis=-1), 0.0)


def person_index(record: EpisodeRecord, person_ids: tuple[int, ...]) -> NDArray[np.intp]:
    """Column indices of ``person_ids`` in the record's people arrays (missing ids dropped)."""
    ids = [int(i) for i in np.asarray(record.people_ids).tolist()]
    lookup = {pid: k for k, pid in enumerate(ids)}
    return np.array([lookup[p] for p in person_ids if p in lookup], dtype=np.intp)


def person_headings(record: EpisodeRecord, min_speed: float = 0.05) -> FloatArray:
    """Heading of each person ``(T, K)`` (rad): the direction of their velocity when moving faster
    than ``min_speed`` (m/s), else their yaw in ``record.context`` (0 when unknown)."""
    vel = record.people_velocities
    speed = np.linalg.norm(vel, axis=-1)
    yaw0 = np.zeros(vel.shape[1])
    known = {p.id: p.yaw for p in record.context.people}
    for k, pid in enumerate(np.asarray(record.people_ids).tolist()):
        yaw0[k] = known.get(int(pid), 0.0)
    moving = np.arctan2(vel[..., 1], vel[..., 0])
    return np.where(speed > min_speed, moving, yaw0[None, :])

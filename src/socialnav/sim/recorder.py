"""Per-step recording and exact collision checks against the robot's polygon footprint.

navground models every agent as a disc and, by default, pushes overlapping discs apart. With a
rectangular footprint that would both invent contacts (disc corners) and hide real ones (the
push-apart keeps discs from ever overlapping). The simulator therefore runs navground with
``ignore_collisions = True`` (kinematic motion, nobody is pushed) and measures collisions here,
geometrically: footprint polygon vs person discs, and footprint polygon vs wall segments,
obstacle polygons and obstacle discs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import (
    FloatArray,
    body_to_world,
    point_segment_distance,
    points_in_polygon,
    polygon_edges,
    signed_distance_to_polygon,
)
from socialnav.core.scene import SocialContext


def _cross(o: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    return (a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1]) - (a[..., 1] - o[..., 1]) * (
        b[..., 0] - o[..., 0]
    )


def segments_intersect(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray) -> bool:
    """Whether any segment ``a (E, 2)`` touches any segment ``b (S, 2)`` (closed segments)."""
    if len(a0) == 0 or len(b0) == 0:
        return False
    p, p2 = a0[:, None], a1[:, None]
    q, q2 = b0[None], b1[None]
    d1, d2 = _cross(q, q2, p), _cross(q, q2, p2)
    d3, d4 = _cross(p, p2, q), _cross(p, p2, q2)
    proper = (d1 * d2 < 0) & (d3 * d4 < 0)
    if proper.any():
        return True
    # Touching / collinear cases: an end point lies on the other segment.
    touch = (
        (point_segment_distance(a0, b0, b1) <= 1e-12).any()
        or (point_segment_distance(a1, b0, b1) <= 1e-12).any()
        or (point_segment_distance(b0, a0, a1) <= 1e-12).any()
        or (point_segment_distance(b1, a0, a1) <= 1e-12).any()
    )
    return bool(touch)


@dataclass(frozen=True)
class StaticGeometry:
    """Walls ``(S, 2, 2)``, obstacle polygons ``[(V, 2)]`` and obstacle discs ``(D, 3)``."""

    walls: FloatArray
    polygons: tuple[FloatArray, ...]
    discs: FloatArray
    _seg_a: FloatArray = field(init=False, repr=False)
    _seg_b: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        starts = [self.walls[:, 0]] + [polygon_edges(p)[0] for p in self.polygons]
        ends = [self.walls[:, 1]] + [polygon_edges(p)[1] for p in self.polygons]
        object.__setattr__(self, "_seg_a", np.concatenate(starts).reshape(-1, 2))
        object.__setattr__(self, "_seg_b", np.concatenate(ends).reshape(-1, 2))

    def collides(
        self, footprint_world: FloatArray, center: FloatArray | None = None, radius: float = np.inf
    ) -> bool:
        """Whether the world-frame footprint polygon ``(V, 2)`` touches any static obstacle.

        ``center``/``radius``: a disc containing the footprint, for a cheap early "no".
        """
        if center is not None and np.isfinite(radius):
            near = (
                len(self._seg_a)
                and point_segment_distance(center, self._seg_a, self._seg_b).min() <= radius
            )
            inside = any(points_in_polygon(center, p) for p in self.polygons)
            disc_near = (
                len(self.discs)
                and (np.hypot(*(self.discs[:, :2] - center).T) <= radius + self.discs[:, 2]).any()
            )
            if not (near or inside or disc_near):
                return False
        fa, fb = polygon_edges(footprint_world)
        if segments_intersect(fa, fb, self._seg_a, self._seg_b):
            return True
        for poly in self.polygons:  # full containment either way (no edge crossing)
            if points_in_polygon(footprint_world[:1], poly).any():
                return True
            if points_in_polygon(poly[:1], footprint_world).any():
                return True
        if len(self.discs):
            sd = signed_distance_to_polygon(self.discs[:, :2], footprint_world)
            if (sd < self.discs[:, 2]).any():
                return True
        return False


def person_collisions(
    footprint_world: FloatArray, positions: FloatArray, radii: FloatArray
) -> bool:
    """Whether the footprint ``(V, 2)`` overlaps any person disc (``positions (K, 2)``)."""
    if len(positions) == 0:
        return False
    sd = signed_distance_to_polygon(positions, footprint_world)
    return bool((sd < radii).any())


class EpisodeRecorder:
    """Accumulates samples, then builds an :class:`EpisodeRecord`."""

    def __init__(
        self,
        footprint: FloatArray,
        people_ids: np.ndarray,
        people_radii: FloatArray,
        static: StaticGeometry,
    ) -> None:
        self.footprint = np.asarray(footprint, dtype=float)
        self.radius = float(np.linalg.norm(self.footprint, axis=1).max())
        self.people_ids = np.asarray(people_ids)
        self.people_radii = np.asarray(people_radii, dtype=float)
        self.static = static
        self.times: list[float] = []
        self.poses: list[FloatArray] = []
        self.twists: list[FloatArray] = []
        self.people_pos: list[FloatArray] = []
        self.people_vel: list[FloatArray] = []
        self.people_yaw: list[FloatArray] = []
        self.hit_person: list[bool] = []
        self.hit_obstacle: list[bool] = []
        self.status: list[str] = []

    def add(
        self,
        time: float,
        pose: FloatArray,
        cmd: FloatArray,
        people_pos: FloatArray,
        people_vel: FloatArray,
        status: str,
        people_yaw: FloatArray | None = None,
    ) -> None:
        """One sample: the state at ``time`` and the body command applied after it; people's
        yaws ``(K,)`` are the simulator's orientations (None: derived from their motion)."""
        fp = body_to_world(self.footprint, pose)
        self.times.append(time)
        self.poses.append(np.asarray(pose, dtype=float))
        self.twists.append(np.asarray(cmd, dtype=float))
        self.people_pos.append(np.asarray(people_pos, dtype=float).reshape(-1, 2))
        self.people_vel.append(np.asarray(people_vel, dtype=float).reshape(-1, 2))
        if people_yaw is not None:
            self.people_yaw.append(np.asarray(people_yaw, dtype=float).reshape(-1))
        center = np.asarray(pose[:2], dtype=float)
        gap = np.hypot(*(self.people_pos[-1] - center).T) - self.people_radii - self.radius
        near = self.people_pos[-1][gap <= 0.0]  # only people within reach of the footprint
        self.hit_person.append(person_collisions(fp, near, self.people_radii[gap <= 0.0]))
        self.hit_obstacle.append(self.static.collides(fp, center, self.radius))
        self.status.append(str(status))

    def build(self, **task: Any) -> EpisodeRecord:
        k, t = len(self.people_ids), len(self.times)
        yaws = None
        if len(self.people_yaw) == t:
            yaws = np.asarray(self.people_yaw, dtype=float).reshape(t, k)
        return EpisodeRecord(
            times=np.asarray(self.times, dtype=float),
            robot_poses=np.asarray(self.poses, dtype=float).reshape(-1, 3),
            robot_twists=np.asarray(self.twists, dtype=float).reshape(-1, 3),
            robot_footprint=self.footprint,
            people_ids=self.people_ids,
            people_positions=np.asarray(self.people_pos, dtype=float).reshape(t, k, 2),
            people_velocities=np.asarray(self.people_vel, dtype=float).reshape(t, k, 2),
            people_radii=self.people_radii,
            collision_person=np.asarray(self.hit_person, dtype=bool),
            collision_obstacle=np.asarray(self.hit_obstacle, dtype=bool),
            status=np.asarray(self.status, dtype=object),
            people_headings=yaws,
            walls=self.static.walls,
            obstacles=self.static.polygons,
            **task,
        )


def context_at(
    base: SocialContext, positions: FloatArray, velocities: FloatArray, yaws: FloatArray
) -> SocialContext:
    """``base`` with its people moved to ``positions (K, 2)``/``velocities (K, 2)``/``yaws (K,)``
    (same order as ``base.people``)."""
    from socialnav.core.scene import Person

    people = tuple(
        Person(p.id, (float(x[0]), float(x[1])), (float(v[0]), float(v[1])), float(y), p.radius)
        for p, x, v, y in zip(base.people, positions, velocities, yaws, strict=True)
    )
    return base.with_people(people)

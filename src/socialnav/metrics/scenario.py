"""Scenario-specific metrics for the families of scenarios.md (queue, group, gallery).

The social geometry comes from ``socialnav.social.spaces`` (queue bands, o-space disc,
activity-space trapezoid) built from the record's ``context`` (which people form a queue, a
group, view an artwork) and the people's positions at the *first* sample (these people stand;
a line that moves is measured against where it stood when the episode began).

Conventions:
- Queue band and activity space: the robot's footprint polygon (convex hull of
  ``record.robot_footprint`` at each recorded pose) against the polygon; the depth is the
  separating-axis minimum translation distance.
- O-space: two variants. ``_center`` measures the robot centre against the disc of radius
  R - 0.3 (what the success condition uses: a robot standing *on* the group circle, as a member
  does, keeps its centre out of the disc, whereas a 0.65 m PR2 footprint at radius R already
  reaches 0.325 m inwards); ``_footprint`` measures the footprint against the same disc.
- Spot errors use ``record.target`` (the social goal) and the final sample; they are NaN unless
  the record's family is the one the spot belongs to.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.metrics.base import metric
from socialnav.metrics.series import (
    convex_overlap_depth,
    footprint_disc_depth,
    footprint_world,
    person_index,
)
from socialnav.social.plausibility import plausible_context
from socialnav.social.spaces import activity_space_polygon, o_space, queue_band_polygons

NAN = float("nan")


# --- geometry read from the record ---------------------------------------------------------


def queue_members(record: EpisodeRecord) -> list[FloatArray]:
    """Member positions ``(M, 2)`` (head → tail) at the first sample, one array per queue."""
    start = record.people_positions[0]
    lines = [start[person_index(record, q.member_ids)] for q in record.context.queues]
    return [m for m in lines if m.shape[0] > 0]


def queue_bands(record: EpisodeRecord) -> list[FloatArray]:
    """Every band ``(4, 2)`` between consecutive members of every queue."""
    return [band for members in queue_members(record) for band in queue_band_polygons(members)]


def ospaces(record: EpisodeRecord) -> list[tuple[FloatArray, float]]:
    """``(center (2,), o-space radius R - 0.3)`` of every group at the first sample, but those
    that fail the sanity limits (:func:`~socialnav.social.plausibility.plausible_context`: the
    planner plans around their members as people, and there is no o-space to keep out of)."""
    start = record.people_positions[0]
    discs = []
    for group in plausible_context(record.context).groups:
        members = start[person_index(record, group.member_ids)]
        if members.shape[0] > 0:
            discs.append(o_space(members))
    return discs


def activity_spaces(record: EpisodeRecord) -> list[FloatArray]:
    """Activity-space trapezoid ``(4, 2)`` of every (artwork, viewer) pair at the first sample."""
    start = record.people_positions[0]
    polys = []
    for art in record.context.artworks:
        for viewer in start[person_index(record, art.viewer_ids)]:
            polys.append(activity_space_polygon(art.center, art.width, art.facing, viewer))
    return polys


def viewer_positions(record: EpisodeRecord) -> FloatArray:
    """Positions ``(V, 2)`` of every artwork viewer at the *last* sample."""
    ids = tuple(i for art in record.context.artworks for i in art.viewer_ids)
    return record.people_positions[-1][person_index(record, ids)]


def _onsets(flags: np.ndarray) -> int:
    return int(flags[0]) + int(np.count_nonzero(flags[1:] & ~flags[:-1])) if flags.size else 0


def _polygons_depth(record: EpisodeRecord, polygons: list[FloatArray]) -> FloatArray:
    """Deepest footprint penetration into any of ``polygons`` at each sample ``(T,)``."""
    if not polygons:
        return np.zeros(record.num_steps)
    footprint = footprint_world(record)[:, None]  # (T, 1, V, 2)
    if len({p.shape for p in polygons}) == 1:  # the usual case: all (4, 2), one batched call
        return convex_overlap_depth(footprint, np.stack(polygons)[None]).max(axis=1)
    return np.max([convex_overlap_depth(footprint[:, 0], p[None]) for p in polygons], axis=0)


def ospace_depth_center(record: EpisodeRecord) -> FloatArray | None:
    """Depth (m) of the robot centre inside any o-space disc at each sample ``(T,)``:
    ``max_g (r_g - |p - c_g|)^+``; None without groups."""
    discs = ospaces(record)
    if not discs:
        return None
    d = [np.maximum(r - np.linalg.norm(record.robot_xy - c, axis=1), 0.0) for c, r in discs]
    return np.max(d, axis=0)


def ospace_depth_footprint(record: EpisodeRecord) -> FloatArray | None:
    """Depth (m) of any o-space disc into the robot footprint at each sample ``(T,)``; None
    without groups."""
    discs = ospaces(record)
    if not discs:
        return None
    return np.max([footprint_disc_depth(record, c, r) for c, r in discs], axis=0)


def activity_depth(record: EpisodeRecord) -> FloatArray | None:
    """Footprint penetration (m) into any activity space at each sample ``(T,)``; None without
    viewers."""
    polys = activity_spaces(record)
    return _polygons_depth(record, polys) if polys else None


def cut_in_depth(record: EpisodeRecord) -> FloatArray | None:
    """Footprint penetration (m) into any queue band at each sample ``(T,)``; None without a
    queue of at least two members."""
    bands = queue_bands(record)
    return _polygons_depth(record, bands) if bands else None


def final_spot_error(record: EpisodeRecord) -> float:
    """|p_T - target|: distance (m) from the final robot position to ``record.target``."""
    return float(np.linalg.norm(record.robot_xy[-1] - record.target[:2]))


def facing_error(record: EpisodeRecord, point: FloatArray) -> float:
    """|wrap(θ_T - atan2(point - p_T))|: how far (rad) the final heading is from facing
    ``point``."""
    d = np.asarray(point, dtype=float) - record.robot_xy[-1]
    return abs(float(wrap_angle(record.robot_poses[-1, 2] - np.arctan2(d[1], d[0]))))


def _nearest_to_target(points: list[FloatArray], record: EpisodeRecord) -> FloatArray:
    return min(points, key=lambda p: float(np.linalg.norm(p - record.target[:2])))


def queue_heading_error_value(record: EpisodeRecord) -> float:
    """Final heading error (rad) to the last member (first-sample position) of the queue whose
    tail is nearest the target: facing the person ahead = facing along the line toward its
    head. NaN without a queue."""
    members = queue_members(record)
    if not members:
        return NAN
    return facing_error(record, _nearest_to_target([m[-1] for m in members], record))


def group_heading_error_value(record: EpisodeRecord) -> float:
    """Final heading error (rad) to the centre of the group nearest the target; NaN without
    groups."""
    discs = ospaces(record)
    if not discs:
        return NAN
    return facing_error(record, _nearest_to_target([c for c, _ in discs], record))


# --- metrics ---------------------------------------------------------------------------------


def _time(record: EpisodeRecord, depth: FloatArray | None) -> float:
    return NAN if depth is None else float(np.count_nonzero(depth > 0.0) * record.dt)


def _max(depth: FloatArray | None) -> float:
    return NAN if depth is None else float(depth.max())


@metric("queue_cut_in", unit="1", direction="min")
def queue_cut_in(record: EpisodeRecord) -> float:
    """Number of entries (onsets; a record starting inside counts one) of the robot footprint
    into any band between consecutive queue members (``social.spaces.queue_band_polygons``,
    width 2 × human radius). NaN without a queue of >= 2 members."""
    depth = cut_in_depth(record)
    return NAN if depth is None else float(_onsets(depth > 0.0))


@metric("queue_cut_in_time", unit="s", direction="min")
def queue_cut_in_time(record: EpisodeRecord) -> float:
    """dt × number of samples with the robot footprint inside any queue band. NaN without a
    queue of >= 2 members."""
    return _time(record, cut_in_depth(record))


@metric("queue_slot_error", unit="m", direction="min")
def queue_slot_error(record: EpisodeRecord) -> float:
    """|p_T - target| with target = the tail slot (family ``queue`` only, else NaN)."""
    return final_spot_error(record) if record.family == "queue" else NAN


@metric("queue_heading_error", unit="rad", direction="min")
def queue_heading_error(record: EpisodeRecord) -> float:
    """|wrap(θ_T - bearing to the last queue member)| at the final sample: 0 when the robot
    faces the person ahead of it in line. NaN without a queue."""
    return queue_heading_error_value(record)


@metric("ospace_intrusion_time_center", unit="s", direction="min")
def ospace_intrusion_time_center(record: EpisodeRecord) -> float:
    """dt × number of samples with the robot centre inside an o-space disc (radius R - 0.3
    around the fitted group circle). NaN without groups."""
    return _time(record, ospace_depth_center(record))


@metric("ospace_intrusion_depth_center", unit="m", direction="min")
def ospace_intrusion_depth_center(record: EpisodeRecord) -> float:
    """max_t (r - |p_t - c|)^+ over o-space discs (c, r = R - 0.3). NaN without groups."""
    return _max(ospace_depth_center(record))


@metric("ospace_intrusion_time_footprint", unit="s", direction="min")
def ospace_intrusion_time_footprint(record: EpisodeRecord) -> float:
    """dt × number of samples with the robot footprint overlapping an o-space disc. NaN without
    groups."""
    return _time(record, ospace_depth_footprint(record))


@metric("ospace_intrusion_depth_footprint", unit="m", direction="min")
def ospace_intrusion_depth_footprint(record: EpisodeRecord) -> float:
    """max_t (r - sd(c, footprint_t))^+, sd = signed distance of the disc centre to the footprint
    (negative inside): how far the o-space disc reaches into the robot. NaN without groups."""
    return _max(ospace_depth_footprint(record))


@metric("join_spot_error", unit="m", direction="min")
def join_spot_error(record: EpisodeRecord) -> float:
    """|p_T - target| with target = the free spot on the group circle (family ``group`` only,
    else NaN)."""
    return final_spot_error(record) if record.family == "group" else NAN


@metric("join_heading_error", unit="rad", direction="min")
def join_heading_error(record: EpisodeRecord) -> float:
    """|wrap(θ_T - bearing to the group centre)| at the final sample. NaN without groups."""
    return group_heading_error_value(record)


@metric("activity_space_time", unit="s", direction="min")
def activity_space_time(record: EpisodeRecord) -> float:
    """dt × number of samples with the robot footprint overlapping any activity-space trapezoid
    (viewer's shoulders ±0.3 m to the artwork's ends). NaN without artwork viewers."""
    return _time(record, activity_depth(record))


@metric("activity_space_depth", unit="m", direction="min")
def activity_space_depth(record: EpisodeRecord) -> float:
    """max_t of the footprint's penetration depth (separating-axis minimum translation) into any
    activity space. NaN without artwork viewers."""
    return _max(activity_depth(record))


@metric("presenter_spot_error", unit="m", direction="min")
def presenter_spot_error(record: EpisodeRecord) -> float:
    """|p_T - target| with target = the presenter spot (family ``gallery_present`` only, else
    NaN)."""
    return final_spot_error(record) if record.family == "gallery_present" else NAN


@metric("viewer_distance_final", unit="m", direction="min")
def viewer_distance_final(record: EpisodeRecord) -> float:
    """min_v |p_T - h_v(T)| over artwork viewers, centre-to-centre (the presenter should end
    0.9–1.6 m from the viewer; "min" = closer is better only inside that band). NaN without
    viewers."""
    viewers = viewer_positions(record)
    if viewers.shape[0] == 0:
        return NAN
    return float(np.linalg.norm(viewers - record.robot_xy[-1], axis=1).min())


@metric("presenter_heading_error", unit="rad", direction="min")
def presenter_heading_error(record: EpisodeRecord) -> float:
    """|wrap(θ_T - bearing to the nearest viewer)| at the final sample (the presenter faces the
    viewer). NaN without viewers."""
    viewers = viewer_positions(record)
    if viewers.shape[0] == 0:
        return NAN
    nearest = viewers[np.argmin(np.linalg.norm(viewers - record.robot_xy[-1], axis=1))]
    return facing_error(record, nearest)


@metric("waypoint_min_distance", unit="m", direction="min")
def waypoint_min_distance(record: EpisodeRecord) -> float:
    """min_t |p_t - waypoint| for the social waypoint (gallery activity). NaN without one."""
    if record.waypoint is None:
        return NAN
    wp = np.asarray(record.waypoint, dtype=float)[:2]
    return float(np.linalg.norm(record.robot_xy - wp, axis=1).min())

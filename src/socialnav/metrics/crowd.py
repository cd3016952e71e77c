"""Crowd-navigation metrics in the conventions of SocNavBench (Biswas et al. 2022) and Francis
et al., "Principles and Guidelines for Evaluating Social Robot Navigation Algorithms" (2023).

Contacts are judged on the robot's footprint: the body-to-body gap (``series.footprint_gaps``)
below zero. A *contact event* is a maximal run of consecutive samples in contact with one person.
It is **active** when the robot was moving toward that person — at some sample of the event,
either the step into it or the step out of it brings the robot's footprint closer to the
person's centre (held where they are at that sample) faster than :data:`APPROACH_SPEED` — and
**passive** otherwise (the robot stopped, or moving away while someone walks into it). The
footprint, not the robot's centre, is what approaches: a robot turning on the spot sweeps its
corners into a person beside it although its centre does not move, and a robot sliding its
flank past a person does not close on them although its centre's velocity may point their way
(recorded crowds, dev seeds 0–89: 46 of paccet's 206 contact events judged passive on the
centre's velocity are active on the footprint's, most of them turning at 0.5–1 rad/s).

People appear in a recording mid-episode, sometimes beside or inside the robot's footprint
(ETH/UCY annotate people from where the camera first sees them). A robot cannot be at rest
sooner than its braking time after it first sees someone, so the steps it takes within that
time are not judged against them (*passive safety* with respect to what is seen: Macek et al.
2009, Bouraine et al. 2012): the step into a person's first sample, and the steps out of the
next ``n`` samples, ``n = ceil(max_axis |v| / acc_lim / dt)`` with ``v`` the robot's body twist
over the step into the appearance (from the poses; axes ``x``, ``y``, ``theta``) and the
acceleration limits of the robot model named by ``meta["robot"]`` (:func:`braking_steps`). With
no known robot model, or for someone present from the episode's first sample, ``n = 0``: only
the step into the appearance is unjudged. Steps after that window are judged as any other, so a
robot that keeps driving into someone it has had time to stop for is active.
Success on a crowd episode requires no active contact; passive contacts are reported beside it
(see ``metrics.success``, family ``crowd``).

Time near people uses the same body-to-body gap: Hall's intimate (0.45 m) and personal (1.2 m)
distances, counted as ``dt`` per sample where the gap to the closest present person is below
them (SocNavBench counts time inside personal space the same way).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import signed_distance_to_polygon, world_to_body_frames, wrap_angle
from socialnav.core.robot import ROBOT_MODELS
from socialnav.core.success import CONDITIONS, ConditionCheck
from socialnav.metrics.base import MetricFn, metric
from socialnav.metrics.series import convex_footprint, footprint_gaps
from socialnav.social.proxemics import INTIMATE, PERSONAL

#: speed (m/s) at which the robot's footprint closes on a person, above which it approaches them
APPROACH_SPEED = 0.05
FRANCIS = "Francis et al. 2023; SocNavBench (Biswas et al. 2022)"


def contact_events(record: EpisodeRecord) -> list[tuple[int, int, int, bool]]:
    """Contact events ``(person index, first sample, last sample, active)`` in time order."""
    if record.people_ids.shape[0] == 0 or record.num_steps == 0:
        return []
    contact = footprint_gaps(record) < 0.0  # (T, K); absent people are +inf, never in contact
    if not contact.any():
        return []
    poses = record.robot_poses
    before = np.vstack([poses[:1], poses[:-1]])  # the pose the step into sample t left
    after = np.vstack([poses[1:], poses[-1:]])  # the pose the step out of sample t reaches
    fp = convex_footprint(record)
    present = record.people_present  # (T, K)
    was_present = np.vstack([np.zeros((1, present.shape[1]), dtype=bool), present[:-1]])
    events = []
    for k in np.flatnonzero(contact.any(axis=0)):
        # The person held at sample t's position: only the robot's own motion (translation and
        # turning) changes the footprint's signed distance to them.
        at = np.where(present[:, k, None], record.people_positions[:, k], 0.0)[:, None]
        sd = [
            signed_distance_to_polygon(world_to_body_frames(at, q)[:, 0], fp)
            for q in (before, poses, after)
        ]
        # the step into a sample counts only if the person was there before it
        into_k = np.where(was_present[:, k], (sd[0] - sd[1]) / record.dt, -np.inf)
        out_k = (sd[1] - sd[2]) / record.dt
        # nor the steps the robot takes braking after someone appears (module docstring)
        for a in np.flatnonzero(present[:, k] & ~was_present[:, k]):
            n = braking_steps(record, int(a))
            into_k[a : a + n + 1] = -np.inf
            out_k[a : a + n] = -np.inf
        approach = np.maximum(into_k, out_k)
        for first, last in _runs(contact[:, k]):
            active = bool(np.nanmax(approach[first : last + 1]) > APPROACH_SPEED)
            events.append((int(k), first, last, active))
    events.sort(key=lambda e: e[1])
    return events


def braking_steps(record: EpisodeRecord, sample: int) -> int:
    """The number of samples ``n`` after ``sample`` within which the robot cannot be at rest:
    ``ceil(max_axis |v| / acc_lim / dt)``, with ``v`` its body twist ``(vx, vy, wz)`` (m/s,
    rad/s) over the step into ``sample`` (from ``record.robot_poses``) and ``acc_lim`` the
    ``acc_lim_x, acc_lim_y, acc_lim_theta`` of the robot model named by ``meta["robot"]``
    (``socialnav.core.robot.ROBOT_MODELS``); an axis with a zero limit, or a non-finite twist,
    does not count, and none counts faster than the model's ``max_vel_*`` (a jump in the poses,
    e.g. a relocalization, is not speed to brake from). 0 at the first sample or when the model
    is unknown."""
    model = ROBOT_MODELS.get(str(record.meta.get("robot", "")))
    if model is None or sample <= 0 or sample >= record.num_steps:
        return 0
    (x0, y0, yaw0), (x1, y1, yaw1) = record.robot_poses[sample - 1], record.robot_poses[sample]
    c, s = math.cos(yaw0), math.sin(yaw0)
    dx, dy = (x1 - x0) / record.dt, (y1 - y0) / record.dt
    twist = (c * dx + s * dy, -s * dx + c * dy, float(wrap_angle(yaw1 - yaw0)) / record.dt)
    limits = (model.acc_lim_x, model.acc_lim_y, model.acc_lim_theta)
    # no axis faster than the model allows: a jump in the poses is not speed to brake from
    top = (max(model.max_vel_x, abs(model.min_vel_x)), model.max_vel_y, model.max_vel_theta)
    seconds = max(
        (
            min(abs(v), vmax) / lim
            for v, vmax, lim in zip(twist, top, limits, strict=True)
            if lim > 0 and math.isfinite(v)
        ),
        default=0.0,
    )
    return math.ceil(seconds / record.dt - 1e-9)


def _runs(mask: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """``(first, last)`` index pairs of the runs of True in a 1-D mask."""
    padded = np.concatenate([[False], mask, [False]]).astype(np.int8)
    edges = np.diff(padded)
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1, strict=True))


@metric("collisions_active", unit="1", direction="min", reference=FRANCIS)
def collisions_active(record: EpisodeRecord) -> float:
    """Number of active contact events: footprint contact with a person while the robot moves
    toward them (its footprint closing on the person's centre at > 0.05 m/s), not counting the
    steps it takes braking after the person appears (:func:`braking_steps`)."""
    return float(sum(1 for *_, active in contact_events(record) if active))


@metric("collisions_passive", unit="1", direction="min", reference=FRANCIS)
def collisions_passive(record: EpisodeRecord) -> float:
    """Number of passive contact events: footprint contact with a person while the robot is
    stopped or moving away (the person walked into it)."""
    return float(sum(1 for *_, active in contact_events(record) if not active))


def _time_within(threshold: float) -> MetricFn:
    def time_within(record: EpisodeRecord) -> float:
        if record.people_ids.shape[0] == 0:
            return 0.0
        gap = footprint_gaps(record).min(axis=1)
        return float(np.count_nonzero(gap < threshold) * record.dt)

    time_within.__doc__ = (
        f"dt × number of samples where the body-to-body gap (footprint to the person's disc) to "
        f"the closest present person is below {threshold} m; 0 without people."
    )
    return time_within


metric("time_within_0.45", unit="s", direction="min", reference=FRANCIS)(_time_within(INTIMATE))
metric("time_within_1.2", unit="s", direction="min", reference=FRANCIS)(_time_within(PERSONAL))


def _no_active(record: EpisodeRecord, tolerance: float) -> bool:
    return not any(active for *_, active in contact_events(record))


def _no_passive(record: EpisodeRecord, tolerance: float) -> bool:
    return not any(not active for *_, active in contact_events(record))


def _no_obstacle(record: EpisodeRecord, tolerance: float) -> bool:
    return not bool(np.any(record.collision_obstacle))


for _name, _check in {
    "no_active_collision": ConditionCheck(
        _no_active, description="no contact with a person while moving toward them"
    ),
    "no_passive_contact": ConditionCheck(
        _no_passive, description="nobody walked into the stopped or retreating robot"
    ),
    "no_obstacle_collision": ConditionCheck(_no_obstacle, description="no contact with walls"),
}.items():
    if _name not in CONDITIONS:
        CONDITIONS.add(_name, _check)

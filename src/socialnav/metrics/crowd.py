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
(ETH/UCY annotate people from where the camera first sees them), and a robot cannot be at rest
sooner than its braking time after it sees someone (*passive safety* with respect to what is
seen: Macek et al. 2009, Bouraine et al. 2012). So the step into a person's first sample is not
judged, and each time a person appears (again: a track that was absent), the next
:func:`braking_steps` steps are not judged either *if the robot brakes at its acceleration
limits in them* (:func:`braking_after`: on every axis no faster than braking from its twist at
the appearance allows). A robot that keeps its speed, speeds up, or is still moving after its
braking time has those steps judged as any other. The limits are those of the robot model
``meta["robot"]`` names, else the record's ``meta["acc_lim"]`` and ``meta["max_vel"]`` (the
simulator writes them for any robot; :func:`robot_limits`); with neither, with a period that is
not a positive number, and for someone present from the episode's first sample, only the step
into the appearance is unjudged.

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
from socialnav.core.geometry import (
    FloatArray,
    signed_distance_to_polygon,
    world_to_body_frames,
    wrap_angle,
)
from socialnav.core.robot import ROBOT_MODELS
from socialnav.core.success import CONDITIONS, ConditionCheck
from socialnav.metrics.base import MetricFn, metric
from socialnav.metrics.series import convex_footprint, footprint_gaps
from socialnav.social.proxemics import INTIMATE, PERSONAL

#: speed (m/s) at which the robot's footprint closes on a person, above which it approaches them
APPROACH_SPEED = 0.05
#: a step counts as braking at the limits with up to this fraction of one period's velocity
#: change to spare (the simulator's integration and float rounding)
BRAKING_SLACK = 0.05
#: a twist from the poses faster than ``JUMP_FACTOR × max_vel + JUMP_MARGIN`` (m/s, rad/s) on
#: some axis is a jump of the poses (a relocalization), not a speed to brake from
JUMP_FACTOR = 1.5
JUMP_MARGIN = 0.05
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
        # nor the steps the robot brakes at its limits after someone appears (module docstring)
        for a in np.flatnonzero(present[:, k] & ~was_present[:, k]):
            for step in braking_after(record, int(a)):
                out_k[step] = -np.inf
                into_k[step + 1] = -np.inf
        approach = np.maximum(into_k, out_k)
        for first, last in _runs(contact[:, k]):
            active = bool(np.nanmax(approach[first : last + 1]) > APPROACH_SPEED)
            events.append((int(k), first, last, active))
    events.sort(key=lambda e: e[1])
    return events


def robot_limits(record: EpisodeRecord) -> tuple[FloatArray, FloatArray] | None:
    """``(acc_lim (3,), max_vel (3,))`` of the robot, axes ``x, y, theta`` (m/s², rad/s²; m/s,
    rad/s; ``max_vel[0]`` the larger of ``|max_vel_x|`` and ``|min_vel_x|``): those of the
    model ``meta["robot"]`` names in ``socialnav.core.robot.ROBOT_MODELS`` (any case), else
    ``meta["acc_lim"]`` and ``meta["max_vel"]`` (the simulator writes them for any robot) when
    they are three finite non-negative numbers each; None otherwise. A known model wins, so a
    record cannot claim weaker brakes than its robot has."""
    model = ROBOT_MODELS.get(str(record.meta.get("robot", "")).lower())
    if model is not None:
        limits = model.kinematic_limits()
        return np.array(limits["acc_lim"]), np.array(limits["max_vel"])
    try:
        acc = np.asarray(record.meta.get("acc_lim"), dtype=float).reshape(3)
        top = np.asarray(record.meta.get("max_vel"), dtype=float).reshape(3)
    except (TypeError, ValueError, OverflowError):
        return None
    pair = np.concatenate([acc, top])
    if not (np.all(np.isfinite(pair)) and np.all(pair >= 0.0)):
        return None
    return acc, top


def _step_twist(record: EpisodeRecord, step: int) -> FloatArray:
    """The robot's body twist ``(vx, vy, wz)`` (m/s, rad/s) over the step from sample ``step``
    to ``step + 1``, from its poses: the displacement in the frame of the heading halfway
    through the step (the chord of a constant-twist arc points there; in the starting frame a
    robot turning at 1 rad/s would show a sideways speed it does not have)."""
    (x0, y0, yaw0), (x1, y1, yaw1) = record.robot_poses[step], record.robot_poses[step + 1]
    turn = float(wrap_angle(yaw1 - yaw0))
    mid = yaw0 + 0.5 * turn
    c, s = math.cos(mid), math.sin(mid)
    dx, dy = (x1 - x0) / record.dt, (y1 - y0) / record.dt
    return np.array([c * dx + s * dy, -s * dx + c * dy, turn / record.dt])


def _braking(record: EpisodeRecord, sample: int) -> tuple[int, FloatArray, FloatArray]:
    """``(n, acc_lim (3,), v_in (3,))`` of :func:`braking_steps` and :func:`braking_after`
    (``n`` 0 where there is nothing to excuse)."""
    limits = robot_limits(record)
    dt_ok = math.isfinite(record.dt) and record.dt > 0
    if limits is None or not dt_ok or sample <= 0 or sample >= record.num_steps:
        return 0, np.zeros(3), np.zeros(3)
    acc, top = limits
    v_in = _step_twist(record, sample - 1)
    v = np.abs(v_in)
    if not np.all(np.isfinite(v)) or np.any(v > JUMP_FACTOR * top + JUMP_MARGIN):
        return 0, acc, v_in
    seconds = float(np.max(np.where(acc > 0, v / np.where(acc > 0, acc, 1.0), 0.0)))
    return math.ceil(seconds / record.dt - 1e-9), acc, v_in


def braking_steps(record: EpisodeRecord, sample: int) -> int:
    """The number of samples ``n`` after ``sample`` within which the robot cannot be at rest:
    ``ceil(max_axis |v| / acc_lim / dt)``, with ``v`` its body twist ``(vx, vy, wz)`` (m/s,
    rad/s) over the step into ``sample`` (from ``record.robot_poses``) and the limits of
    :func:`robot_limits`; an axis with a zero limit does not count. 0 at the first sample, when
    the limits are unknown, and when ``v`` is no speed: faster than 1.5 × ``max_vel`` + 0.05 on
    an axis, or not finite (a jump in the poses, e.g. a relocalization)."""
    return _braking(record, sample)[0]


def braking_after(record: EpisodeRecord, sample: int) -> list[int]:
    """The steps (index ``s``: from sample ``s`` to ``s + 1``) among the
    :func:`braking_steps` after ``sample`` in which the robot brakes at its limits: on every
    axis, ``|v_s| <= max(|v_in| - acc_lim · (s - sample + 1) · dt, 0)`` and ``v_s`` not of the
    opposite sign to ``v_in`` (each up to ``BRAKING_SLACK`` of one period's change), ``v_in``
    the twist over the step into ``sample``. A robot that keeps its speed, speeds up, reverses
    or turns the other way in that time has those steps judged."""
    n, acc, v_in = _braking(record, sample)
    toward = np.sign(v_in)
    slack = BRAKING_SLACK * acc * record.dt + 1e-9
    steps = []
    for s in range(sample, min(sample + n, record.num_steps - 1)):
        bound = np.maximum(np.abs(v_in) - acc * (s - sample + 1) * record.dt, 0.0)
        v = _step_twist(record, s)
        # slower on every axis, and never the other way: braking stops, it does not reverse
        if np.all(np.abs(v) <= bound + slack) and np.all(v * toward >= -slack):
            steps.append(s)
    return steps


def _runs(mask: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """``(first, last)`` index pairs of the runs of True in a 1-D mask."""
    padded = np.concatenate([[False], mask, [False]]).astype(np.int8)
    edges = np.diff(padded)
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1, strict=True))


@metric("collisions_active", unit="1", direction="min", reference=FRANCIS)
def collisions_active(record: EpisodeRecord) -> float:
    """Number of active contact events: footprint contact with a person while the robot moves
    toward them (its footprint closing on the person's centre at > 0.05 m/s), not counting the
    steps in which it brakes at its limits right after the person appears
    (:func:`braking_after`)."""
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

"""The metrics of Table 1 (hallway passing) of Banisetty et al., "Socially-Aware Navigation: A
Non-linear Multi-Objective Optimization Approach", with the definitions of metrics.md.

Deviations from / gaps in the paper (which defines these in one sentence each):
- The start→goal line is ``record.start`` → ``record.goal`` (the goal the robot was given).
- One person: the one who came closest to the robot (the paper has a single person).
  ``proxemic_intrusions`` instead sums over all people (identical with one person).
- ``time_to_goal`` and ``total_distance`` are NaN when the goal is never reached (and held).
- Crossings (``lateral_distance``, ``deviation_distance``) are interpolated linearly between
  samples; positions are interpolated, then the distance is taken.
- The paper's N is a sum over its 5 runs; these are per-run values (sum them for the table).
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.metrics.base import metric
from socialnav.metrics.series import (
    closest_person,
    goal_reached_index,
    line_frame,
    person_distances,
    step_lengths,
)
from socialnav.social.proxemics import PERSONAL

PAPER = "Banisetty et al., Table 1; metrics.md"
DEVIATION_THRESHOLD = 0.1  # m, lateral offset from the start→goal line (metrics.md)


@metric("total_distance", unit="m", direction="min", reference=PAPER)
def total_distance(record: EpisodeRecord) -> float:
    """D_t = Σ_{t < k*} |p_{t+1} - p_t|, the path length until the goal is reached.

    k* is the first sample from which the robot stays within ``goal_tolerance`` of
    ``record.target`` until the end (see ``time_to_goal``). NaN when never reached.
    """
    k = goal_reached_index(record)
    if k is None:
        return float("nan")
    return float(step_lengths(record)[:k].sum())


@metric("time_to_goal", unit="s", direction="min", reference=PAPER)
def time_to_goal(record: EpisodeRecord) -> float:
    """t = t_{k*} - t_0: the first sample time at which |p - target| <= goal_tolerance holds and
    keeps holding until the end of the record. NaN when the last sample is outside. A final turn
    in place at the goal (``ROTATING_TO_GOAL``) is not counted: the status reaches
    ``GOAL_REACHED`` after it, later than this time."""
    k = goal_reached_index(record)
    if k is None:
        return float("nan")
    return float(record.times[k] - record.times[0])


def _crossing(values: np.ndarray) -> tuple[int, float] | None:
    """First step ``k`` where ``values`` changes sign between samples ``k`` and ``k + 1`` (or
    reaches 0 at ``k + 1`` from non-zero), with the interpolation fraction in ``(0, 1]``.
    A series that starts at exactly 0 does not count as a crossing at ``t_0``."""
    v0, v1 = values[:-1], values[1:]
    hits = np.flatnonzero((v0 != 0) & (np.sign(v0) != np.sign(v1)))
    if hits.size == 0:
        return None
    k = int(hits[0])
    return k, float(values[k] / (values[k] - values[k + 1]))


@metric("lateral_distance", unit="m", direction="max", reference=PAPER)
def lateral_distance(record: EpisodeRecord) -> float:
    """D_l = |(h - p)·n| at the first moment the along-line offset (h - p)·u changes sign.

    u is the unit start→goal direction, n its left normal, p the robot and h the closest person
    (module docstring). The crossing time is interpolated linearly between the two samples
    around the sign change. NaN when they never pass, with no person, or start == goal.
    """
    frame = line_frame(record)
    j = closest_person(record)
    if frame is None or j is None:
        return float("nan")
    _, u, n = frame
    rel = record.people_positions[:, j] - record.robot_xy  # (T, 2)
    crossing = _crossing(rel @ u)
    if crossing is None:
        return float("nan")
    k, alpha = crossing
    at = (1.0 - alpha) * rel[k] + alpha * rel[k + 1]
    return float(abs(at @ n))


@metric("proxemic_intrusions", unit="1", direction="min", reference=PAPER)
def proxemic_intrusions(record: EpisodeRecord) -> float:
    """N = number of transitions of the centre-to-centre distance from >= 1.2 m to < 1.2 m,
    summed over people.

    Convention: a record that *starts* inside someone's personal space counts as one intrusion
    for that person (otherwise a robot parked inside personal space would score 0).
    """
    d = person_distances(record)
    if d.shape[1] == 0:
        return 0.0
    inside = d < PERSONAL
    entries = np.count_nonzero(inside[1:] & ~inside[:-1]) + np.count_nonzero(inside[0])
    return float(entries)


@metric("deviation_distance", unit="m", direction="max", reference=PAPER)
def deviation_distance(record: EpisodeRecord) -> float:
    """D_d = |p(t_d) - h(t_d)|, where t_d is the first time the robot's lateral offset
    |(p - start)·n| from the start→goal line exceeds 0.1 m (interpolated between samples).

    h is the closest person. NaN ("n/a" in the paper) when the offset never exceeds 0.1 m,
    with no person, or start == goal.
    """
    frame = line_frame(record)
    j = closest_person(record)
    if frame is None or j is None:
        return float("nan")
    origin, _, n = frame
    offset = np.abs((record.robot_xy - origin) @ n)
    above = np.flatnonzero(offset > DEVIATION_THRESHOLD)
    if above.size == 0:
        return float("nan")
    k = int(above[0])
    rel = record.people_positions[:, j] - record.robot_xy
    if k == 0:
        return float(np.linalg.norm(rel[0]))
    alpha = (DEVIATION_THRESHOLD - offset[k - 1]) / (offset[k] - offset[k - 1])
    at = (1.0 - alpha) * rel[k - 1] + alpha * rel[k]
    return float(np.linalg.norm(at))

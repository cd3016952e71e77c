"""Seeded robot tasks inside a recorded crowd (the crowd suite's episodes).

A seed selects one episode: ``numpy.random.default_rng(seed)`` draws a start time ``t0`` and a
start/goal pair until every rule holds —

- start and goal :data:`DISTANCE` (8–12 m) apart, both at least :data:`BORDER` (2 m) inside the
  annotated area (so nobody appears on top of the robot: people enter at the border);
- nobody within :data:`CLEARANCE` (1 m, centre to centre) of the start at ``t0``;
- at least :data:`MIN_PEOPLE` (5) people within :data:`NEAR` (6 m) of the start at ``t0``;
- the line along the crowd's main flow (:meth:`Recording.main_flow`, ±:data:`SPREAD`) for even
  seeds, across it for odd seeds where the area allows a line that long across the flow (else
  along it too); the direction along the line (with or against the flow) is drawn.

The robot starts facing the goal and the goal keeps that heading. By convention seeds below
:data:`REPORT_SEED` tune, seeds from it on report.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.crowds.recording import Recording

DISTANCE = (8.0, 12.0)
BORDER = 2.0
CLEARANCE = 1.0
MIN_PEOPLE = 5
NEAR = 6.0
SPREAD = math.radians(20.0)
TIME_LIMIT = 60.0
REPORT_SEED = 10_000
#: start times drawn per seed before giving up; start/goal pairs drawn per start time
MAX_TIMES = 400
PAIRS_PER_TIME = 40


@dataclass(frozen=True)
class CrowdEpisode:
    """One seeded task: ``t0`` (s), ``start``/``goal`` ``(x, y, yaw)`` (m, rad), ``flow``
    (``along`` or ``across``), ``people_near`` (people within :data:`NEAR` of the start at
    ``t0``)."""

    seed: int
    t0: float
    start: tuple[float, float, float]
    goal: tuple[float, float, float]
    flow: str
    people_near: int
    time_limit: float = TIME_LIMIT


def across_allowed(recording: Recording) -> bool:
    """Whether the area, shrunk by BORDER, holds a DISTANCE[0] line across the main flow."""
    return _longest_line(recording, _across(recording.main_flow())) >= DISTANCE[0]


def _across(flow: np.ndarray) -> np.ndarray:
    return np.array([-flow[1], flow[0]])


def _longest_line(recording: Recording, direction: np.ndarray) -> float:
    """Longest chord of the shrunk area along ``direction`` (the box's extent projected)."""
    a = recording.area
    w = max(a.xmax - a.xmin - 2 * BORDER, 0.0)
    h = max(a.ymax - a.ymin - 2 * BORDER, 0.0)
    dx, dy = abs(direction[0]), abs(direction[1])
    chords = [w / dx if dx > 1e-9 else math.inf, h / dy if dy > 1e-9 else math.inf]
    return float(min(chords))


def generate_episode(
    recording: Recording, seed: int, time_limit: float = TIME_LIMIT
) -> CrowdEpisode:
    """The episode of ``seed`` (deterministic). Raises :class:`ConfigurationError` when no
    start time and start/goal pair within the draw budget satisfies the rules."""
    rng = np.random.default_rng(int(seed))
    flow = recording.main_flow()
    kind = "across" if seed % 2 == 1 and across_allowed(recording) else "along"
    axis = flow if kind == "along" else _across(flow)
    area = recording.area
    t_lo = recording.start_time
    t_hi = max(recording.end_time - 0.5 * time_limit, t_lo)
    lo = np.array([area.xmin + BORDER, area.ymin + BORDER])
    hi = np.array([area.xmax - BORDER, area.ymax - BORDER])
    if np.any(hi <= lo):
        raise ConfigurationError(
            f"{recording.name}: the annotated area {area} is too small for a {BORDER} m border"
        )
    # why draws fail, for the error: a recording that never yields an episode says which rule
    misses = {"few_present": 0, "goal_outside": 0, "crowded_start": 0, "few_near": 0}
    for _ in range(MAX_TIMES):
        t0 = float(rng.uniform(t_lo, t_hi))
        state = recording.state_at(t0, recording.active_ids(t0, t0))
        people = state.positions[0][state.present[0]]
        if len(people) < MIN_PEOPLE:
            misses["few_present"] += 1
            continue
        for _ in range(PAIRS_PER_TIME):
            start = rng.uniform(lo, hi)
            angle = math.atan2(axis[1], axis[0]) + rng.uniform(-SPREAD, SPREAD)
            if rng.random() < 0.5:
                angle += math.pi
            length = rng.uniform(*DISTANCE)
            goal = start + length * np.array([math.cos(angle), math.sin(angle)])
            if not area.contains(goal, BORDER):
                misses["goal_outside"] += 1
                continue
            d = np.hypot(*(people - start).T)
            if d.min() < CLEARANCE:
                misses["crowded_start"] += 1
                continue
            near = int(np.count_nonzero(d <= NEAR))
            if near < MIN_PEOPLE:
                misses["few_near"] += 1
                continue
            yaw = float(math.atan2(goal[1] - start[1], goal[0] - start[0]))
            return CrowdEpisode(
                int(seed),
                round(t0, 3),
                (float(start[0]), float(start[1]), yaw),
                (float(goal[0]), float(goal[1]), yaw),
                kind,
                near,
                float(time_limit),
            )
    pairs = max(MAX_TIMES - misses["few_present"], 0) * PAIRS_PER_TIME
    raise ConfigurationError(
        f"{recording.name}: seed {seed}: no episode after {MAX_TIMES} start times: "
        f"{misses['few_present']} had fewer than {MIN_PEOPLE} people present; of their "
        f"{pairs} start/goal draws, {misses['goal_outside']} put the goal ({DISTANCE[0]:g}–"
        f"{DISTANCE[1]:g} m on) outside the area less a {BORDER:g} m border "
        f"({area.xmax - area.xmin:.1f} × {area.ymax - area.ymin:.1f} m), "
        f"{misses['crowded_start']} had someone within {CLEARANCE:g} m of the start and "
        f"{misses['few_near']} fewer than {MIN_PEOPLE} people within {NEAR:g} m of it"
    )

"""Success conditions of the scenario suite (scenarios.md, "Success conditions"), measured from
the recorded trajectory only.

The families are the experiments of Banisetty et al. (section "Results"), which judges them
from figures; these measurable conditions are the project's (scenarios.md).

Every family:
- ``reached_goal``: within tolerance of ``record.target`` (the social goal where the scenario
  has one) from some sample on until the end, reached within ``record.time_limit``. The
  tolerance is ``record.goal_tolerance``; for the families whose target is a social spot
  (``gallery_present``, ``queue``, ``group``) it is ``max(goal_tolerance, 0.3)``, so that a
  robot ending inside the 0.3 m spot radius of scenarios.md counts as arrived whatever the
  planner's own (tighter) goal tolerance was.
- ``no_collision``: no sample flagged in ``collision_person`` or ``collision_obstacle``.

Per family (``record.family``; ``custom`` has only the common conditions):
- ``hallway``: ``no_personal_space_intrusion`` — the centre-to-centre distance to every person
  stays >= 1.2 m. In scenario ``hallway_headon`` it is reported but *not required* (the person
  never yields; the robot can only yield as far as the walls allow).
- ``gallery_present``: ``at_presenter_spot`` (final |p - target| <= 0.3 m) and
  ``outside_activity_space`` (the footprint never overlaps an activity-space trapezoid).
- ``gallery_activity``: ``outside_activity_space`` (zero time inside); reaching the goal is the
  common ``reached_goal``.
- ``queue``: ``at_tail_slot`` (final |p - target| <= 0.3 m), ``facing_line`` (final heading
  within 0.5 rad of the bearing to the last member — scenarios.md gives no tolerance; 0.5 rad
  ≈ 29° is this library's choice) and ``no_cut_in`` (the footprint never enters a band between
  consecutive members).
- ``group``: ``at_free_spot`` (final |p - target| <= 0.3 m), ``facing_centre`` (final heading
  within 0.5 rad of the bearing to the group centre) and ``outside_o_space`` (the robot *centre*
  never inside the disc of radius R - 0.3; see ``metrics.scenario`` for why the centre).

``evaluate_success`` returns every condition (required or not) plus ``"success"`` = all
*required* conditions. A record whose family needs a queue, group or viewed artwork that its
``context`` lacks raises a ValueError.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import InvalidInputError
from socialnav.metrics.base import validate_record
from socialnav.metrics.scenario import (
    activity_depth,
    cut_in_depth,
    final_spot_error,
    group_heading_error_value,
    ospace_depth_center,
    queue_heading_error_value,
)
from socialnav.metrics.series import closest_distance, reached_within_limit
from socialnav.social.proxemics import PERSONAL

FAMILIES = ("hallway", "gallery_present", "gallery_activity", "queue", "group", "custom")
SPOT_TOLERANCE = 0.3  # m, scenarios.md
HEADING_TOLERANCE = 0.5  # rad, this library's choice (scenarios.md: "facing")
PERSONAL_SPACE_OPTIONAL = frozenset({"hallway_headon"})
SPOT_FAMILIES = frozenset({"gallery_present", "queue", "group"})


@dataclass(frozen=True)
class Condition:
    """One success condition: ``name``, whether it ``passed``, whether it counts toward
    ``success`` (``required``)."""

    name: str
    passed: bool
    required: bool = True


def _never(depth: np.ndarray | None, what: str, record: EpisodeRecord) -> bool:
    if depth is None:
        raise InvalidInputError(
            f"{record.family} record {record.scenario!r} has no {what} in its context"
        )
    return bool(np.all(depth <= 0.0))


def success_conditions(record: EpisodeRecord) -> list[Condition]:
    """The conditions of ``record.family`` evaluated on the record (see module docstring)."""
    validate_record(record)
    if record.family not in FAMILIES:
        raise InvalidInputError(f"unknown family {record.family!r}; known: {FAMILIES}")
    collided = bool(np.any(record.collision_person) or np.any(record.collision_obstacle))
    tolerance = record.goal_tolerance
    if record.family in SPOT_FAMILIES:
        tolerance = max(tolerance, SPOT_TOLERANCE)
    out = [
        Condition("reached_goal", reached_within_limit(record, tolerance)),
        Condition("no_collision", not collided),
    ]
    family = record.family
    if family == "hallway":
        ok = bool(np.all(closest_distance(record) >= PERSONAL))
        required = record.scenario not in PERSONAL_SPACE_OPTIONAL
        out.append(Condition("no_personal_space_intrusion", ok, required))
    elif family in ("gallery_present", "gallery_activity"):
        if family == "gallery_present":
            at_spot = final_spot_error(record) <= SPOT_TOLERANCE
            out.append(Condition("at_presenter_spot", at_spot))
        outside = _never(activity_depth(record), "artwork viewer", record)
        out.append(Condition("outside_activity_space", outside))
    elif family == "queue":
        heading = queue_heading_error_value(record)
        if np.isnan(heading):
            raise InvalidInputError(f"queue record {record.scenario!r} has no queue in context")
        out += [
            Condition("at_tail_slot", final_spot_error(record) <= SPOT_TOLERANCE),
            Condition("facing_line", heading <= HEADING_TOLERANCE),
            Condition("no_cut_in", _never(cut_in_depth(record), "queue of >= 2 people", record)),
        ]
    elif family == "group":
        outside = _never(ospace_depth_center(record), "group", record)
        out += [
            Condition("at_free_spot", final_spot_error(record) <= SPOT_TOLERANCE),
            Condition("facing_centre", group_heading_error_value(record) <= HEADING_TOLERANCE),
            Condition("outside_o_space", outside),
        ]
    return out


def evaluate_success(record: EpisodeRecord) -> dict[str, bool]:
    """Condition name → passed, plus ``"success"`` = every required condition passed."""
    conditions = success_conditions(record)
    result = {c.name: c.passed for c in conditions}
    result["success"] = all(c.passed for c in conditions if c.required)
    return result

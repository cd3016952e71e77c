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
- ``gallery_present``: ``at_presenter_spot`` (final |p - target| <= 0.3 m),
  ``facing_viewer`` (final heading within 0.5 rad of the bearing to the nearest viewer:
  scenarios.md's presenter "faces the viewer") and ``outside_activity_space`` (the footprint
  never overlaps an activity-space trapezoid).
- ``gallery_activity``: ``outside_activity_space`` (zero time inside); reaching the goal is the
  common ``reached_goal``.
- ``queue``: ``at_tail_slot`` (final |p - target| <= 0.3 m), ``facing_line`` (final heading
  within 0.5 rad of the bearing to the last member — scenarios.md gives no tolerance; 0.5 rad
  ≈ 29° is this library's choice) and ``no_cut_in`` (the footprint never enters a band between
  consecutive members).
- ``group``: ``at_free_spot`` (final |p - target| <= 0.3 m), ``facing_centre`` (final heading
  within 0.5 rad of the bearing to the group centre) and ``outside_o_space`` (the robot *centre*
  never inside the disc of radius R - 0.3; see ``metrics.scenario`` for why the centre).

- ``mixed`` (a group or a queue plus walkers, generated suite): the conditions of the structure
  the target belongs to (``queue`` when the scene has a queue, else ``group``).
- ``crowdnav`` (Chen et al. 2019's circle crossing): the common conditions only.

Per-scenario options (``record.meta["success_options"]``, a dumped
``socialnav.sim.scenario.SuccessOptions``; the generated suite sets them): ``position_tolerance``
replaces both the arrival tolerance and the spot radius, ``yaw_tolerance`` adds the final yaw
to the arrival test, ``heading_tolerance`` replaces 0.5 rad in the facing conditions, and
``conditions`` / ``per_robot[meta["robot"]]`` mark conditions not required, with the reason
kept on the :class:`Condition`.

``evaluate_success`` returns every condition (required or not) plus ``"success"`` = all
*required* conditions. A record whose family needs a queue, group or viewed artwork that its
``context`` lacks raises a ValueError.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import wrap_angle
from socialnav.metrics.base import validate_record
from socialnav.metrics.scenario import (
    activity_depth,
    cut_in_depth,
    facing_error,
    final_spot_error,
    group_heading_error_value,
    ospace_depth_center,
    queue_heading_error_value,
    viewer_positions,
)
from socialnav.metrics.series import closest_distance, reached_within_limit
from socialnav.social.proxemics import PERSONAL

FAMILIES = (
    "hallway",
    "gallery_present",
    "gallery_activity",
    "queue",
    "group",
    "mixed",
    "crowdnav",
    "custom",
)
SPOT_TOLERANCE = 0.3  # m, scenarios.md
HEADING_TOLERANCE = 0.5  # rad, this library's choice (scenarios.md: "facing")
PERSONAL_SPACE_OPTIONAL = frozenset({"hallway_headon"})
SPOT_FAMILIES = frozenset({"gallery_present", "queue", "group", "mixed"})


@dataclass(frozen=True)
class Condition:
    """One success condition: ``name``, whether it ``passed``, whether it counts toward
    ``success`` (``required``)."""

    name: str
    passed: bool
    required: bool = True
    reason: str = ""


def _never(depth: np.ndarray | None, what: str, record: EpisodeRecord) -> bool:
    if depth is None:
        raise InvalidInputError(
            f"{record.family} record {record.scenario!r} has no {what} in its context"
        )
    return bool(np.all(depth <= 0.0))


def _options(record: EpisodeRecord) -> dict[str, Any]:
    opts = record.meta.get("success_options") or {}
    return opts if isinstance(opts, dict) else {}


def _overrides(opts: dict[str, Any], robot: str) -> dict[str, dict[str, Any]]:
    merged = dict(opts.get("conditions") or {})
    merged.update((opts.get("per_robot") or {}).get(robot, {}))
    return merged


def _arrived(record: EpisodeRecord, tolerance: float, yaw_tolerance: float | None) -> bool:
    if not reached_within_limit(record, tolerance):
        return False
    if yaw_tolerance is None:
        return True
    yaw_error = abs(float(wrap_angle(record.robot_poses[-1, 2] - record.target[2])))
    return yaw_error <= yaw_tolerance


def _viewer_heading_error(record: EpisodeRecord) -> float:
    viewers = viewer_positions(record)
    if viewers.shape[0] == 0:
        raise InvalidInputError(f"gallery record {record.scenario!r} has no viewer in context")
    nearest = viewers[np.argmin(np.linalg.norm(viewers - record.robot_xy[-1], axis=1))]
    return facing_error(record, nearest)


def success_conditions(record: EpisodeRecord) -> list[Condition]:
    """The conditions of ``record.family`` evaluated on the record (see module docstring)."""
    validate_record(record)
    if record.family not in FAMILIES:
        raise InvalidInputError(f"unknown family {record.family!r}; known: {FAMILIES}")
    opts = _options(record)
    collided = bool(np.any(record.collision_person) or np.any(record.collision_obstacle))
    spot = opts.get("position_tolerance") or SPOT_TOLERANCE
    heading_tol = opts.get("heading_tolerance") or HEADING_TOLERANCE
    tolerance = record.goal_tolerance
    if record.family in SPOT_FAMILIES:
        tolerance = max(tolerance, SPOT_TOLERANCE)
    if opts.get("position_tolerance"):
        tolerance = float(opts["position_tolerance"])
    out = [
        Condition("reached_goal", _arrived(record, tolerance, opts.get("yaw_tolerance"))),
        Condition("no_collision", not collided),
    ]
    family = record.family
    if family == "mixed":
        family = "queue" if record.context.queues else "group"
    if family == "hallway":
        ok = bool(np.all(closest_distance(record) >= PERSONAL))
        required = record.scenario not in PERSONAL_SPACE_OPTIONAL
        out.append(Condition("no_personal_space_intrusion", ok, required))
    elif family in ("gallery_present", "gallery_activity"):
        if family == "gallery_present":
            out.append(Condition("at_presenter_spot", final_spot_error(record) <= spot))
            out.append(Condition("facing_viewer", _viewer_heading_error(record) <= heading_tol))
        outside = _never(activity_depth(record), "artwork viewer", record)
        out.append(Condition("outside_activity_space", outside))
    elif family == "queue":
        heading = queue_heading_error_value(record)
        if np.isnan(heading):
            raise InvalidInputError(f"queue record {record.scenario!r} has no queue in context")
        out += [
            Condition("at_tail_slot", final_spot_error(record) <= spot),
            Condition("facing_line", heading <= heading_tol),
            Condition("no_cut_in", _never(cut_in_depth(record), "queue of >= 2 people", record)),
        ]
    elif family == "group":
        outside = _never(ospace_depth_center(record), "group", record)
        out += [
            Condition("at_free_spot", final_spot_error(record) <= spot),
            Condition("facing_centre", group_heading_error_value(record) <= heading_tol),
            Condition("outside_o_space", outside),
        ]
    overrides = _overrides(opts, str(record.meta.get("robot", "")))
    return [
        replace(c, required=bool(o.get("required", True)), reason=str(o.get("reason", "")))
        if (o := overrides.get(c.name)) is not None
        else c
        for c in out
    ]


def evaluate_success(record: EpisodeRecord) -> dict[str, bool]:
    """Condition name → passed, plus ``"success"`` = every required condition passed."""
    conditions = success_conditions(record)
    result = {c.name: c.passed for c in conditions}
    result["success"] = all(c.passed for c in conditions if c.required)
    return result

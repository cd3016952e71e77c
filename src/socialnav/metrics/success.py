"""Success conditions of the scenario suite (scenarios.md, "Success conditions"), measured from
the recorded trajectory only.

The families are the experiments of Banisetty et al. (section "Results"), which judges them
from figures; these measurable conditions are the project's (scenarios.md).

Which conditions apply is data: the record's ``success`` list (its family's declaration in
:data:`socialnav.core.success.FAMILIES`, its social structures' conditions, and the scenario's
``success:`` overrides), or, for a record without one, the declaration of its family and
structures. This module registers the checks of the built-in conditions in
:data:`socialnav.core.success.CONDITIONS`:

- ``reached_goal``: within tolerance of ``record.target`` (the target the controller recorded
  driving to) from some sample on until the end, reached within ``record.time_limit``. The
  tolerance is ``max(record.goal_tolerance, tolerance)`` (m): the families whose target is a
  social spot (``gallery_present``, ``queue``, ``group``) declare 0.3, so that a robot ending
  inside the 0.3 m spot radius of scenarios.md counts as arrived whatever the planner's own
  (tighter) goal tolerance was.
- ``no_collision``: no sample flagged in ``collision_person`` or ``collision_obstacle``.

Per family (``record.family``; ``custom`` has only the common conditions):
- ``hallway``: ``no_personal_space_intrusion`` — the centre-to-centre distance to every person
  stays >= 1.2 m (the tolerance). Scenario ``hallway_headon`` marks it *not required* in its
  YAML (the person never yields; the robot can only yield as far as the walls allow).
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

- ``mixed`` (generated suite): the ``queue`` or ``group`` conditions; ``crowdnav``: the common ones.

At the social spots (``gallery_present``, ``queue``, ``group``) ``arrival_yaw`` compares the
final yaw with the target's; its default tolerance (π rad) accepts any yaw, the generated suite
sets 0.2 rad. Spot tolerances (0.3 m) and heading tolerances (0.5 rad) are the conditions'
defaults; a scenario's ``success:`` overrides them (per robot too), and a condition it marks not
required keeps its reason on the :class:`Condition`.
``evaluate_success`` returns every condition (required or not) plus ``"success"`` = all
*required* conditions. A record whose family needs a queue, group or viewed artwork that its
``context`` lacks raises an ``InvalidInputError``; an unknown family or condition a
``ConfigurationError`` listing the known ones.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import wrap_angle
from socialnav.core.success import (
    CONDITIONS,
    FAMILIES,
    Condition,
    ConditionCheck,
    ConditionSpec,
    judged_family,
)
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
from socialnav.social.structures import structure_conditions

__all__ = ["Condition", "evaluate_success", "success_conditions", "success_spec"]

SPOT_TOLERANCE = 0.3  # m, scenarios.md
HEADING_TOLERANCE = 0.5  # rad, this library's choice (scenarios.md: "facing")


def _never(depth: np.ndarray | None, what: str, record: EpisodeRecord) -> bool:
    if depth is None:
        raise InvalidInputError(
            f"{record.family} record {record.scenario!r} has no {what} in its context"
        )
    return bool(np.all(depth <= 0.0))


def _reached_goal(record: EpisodeRecord, tolerance: float) -> bool:
    return reached_within_limit(record, max(record.goal_tolerance, tolerance))


def _no_collision(record: EpisodeRecord, tolerance: float) -> bool:
    return not bool(np.any(record.collision_person) or np.any(record.collision_obstacle))


def _no_intrusion(record: EpisodeRecord, tolerance: float) -> bool:
    return bool(np.all(closest_distance(record) >= tolerance))


def _at_spot(record: EpisodeRecord, tolerance: float) -> bool:
    return bool(final_spot_error(record) <= tolerance)


def _outside_activity_space(record: EpisodeRecord, tolerance: float) -> bool:
    return _never(activity_depth(record), "artwork viewer", record)


def _facing_line(record: EpisodeRecord, tolerance: float) -> bool:
    heading = queue_heading_error_value(record)
    if np.isnan(heading):
        raise InvalidInputError(f"queue record {record.scenario!r} has no queue in context")
    return bool(heading <= tolerance)


def _no_cut_in(record: EpisodeRecord, tolerance: float) -> bool:
    return _never(cut_in_depth(record), "queue of >= 2 people", record)


def _facing_centre(record: EpisodeRecord, tolerance: float) -> bool:
    return bool(group_heading_error_value(record) <= tolerance)


def _arrival_yaw(record: EpisodeRecord, tolerance: float) -> bool:
    return bool(abs(float(wrap_angle(record.robot_poses[-1, 2] - record.target[2]))) <= tolerance)


def _facing_viewer(record: EpisodeRecord, tolerance: float) -> bool:
    viewers = viewer_positions(record)
    if viewers.shape[0] == 0:
        raise InvalidInputError(f"gallery record {record.scenario!r} has no viewer in context")
    nearest = viewers[np.argmin(np.linalg.norm(viewers - record.robot_xy[-1], axis=1))]
    return bool(facing_error(record, nearest) <= tolerance)


def _outside_o_space(record: EpisodeRecord, tolerance: float) -> bool:
    depth = ospace_depth_center(record)
    if depth is None and record.context.groups:
        return True  # every group fails the sanity limits: no o-space to stay out of
    return _never(depth, "group", record)


_BUILTIN = {
    "reached_goal": ConditionCheck(
        _reached_goal, 0.0, "m", "within max(goal_tolerance, tolerance) of the target, to the end"
    ),
    "no_collision": ConditionCheck(_no_collision, description="no contact with people or walls"),
    "no_personal_space_intrusion": ConditionCheck(
        _no_intrusion, PERSONAL, "m", "centre distance to every person >= tolerance"
    ),
    "at_presenter_spot": ConditionCheck(_at_spot, SPOT_TOLERANCE, "m", "ends at the spot"),
    "at_tail_slot": ConditionCheck(_at_spot, SPOT_TOLERANCE, "m", "ends at the tail slot"),
    "at_free_spot": ConditionCheck(_at_spot, SPOT_TOLERANCE, "m", "ends at the free spot"),
    "outside_activity_space": ConditionCheck(
        _outside_activity_space, description="footprint never in an activity space"
    ),
    "facing_line": ConditionCheck(
        _facing_line, HEADING_TOLERANCE, "rad", "ends facing the last queue member"
    ),
    "no_cut_in": ConditionCheck(_no_cut_in, description="never between consecutive members"),
    "facing_centre": ConditionCheck(
        _facing_centre, HEADING_TOLERANCE, "rad", "ends facing the group centre"
    ),
    "arrival_yaw": ConditionCheck(
        _arrival_yaw, float(np.pi), "rad", "final yaw within tolerance of the target's"
    ),
    "facing_viewer": ConditionCheck(
        _facing_viewer, HEADING_TOLERANCE, "rad", "ends facing the nearest viewer"
    ),
    "outside_o_space": ConditionCheck(
        _outside_o_space, description="centre never inside the o-space (R - 0.3 m)"
    ),
}
for _name, _check in _BUILTIN.items():
    if _name not in CONDITIONS:
        CONDITIONS.add(_name, _check)


def success_spec(record: EpisodeRecord) -> tuple[ConditionSpec, ...]:
    """The conditions ``record`` is judged on: its own ``success`` list, else its family's
    declaration followed by its social structures' conditions."""
    if record.success:
        return record.success
    family = judged_family(record.family, bool(record.context.queues))
    return FAMILIES.get(family).conditions + structure_conditions(record.context.structures)


def success_conditions(record: EpisodeRecord) -> list[Condition]:
    """Every condition of :func:`success_spec` evaluated on the record (see module docstring)."""
    validate_record(record)
    return [CONDITIONS.get(spec.name).evaluate(record, spec) for spec in success_spec(record)]


def evaluate_success(record: EpisodeRecord) -> dict[str, bool]:
    """Condition name → passed, plus ``"success"`` = every required condition passed."""
    conditions = success_conditions(record)
    result = {c.name: c.passed for c in conditions}
    result["success"] = all(c.passed for c in conditions if c.required)
    return result

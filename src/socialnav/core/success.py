"""Success conditions and scenario families: what an episode must achieve, as data.

A *condition* is a named check of a recorded episode (``reached_goal``, ``no_cut_in``, …) with a
default tolerance in its own unit; its check function is registered in :data:`CONDITIONS` by the
module that measures it (``socialnav.metrics.success`` for the built-in ones, a social-structure
module for its own). A *family* (:data:`FAMILIES`) declares the conditions its scenarios must
meet. A scenario may override, per condition, whether it is required and its tolerance
(``success:`` in the scenario YAML); the resolved list is stored on the episode record
(:attr:`~socialnav.core.episode.EpisodeRecord.success`), so a record says how it is judged.

The families and conditions are the project's measurable reading of Banisetty et al., section
"Results" (which judges the experiments from figures); see ``scenarios.md``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from socialnav.core.errors import ConfigurationError
from socialnav.core.registry import Registry

if TYPE_CHECKING:
    from socialnav.core.episode import EpisodeRecord

__all__ = [
    "CONDITIONS",
    "FAMILIES",
    "Condition",
    "ConditionCheck",
    "ConditionOverride",
    "ConditionSpec",
    "FamilySpec",
    "apply_overrides",
    "judged_family",
    "register_family",
]


@dataclass(frozen=True)
class ConditionSpec:
    """One condition an episode is judged on: its ``name`` (a :data:`CONDITIONS` key), whether
    it counts toward success (``required``) and its ``tolerance`` (the condition's unit; ``None``
    = the condition's default); ``reason``: why it is not required (shown in reports)."""

    name: str
    required: bool = True
    tolerance: float | None = None
    reason: str = ""


@dataclass(frozen=True)
class ConditionOverride:
    """A scenario's change to one condition: ``required``, ``tolerance`` and/or the ``reason``
    it is not required (None = keep)."""

    required: bool | None = None
    tolerance: float | None = None
    reason: str | None = None


@dataclass(frozen=True)
class Condition:
    """One evaluated condition: ``name``, whether it ``passed``, whether it is ``required`` (and
    if not, the ``reason``)."""

    name: str
    passed: bool
    required: bool = True
    reason: str = ""


def not_required_text(conditions: Iterable[ConditionSpec | Condition]) -> str:
    """The conditions of ``conditions`` that are not required, as ``"name: reason; …"`` (a
    name alone where there is no reason; ``""`` if every condition is required): the
    ``not_required`` of a suite row and of ``metrics.json``."""
    return "; ".join(
        f"{c.name}: {c.reason}" if c.reason else c.name for c in conditions if not c.required
    )


#: ``check(record, tolerance) -> passed``; the tolerance is never None when called.
CheckFn = Callable[["EpisodeRecord", float], bool]


@dataclass(frozen=True)
class ConditionCheck:
    """How a condition is measured: ``check(record, tolerance)``, its ``default_tolerance`` in
    ``unit`` (``""`` for conditions without a tolerance) and a one-line ``description``."""

    check: CheckFn
    default_tolerance: float = 0.0
    unit: str = ""
    description: str = ""

    def evaluate(self, record: EpisodeRecord, spec: ConditionSpec) -> Condition:
        """The condition ``spec`` evaluated on ``record``."""
        tolerance = self.default_tolerance if spec.tolerance is None else spec.tolerance
        passed = bool(self.check(record, float(tolerance)))
        return Condition(spec.name, passed, spec.required, spec.reason)


#: condition name → :class:`ConditionCheck`
CONDITIONS: Registry[ConditionCheck] = Registry("success condition")


@dataclass(frozen=True)
class FamilySpec:
    """A scenario family: ``description`` and the ``conditions`` its scenarios are judged on
    (besides those of their social structures)."""

    description: str
    conditions: tuple[ConditionSpec, ...]


#: family name → :class:`FamilySpec`
FAMILIES: Registry[FamilySpec] = Registry("scenario family")


def register_family(name: str, description: str, conditions: Iterable[ConditionSpec]) -> None:
    """Declare family ``name`` (raises ``ConfigurationError`` when the name is taken)."""
    FAMILIES.add(name, FamilySpec(description, tuple(conditions)))


def apply_overrides(
    specs: Iterable[ConditionSpec], overrides: Mapping[str, ConditionOverride], where: str = ""
) -> tuple[ConditionSpec, ...]:
    """``specs`` with a scenario's ``overrides`` applied, in order.

    Raises ``ConfigurationError`` (naming ``where``, e.g. the scenario file) when an override
    names a condition that does not apply, with the ones that do.
    """
    specs = tuple(specs)
    names = [s.name for s in specs]
    unknown = sorted(set(overrides) - set(names))
    if unknown:
        prefix = f"{where}: " if where else ""
        raise ConfigurationError(
            f"{prefix}success: {', '.join(unknown)} is not a condition of this scenario; "
            f"its conditions: {', '.join(names)}"
        )
    out = []
    for spec in specs:
        o = overrides.get(spec.name)
        if o is not None:
            spec = replace(
                spec,
                required=spec.required if o.required is None else o.required,
                tolerance=spec.tolerance if o.tolerance is None else o.tolerance,
                reason=spec.reason if o.reason is None else o.reason,
            )
        out.append(spec)
    return tuple(out)


def judged_family(family: str, has_queue: bool) -> str:
    """The family whose conditions judge a scene: ``family`` itself, except that a ``mixed``
    scene (a group or a queue plus walkers) is judged as ``queue`` when it has a queue, else as
    ``group``."""
    if family == "mixed":
        return "queue" if has_queue else "group"
    return family


COMMON = (ConditionSpec("reached_goal"), ConditionSpec("no_collision"))
#: the paper's social spots count as reached within 0.3 m (scenarios.md) whatever the planner's
#: own goal tolerance
SPOT = 0.3
#: at a social spot the final yaw is judged too; its default tolerance (π rad) accepts any yaw,
#: so only a scenario that sets a tolerance (the generated suite: 0.2 rad) asks for it
ARRIVAL_YAW = ConditionSpec("arrival_yaw")

register_family(
    "hallway",
    "a corridor with people standing or walking (Table 1)",
    (*COMMON, ConditionSpec("no_personal_space_intrusion")),
)
register_family(
    "gallery_present",
    "present an artwork to its viewer",
    (
        ConditionSpec("reached_goal", tolerance=SPOT),
        ConditionSpec("no_collision"),
        ConditionSpec("at_presenter_spot"),
        ARRIVAL_YAW,
        ConditionSpec("facing_viewer"),
        ConditionSpec("outside_activity_space"),
    ),
)
register_family(
    "gallery_activity",
    "pass people viewing an artwork without crossing their activity space",
    (*COMMON, ConditionSpec("outside_activity_space")),
)
register_family(
    "queue",
    "join the tail of a queue",
    (
        ConditionSpec("reached_goal", tolerance=SPOT),
        ConditionSpec("no_collision"),
        ConditionSpec("at_tail_slot"),
        ARRIVAL_YAW,
        ConditionSpec("facing_line"),
        ConditionSpec("no_cut_in"),
    ),
)
register_family(
    "group",
    "join (or lead) a conversational group",
    (
        ConditionSpec("reached_goal", tolerance=SPOT),
        ConditionSpec("no_collision"),
        ConditionSpec("at_free_spot"),
        ARRIVAL_YAW,
        ConditionSpec("facing_centre"),
        ConditionSpec("outside_o_space"),
    ),
)
register_family("custom", "no family-specific conditions", COMMON)
# The generated suite's families (socialnav.sim.generate). A ``mixed`` scene is judged like the
# structure its target belongs to: ``Scenario.success_spec`` takes the ``queue`` family's
# conditions when the scene has a queue, else the ``group`` family's.
register_family(
    "mixed",
    "join a group or a queue while walkers cross the room (judged as queue or group)",
    FAMILIES.get("group").conditions,
)
register_family(
    "crowdnav",
    "CrowdNav's circle crossing (Chen et al. 2019): reach the antipode through the crowd",
    COMMON,
)
# Replayed recorded crowds (socialnav.metrics.crowd): people never yield, so success asks for no
# *active* contact; passive contacts (someone walked into the robot) are reported, not required.
register_family(
    "crowd",
    "a task among replayed recorded pedestrians (SocNavBench / Francis et al. conventions)",
    (
        ConditionSpec("reached_goal"),
        ConditionSpec("no_obstacle_collision"),
        ConditionSpec("no_active_collision"),
        ConditionSpec("no_passive_contact", required=False),
    ),
)

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
    "register_family",
]


@dataclass(frozen=True)
class ConditionSpec:
    """One condition an episode is judged on: its ``name`` (a :data:`CONDITIONS` key), whether
    it counts toward success (``required``) and its ``tolerance`` (the condition's unit; ``None``
    = the condition's default)."""

    name: str
    required: bool = True
    tolerance: float | None = None


@dataclass(frozen=True)
class ConditionOverride:
    """A scenario's change to one condition: ``required`` and/or ``tolerance`` (None = keep)."""

    required: bool | None = None
    tolerance: float | None = None


@dataclass(frozen=True)
class Condition:
    """One evaluated condition: ``name``, whether it ``passed``, whether it is ``required``."""

    name: str
    passed: bool
    required: bool = True


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
        return Condition(spec.name, bool(self.check(record, float(tolerance))), spec.required)


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
            )
        out.append(spec)
    return tuple(out)


COMMON = (ConditionSpec("reached_goal"), ConditionSpec("no_collision"))
#: the paper's social spots count as reached within 0.3 m (scenarios.md) whatever the planner's
#: own goal tolerance
SPOT = 0.3

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
        ConditionSpec("facing_centre"),
        ConditionSpec("outside_o_space"),
    ),
)
register_family("custom", "no family-specific conditions", COMMON)
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

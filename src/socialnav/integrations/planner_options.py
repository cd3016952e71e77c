"""Our planners and their options, read from the controller registry for the integrations.

"Our planners" are the registered controllers that are not navground behaviours (those are
navground's own; a navground or Gymnasium user already has them). An *option* of a planner is a
keyword of its factory with a scalar type (``bool``, ``int``, ``float``, ``str``); a keyword typed
as a dataclass (``params: LocalPlannerParams | Mapping | None``) contributes each of the
dataclass's scalar fields, passed back to the factory as a mapping of the fields that were set.
Options are found by introspection, so a new field of :class:`LocalPlannerParams` or a new
registered controller appears in the navground behaviour without touching this module.
"""

from __future__ import annotations

import dataclasses
import inspect
import types
import typing
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from socialnav.core.errors import ConfigurationError
from socialnav.sim.controller import CONTROLLERS, ControllerFactory, controller_names

__all__ = ["PlannerOption", "build_planner", "our_planners", "planner_options"]

SCALARS = (bool, int, float, str)


@dataclass(frozen=True)
class PlannerOption:
    """One option: ``name``, scalar ``type``, ``default``; ``group`` is the factory keyword of
    the dataclass it belongs to (``None`` for a plain keyword); ``planners`` that take it."""

    name: str
    type: type
    default: Any
    group: str | None
    planners: tuple[str, ...]

    @property
    def description(self) -> str:
        where = f"{self.group}.{self.name}" if self.group else self.name
        return f"{where} (used by: {', '.join(self.planners)})"


def _register_all() -> None:
    # Importing these modules registers the presets and the baselines in CONTROLLERS.
    import socialnav.sim.baselines
    import socialnav.sim.stack  # noqa: F401


def our_planners() -> list[str]:
    """Names of every registered controller of ours (not ``kind="navground"``), in the
    registry's display order."""
    _register_all()
    return [n for n in controller_names() if CONTROLLERS.get(n).kind != "navground"]


def _scalar(annotation: Any) -> type | None:
    return annotation if annotation in SCALARS else None


def _dataclass_of(annotation: Any) -> type | None:
    """The dataclass in ``X``, ``X | None`` or ``X | Mapping[...] | None``."""
    candidates = (
        typing.get_args(annotation)
        if isinstance(annotation, types.UnionType) or typing.get_origin(annotation) is typing.Union
        else (annotation,)
    )
    for c in candidates:
        if isinstance(c, type) and dataclasses.is_dataclass(c):
            return c
    return None


def _factory_options(factory: ControllerFactory) -> list[tuple[str, type, Any, str | None]]:
    target = factory.func if hasattr(factory, "func") else factory  # functools.partial
    init = target.__init__ if isinstance(target, type) else target  # type: ignore[misc]
    hints = typing.get_type_hints(init)
    # keywords a registry entry binds (``partial(GoToGoalController, gain=...)``) define that
    # entry, like its required arguments: they are not options a user sets
    bound = set(getattr(factory, "keywords", {}) or {})
    out: list[tuple[str, type, Any, str | None]] = []
    for name, param in inspect.signature(factory).parameters.items():
        if param.default is inspect.Parameter.empty or name == "record" or name in bound:
            continue  # required arguments are bound by the registry; record is for the runner
        annotation = hints.get(name)
        cls = _dataclass_of(annotation)
        if cls is not None:
            field_hints = typing.get_type_hints(cls)
            defaults = cls()
            for f in dataclasses.fields(cls):
                ftype = _scalar(field_hints.get(f.name))
                if ftype is not None and f.init:
                    out.append((f.name, ftype, getattr(defaults, f.name), name))
            continue
        ftype = _scalar(annotation)
        if ftype is not None:
            out.append((name, ftype, param.default, None))
    return out


def planner_options(planners: list[str] | None = None) -> dict[str, PlannerOption]:
    """Every option of ``planners`` (default: :func:`our_planners`), by name.

    Raises :class:`ConfigurationError` when two planners give one option name different types,
    defaults or groups (a navground property has one type and one default).
    """
    found: dict[str, PlannerOption] = {}
    for planner in our_planners() if planners is None else planners:
        for name, ftype, default, group in _factory_options(CONTROLLERS.get(planner).factory):
            old = found.get(name)
            if old is None:
                found[name] = PlannerOption(name, ftype, default, group, (planner,))
                continue
            if (old.type, old.default, old.group) != (ftype, default, group):
                raise ConfigurationError(
                    f"option {name!r}: planner {planner!r} declares it as {ftype.__name__} = "
                    f"{default!r} ({group}), planner(s) {', '.join(old.planners)} as "
                    f"{old.type.__name__} = {old.default!r} ({old.group})"
                )
            found[name] = dataclasses.replace(old, planners=(*old.planners, planner))
    return dict(sorted(found.items()))


def build_planner(planner: str, values: Mapping[str, Any]) -> Any:
    """The controller ``planner`` built with those of ``values`` (option name → value) it takes.

    Values are cast to the option's type; options of other planners are ignored. Raises
    :class:`ConfigurationError` for an unknown planner or an invalid value (naming the option).
    """
    if planner not in our_planners():
        raise ConfigurationError(CONTROLLERS.unknown_message(planner))
    factory = CONTROLLERS.get(planner).factory
    kwargs: dict[str, Any] = {}
    for name, ftype, _default, group in _factory_options(factory):
        if name not in values:
            continue
        value = ftype(values[name])
        if group is None:
            kwargs[name] = value
        else:
            kwargs.setdefault(group, {})[name] = value
    try:
        return factory(**kwargs)
    except (TypeError, ValueError) as exc:
        raise ConfigurationError(f"planner {planner!r}: {exc}") from exc

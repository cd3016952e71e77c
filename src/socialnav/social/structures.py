"""The registry of social-structure kinds: each kind is one module.

A kind (people waiting at a door, a photographer and subject, …) subclasses
:class:`StructureKind` and is registered in :data:`STRUCTURES` under its YAML ``type``. It brings

- ``params``: its parameter model (a frozen pydantic model); the scenario YAML schema of
  ``structures:`` entries is built from it, and scenario files are validated against it;
- :meth:`StructureKind.member_ids`: the people it involves (they must exist in the scenario);
- :meth:`StructureKind.social_goal`: the pose a robot whose given goal is "about" this
  structure should drive to (a :class:`~socialnav.social.goals.SocialGoal`), with the distance
  of its anchor to the given goal, or ``None`` when the structure does not apply;
- ``conditions``: the success conditions it adds to every episode that contains it (their
  checks registered in :data:`socialnav.core.success.CONDITIONS` by the module);
- :meth:`StructureKind.draw`: how the top-down figure draws it (matplotlib ``Axes``).

The paper's three structures (groups, queues, artworks) predate this registry and remain typed
fields of :class:`~socialnav.core.scene.SocialContext`; a structure of a registered kind is a
:class:`~socialnav.core.scene.Structure` in ``SocialContext.structures``. The planner, the
social-goal resolution (:func:`~socialnav.social.resolve.resolve_social_goal`), the success
check, the storage and the figures consult this registry, so a new kind touches no other file.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any, ClassVar

import numpy as np
from pydantic import BaseModel, ValidationError

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.registry import Registry
from socialnav.core.scene import SocialContext, Structure
from socialnav.core.success import ConditionSpec
from socialnav.social.goals import SocialGoal

__all__ = [
    "STRUCTURES",
    "StructureKind",
    "make_structure",
    "structure_conditions",
    "structure_social_goals",
]


class StructureKind:
    """Base class of a social-structure kind (see the module docstring).

    Subclasses set ``name``, ``description``, ``params`` (a pydantic model) and ``conditions``,
    and override :meth:`member_ids`, :meth:`social_goal` and :meth:`draw` as they need.
    """

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    params: ClassVar[type[BaseModel]]
    conditions: ClassVar[tuple[ConditionSpec, ...]] = ()

    def member_ids(self, params: Any) -> tuple[int, ...]:
        """The ids of the people the structure involves (default: ``params.members``)."""
        return tuple(int(i) for i in getattr(params, "members", ()))

    def social_goal(
        self,
        params: Any,
        social: SocialContext,
        given_goal: FloatArray,
        robot_pose: FloatArray,
    ) -> tuple[float, SocialGoal] | None:
        """``(anchor distance to the given goal (m), social goal)`` when the given goal
        ``(3,)`` is about this structure, seen from ``robot_pose (3,)``; ``None`` otherwise.
        Never raises on a well-formed context."""
        return None

    def draw(self, ax: Any, params: Any, social: SocialContext) -> None:
        """Draw the structure on a matplotlib ``Axes`` in world coordinates (m)."""
        return None


#: YAML ``type`` → :class:`StructureKind` instance
STRUCTURES: Registry[StructureKind] = Registry("social structure")


def make_structure(data: Mapping[str, Any], where: str = "structures") -> Structure:
    """Validate one ``structures:`` entry ``{type: KIND, ...params}`` into a
    :class:`~socialnav.core.scene.Structure`.

    Raises ``ConfigurationError`` naming ``where`` and the field for an unknown ``type`` (with
    the known ones) or invalid parameters."""
    fields = dict(data)
    kind_name = fields.pop("type", None)
    if not isinstance(kind_name, str):
        raise ConfigurationError(f"{where}.type: required, one of {', '.join(STRUCTURES)}")
    try:
        kind = STRUCTURES.get(kind_name)
    except ConfigurationError as exc:
        raise ConfigurationError(f"{where}.type: {exc}") from None
    try:
        params = kind.params.model_validate(fields)
    except ValidationError as exc:
        first = exc.errors()[0]
        loc = ".".join(str(p) for p in first["loc"])
        raise ConfigurationError(f"{where}.{loc}: {first['msg']}") from None
    return Structure(kind_name, params, kind.member_ids(params))


def structure_to_dict(structure: Structure) -> dict[str, Any]:
    """The YAML/JSON form ``{type: KIND, ...params}`` of a structure (inverse of
    :func:`make_structure`)."""
    return {"type": structure.kind, **structure.params.model_dump(mode="json")}


def structure_conditions(structures: Iterable[Structure]) -> tuple[ConditionSpec, ...]:
    """The success conditions the ``structures`` add, each once, in order."""
    out: list[ConditionSpec] = []
    for s in structures:
        for spec in STRUCTURES.get(s.kind).conditions:
            if all(spec.name != o.name for o in out):
                out.append(spec)
    return tuple(out)


def structure_social_goals(
    social: SocialContext, given_goal: FloatArray, robot_pose: FloatArray
) -> list[tuple[float, SocialGoal]]:
    """Every registered structure's social goal for ``given_goal (3,)`` from ``robot_pose
    (3,)``, as ``(anchor distance (m), goal)``."""
    out = []
    for s in social.structures:
        found = STRUCTURES.get(s.kind).social_goal(
            s.params, social, np.asarray(given_goal, dtype=float), robot_pose
        )
        if found is not None:
            out.append(found)
    return out


def structure_json_schemas() -> list[dict[str, Any]]:
    """JSON Schemas of every registered kind's ``structures:`` entry (``type`` + params)."""
    schemas = []
    for name in STRUCTURES:
        kind = STRUCTURES.get(name)
        schema = kind.params.model_json_schema()
        schema.setdefault("properties", {})["type"] = {"const": name}
        schema["required"] = ["type", *schema.get("required", [])]
        schema["description"] = kind.description
        schemas.append(schema)
    return schemas

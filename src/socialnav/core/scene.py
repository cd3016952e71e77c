"""The social context the planner sees: people, groups, queues and artworks.

It comes from a scenario file or, later, from perception; the planner only ever sees a
:class:`SocialContext`. Positions in metres in the world frame; yaw CCW from +x.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import FloatArray

HUMAN_RADIUS = 0.25


def _finite(values: tuple[float, ...], what: str) -> None:
    if not np.all(np.isfinite(values)):
        raise InvalidInputError(f"{what} contains NaN or infinite values: {values}")


@dataclass(frozen=True)
class Person:
    """One person: ``position`` (m), ``velocity`` (m/s, world), ``yaw`` (rad), ``radius`` (m)."""

    id: int
    position: tuple[float, float]
    velocity: tuple[float, float] = (0.0, 0.0)
    yaw: float = 0.0
    radius: float = HUMAN_RADIUS

    def __post_init__(self) -> None:
        _finite((*self.position, *self.velocity, self.yaw, self.radius), f"person {self.id}")
        if self.radius <= 0:
            raise InvalidInputError(f"person {self.id}: radius must be positive")


#: ``join`` / ``lead``: a standing conversation (O-formation) the robot joins or leads;
#: ``walking``: people moving together — an obstacle to keep whole, never a join target.
GROUP_MODES = ("join", "lead", "walking")


@dataclass(frozen=True)
class Group:
    """People in a group. ``mode``: ``"join"`` or ``"lead"`` (an O-formation the robot joins or
    leads) or ``"walking"`` (people moving together; see :data:`GROUP_MODES`)."""

    member_ids: tuple[int, ...]
    mode: str = "join"

    def __post_init__(self) -> None:
        if self.mode not in GROUP_MODES:
            raise InvalidInputError(
                f"group mode must be one of {', '.join(GROUP_MODES)}, got {self.mode!r}"
            )

    @property
    def is_walking(self) -> bool:
        """True for people moving together (``mode == "walking"``)."""
        return self.mode == "walking"


@dataclass(frozen=True)
class Queue:
    """People waiting in line; ``member_ids`` run from the person being served to the last one."""

    member_ids: tuple[int, ...]
    service_point: tuple[float, float]
    spacing: float = 0.8

    def __post_init__(self) -> None:
        _finite((*self.service_point, self.spacing), "queue")


@dataclass(frozen=True)
class Artwork:
    """A flat artwork on a wall: ``center`` (m), ``width`` (m), ``facing`` = yaw of its normal into
    the room (rad); ``viewer_ids`` are the people looking at it."""

    center: tuple[float, float]
    width: float
    facing: float
    viewer_ids: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        _finite((*self.center, self.width, self.facing), "artwork")
        if self.width <= 0:
            raise InvalidInputError("artwork width must be positive")


@dataclass(frozen=True)
class Structure:
    """A social structure of a registered kind (``socialnav.social.structures.STRUCTURES``):
    ``kind`` its registry name, ``params`` the kind's validated parameter model (frozen; its
    fields are the kind's YAML keys), ``member_ids`` the people it involves."""

    kind: str
    params: Any
    member_ids: tuple[int, ...] = ()


@dataclass(frozen=True)
class SocialContext:
    """Everything social the planner may reason about, at one instant: ``people``, the paper's
    ``groups``, ``queues`` and ``artworks``, and ``structures`` of any registered kind."""

    people: tuple[Person, ...] = ()
    groups: tuple[Group, ...] = ()
    queues: tuple[Queue, ...] = ()
    artworks: tuple[Artwork, ...] = ()
    structures: tuple[Structure, ...] = ()
    _index: dict[int, int] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        index = {p.id: i for i, p in enumerate(self.people)}
        if len(index) != len(self.people):
            raise InvalidInputError("person ids must be unique")
        members: list[tuple[str, tuple[int, ...]]] = [
            *(("Group", g.member_ids) for g in self.groups),
            *(("Queue", q.member_ids) for q in self.queues),
            *(("Artwork", a.viewer_ids) for a in self.artworks),
            *((s.kind, s.member_ids) for s in self.structures),
        ]
        for kind, ids in members:
            missing = [i for i in ids if i not in index]
            if missing:
                raise InvalidInputError(f"{kind} refers to unknown person ids {missing}")
        object.__setattr__(self, "_index", index)

    def person(self, person_id: int) -> Person:
        """The person with id ``person_id`` (``KeyError`` when there is none)."""
        return self.people[self._index[person_id]]

    def positions(self, ids: tuple[int, ...] | None = None) -> FloatArray:
        """``(K, 2)`` positions of the given people (all people by default)."""
        chosen = self.people if ids is None else [self.person(i) for i in ids]
        return np.array([p.position for p in chosen], dtype=float).reshape(-1, 2)

    def velocities(self) -> FloatArray:
        """``(K, 2)`` world velocities (m/s) of every person."""
        return np.array([p.velocity for p in self.people], dtype=float).reshape(-1, 2)

    def radii(self) -> FloatArray:
        """``(K,)`` radii (m) of every person."""
        return np.array([p.radius for p in self.people], dtype=float)

    def yaws(self) -> FloatArray:
        """``(K,)`` headings (rad, world) of every person."""
        return np.array([p.yaw for p in self.people], dtype=float)

    def with_people(self, people: tuple[Person, ...]) -> SocialContext:
        """The same groups/queues/artworks/structures with updated people (ids must resolve)."""
        return SocialContext(people, self.groups, self.queues, self.artworks, self.structures)

"""What every structure detector consumes and returns, and the registry they live in.

A detector looks at one instant of tracked people (:class:`TrackFrame`) and the static map
knowledge (:class:`MapKnowledge`: artworks and service points a semantic map carries), and
returns :class:`Candidate` structures with a per-frame ``score`` in [0, 1]. Temporal smoothing
(hysteresis) is not the detector's job: :mod:`socialnav.social.perception.tracking` does it for
every kind alike. Positions in metres, world frame; yaw CCW from +x (REP 103).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any, ClassVar, Generic, Literal, TypeVar

import numpy as np

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.geometry import FloatArray
from socialnav.core.registry import Registry
from socialnav.core.scene import Artwork, Person

StructureKind = Literal["fformation", "walking_group", "queue", "viewers"]

#: Below this speed (m/s) a person counts as standing. Pedestrian walking speeds are
#: 1.0–1.5 m/s (Bohannon 1997); tracker noise on a standing person stays well under 0.3 m/s.
STANDING_SPEED = 0.3


@dataclass(frozen=True)
class TrackFrame:
    """People at one instant, as arrays: ``ids (K,)``, ``positions (K, 2)`` (m),
    ``velocities (K, 2)`` (m/s, world), ``yaws (K,)`` (rad), ``time`` (s)."""

    ids: np.ndarray
    positions: FloatArray
    velocities: FloatArray
    yaws: FloatArray
    time: float = 0.0

    @classmethod
    def from_people(cls, people: Sequence[Person], time: float = 0.0) -> TrackFrame:
        """Arrays from :class:`~socialnav.core.scene.Person` tracks (ids must be unique)."""
        ids = np.array([p.id for p in people], dtype=np.int64)
        if np.unique(ids).size != ids.size:
            raise InvalidInputError("track ids must be unique within a frame")
        return cls(
            ids,
            np.array([p.position for p in people], dtype=float).reshape(-1, 2),
            np.array([p.velocity for p in people], dtype=float).reshape(-1, 2),
            np.array([p.yaw for p in people], dtype=float).reshape(-1),
            float(time),
        )

    def __len__(self) -> int:
        return int(self.ids.shape[0])

    @property
    def speeds(self) -> FloatArray:
        """Speeds ``(K,)`` (m/s)."""
        return np.hypot(self.velocities[:, 0], self.velocities[:, 1])

    def standing(self, speed: float = STANDING_SPEED) -> np.ndarray:
        """Boolean mask ``(K,)`` of people slower than ``speed`` (m/s)."""
        return self.speeds < speed


@dataclass(frozen=True)
class MapKnowledge:
    """What a semantic map tells about places of social activity.

    ``artworks``: the artworks on the walls (their ``viewer_ids`` are ignored: viewers are
    detected); ``service_points (S, 2)``: desks or counters where queues form (m).
    """

    artworks: tuple[Artwork, ...] = ()
    service_points: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))

    def __post_init__(self) -> None:
        sp = np.asarray(self.service_points, dtype=float).reshape(-1, 2)
        if not np.all(np.isfinite(sp)):
            raise InvalidInputError("service_points contains NaN or infinite values")
        object.__setattr__(self, "service_points", sp)


@dataclass(frozen=True)
class Candidate:
    """One structure seen in one frame.

    ``members``: person ids (a queue's run head → tail; an artwork's viewers); ``score`` in
    [0, 1] (how well this frame's evidence fits the structure); ``anchor``: for ``viewers``
    the index of the artwork in :attr:`MapKnowledge.artworks`, for ``queue`` the service point
    ``(x, y)``; ``geometry``: what the detector computed (o-space centre and radius, …).
    """

    kind: StructureKind
    members: tuple[int, ...]
    score: float
    anchor: Any = None
    geometry: dict[str, Any] = field(default_factory=dict)


Detector = Callable[[TrackFrame, MapKnowledge, frozenset[int]], list[Candidate]]
"""``(frame, map, claimed ids) -> candidates``; ``claimed`` are people an earlier detector of
the pipeline already placed (a queue member is not also in a conversation)."""

#: kind → detector factory (``**params -> Detector``); each detector is one module of this
#: package and registers itself here.
DETECTORS: Registry[Callable[..., Detector]] = Registry("structure detector")


P = TypeVar("P")


def check_number(
    what: str,
    value: object,
    low: float = 0.0,
    high: float = math.inf,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> None:
    """Raise :class:`~socialnav.core.errors.ConfigurationError` unless ``value`` is a finite
    number (not a bool) between ``low`` and ``high``, each bound included unless ``*_open``;
    the message names ``what`` (e.g. ``"FFormationDetector: parameter mdl"``) and the range."""
    number = isinstance(value, int | float | np.number) and not isinstance(value, bool)
    v = float(value) if number else math.nan  # type: ignore[arg-type]
    above = v > low if low_open else v >= low
    below = v < high if high_open else v <= high
    if not (math.isfinite(v) and above and below):
        if math.isinf(high):
            span = f"{'>' if low_open else '>='} {low:g}"
        else:
            span = f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}"
        raise ConfigurationError(f"{what} must be a finite number {span}, got {value!r}")


class ParamDetector(Generic[P]):
    """Base of the detectors: holds a frozen parameter dataclass, built from ``params`` (or the
    defaults) with keyword ``overrides`` (the estimator's ``detector_params``). Every numeric
    parameter (lengths, speeds, angles, costs, counts) must be a finite number >= 0, and those
    in ``positive`` > 0; raises :class:`~socialnav.core.errors.ConfigurationError` naming the
    parameter, or an unknown one with the known ones."""

    params_type: ClassVar[type]
    #: parameters that must be > 0 (scales and counts a zero would divide by or empty)
    positive: ClassVar[frozenset[str]] = frozenset()

    def __init__(self, params: P | None = None, **overrides: Any) -> None:
        base: Any = params if params is not None else self.params_type()
        known = {f.name for f in fields(base)}
        unknown = sorted(set(overrides) - known)
        if unknown:
            raise ConfigurationError(
                f"{type(self).__name__}: unknown parameter(s) {', '.join(unknown)}; "
                f"known: {', '.join(sorted(known))}"
            )
        self.params: P = replace(base, **overrides)
        for f in fields(self.params):
            value = getattr(self.params, f.name)
            if isinstance(value, int | float | np.number) and not isinstance(value, bool):
                check_number(
                    f"{type(self).__name__}: parameter {f.name}",
                    value,
                    low_open=f.name in self.positive,
                )


def unclaimed(frame: TrackFrame, claimed: frozenset[int], mask: np.ndarray) -> np.ndarray:
    """Indices into ``frame`` where ``mask (K,)`` holds and the person is not yet claimed."""
    return np.flatnonzero(mask & ~np.isin(frame.ids, list(claimed)))


def faces_ospace(positions: FloatArray, yaws: FloatArray, center: FloatArray) -> bool:
    """Whether most members of a candidate F-formation face its o-space: more than half of the
    people ``positions (K, 2)`` (m), ``yaws (K,)`` (rad) have ``center (2,)`` in front of them
    (a positive component along their heading). Kendon's o-space is the space the members'
    transactional segments share (Conducting Interaction, 1990), so a set whose centre lies
    behind most of them (two people standing back to back) is not one, however close they
    stand. A strict majority, not everyone: a listener whose body turns away while their head
    does not still belongs (on Cristani et al.'s Synth data every detected group already had
    at least half its members facing; requiring more than half removed only false groups,
    F1 at T = 2/3 0.952 → 0.970, CoffeeBreak unchanged)."""
    rel = np.asarray(center, dtype=float) - np.asarray(positions, dtype=float)
    front = rel[:, 0] * np.cos(yaws) + rel[:, 1] * np.sin(yaws)
    return bool(2 * int((front > 0.0).sum()) > front.size)

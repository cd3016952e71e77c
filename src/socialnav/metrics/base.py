"""The metric contract and registry.

A :class:`Metric` is a named, documented, pure function of an :class:`EpisodeRecord`. Its name
carries its variant (``min_distance_center`` vs ``min_distance_edge``, ``psc_0.45`` vs
``psc_1.2``) so two tools never disagree silently on what a number means. Undefined values are
NaN (e.g. ``lateral_distance`` when robot and person never pass), never an exception.

Conventions shared by every metric:

- SI units, radians; "distance" without qualifier is centre-to-centre.
- Sampled at the record's fixed step ``dt``; finite differences use ``dt``.
- Several people: per-person quantities reduce over people (min distance = min over all
  people, counts = sum over people, shares/compliance use the closest person at each sample).
  Metrics that need *one* person (the Table 1 ``lateral_distance``, ``deviation_distance``,
  ``passing_side``) use the person who came closest to the robot during the episode (in
  Table 1 there is a single person).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import InvalidInputError
from socialnav.core.registry import Registry

Direction = Literal["min", "max"]
MetricFn = Callable[[EpisodeRecord], float]


@dataclass(frozen=True)
class Metric:
    """One registered metric.

    ``name`` includes the variant; ``unit`` is an SI unit string (``"1"`` for counts, shares and
    flags); ``direction`` says which is better (``"min"``: lower is better); ``reference`` names
    the source of the definition; ``doc`` is the function's docstring (formula and convention).
    Calling the metric validates the record and returns a float (NaN when undefined).
    """

    name: str
    unit: str
    direction: Direction
    reference: str
    fn: MetricFn = field(repr=False)
    doc: str = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.direction not in ("min", "max"):
            raise ValueError(f"metric {self.name}: direction must be 'min' or 'max'")
        doc = inspect.getdoc(self.fn)
        if not doc:
            raise ValueError(f"metric {self.name}: its function needs a docstring (formula)")
        object.__setattr__(self, "doc", doc)

    def __call__(self, record: EpisodeRecord) -> float:
        """The metric's value on ``record`` (its unit; NaN when undefined)."""
        validate_record(record)
        return float(self.fn(record))


METRICS: Registry[Metric] = Registry("metric")


def metric(
    name: str, *, unit: str, direction: Direction, reference: str = "metrics.md"
) -> Callable[[MetricFn], MetricFn]:
    """Decorator registering ``fn(record) -> float`` as :class:`Metric` ``name``."""

    def decorate(fn: MetricFn) -> MetricFn:
        METRICS.add(name, Metric(name, unit, direction, reference, fn))
        return fn

    return decorate


def validate_record(record: EpisodeRecord) -> None:
    """Raise :class:`InvalidInputError` (a ValueError) when a record cannot be measured."""
    if record.num_steps < 1:
        raise InvalidInputError("episode record has no samples")
    if not (np.isfinite(record.dt) and record.dt > 0):
        raise InvalidInputError(f"episode record dt must be positive, got {record.dt}")
    arrays = {
        "times": record.times,
        "robot_poses": record.robot_poses,
        "people_positions": record.people_positions[record.people_present],
        "people_velocities": record.people_velocities[record.people_present],
        "people_radii": record.people_radii,
        "start": record.start,
        "goal": record.goal,
        "target": record.target,
        "robot_footprint": record.robot_footprint,
    }
    for what, arr in arrays.items():
        if not np.all(np.isfinite(np.asarray(arr, dtype=float))):
            where = " where the person is present" if what.startswith("people_") else ""
            raise InvalidInputError(f"episode record {what} contains NaN or infinite values{where}")
    for what, arr in (("start", record.start), ("goal", record.goal), ("target", record.target)):
        if np.shape(arr) != (3,):
            raise InvalidInputError(f"episode record {what} must be (x, y, yaw)")
    fp = np.asarray(record.robot_footprint)
    if fp.ndim != 2 or fp.shape[1] != 2 or fp.shape[0] < 3:
        raise InvalidInputError(f"robot_footprint must be (V>=3, 2), got {fp.shape}")
    steps = np.diff(record.times)
    if steps.size and np.any(np.abs(steps - record.dt) > 1e-6 + 1e-3 * record.dt):
        raise InvalidInputError("episode record times are not sampled every dt")


def compute_metrics(record: EpisodeRecord, names: Iterable[str] | None = None) -> dict[str, float]:
    """Evaluate the named metrics (all registered ones by default) on ``record``.

    Unknown names raise a ConfigurationError listing the known ones.
    """
    validate_record(record)
    chosen = METRICS.names() if names is None else list(names)
    metrics = [METRICS.get(n) for n in chosen]
    return {m.name: float(m.fn(record)) for m in metrics}

"""The critic contract, modelled on Nav2 DWB critics.

A critic turns a batch of trajectories into a raw cost per trajectory (in its own unit; weights
live in the objectives, never inside a critic) plus boolean masks of trajectories it declares
illegal, keyed by reason — the counts per reason are what a user reads when the planner misbehaves.
Critics are frozen dataclasses: their fields are their documented parameters.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar, Literal

import numpy as np

from socialnav.core.errors import SocialNavError
from socialnav.core.geometry import FloatArray
from socialnav.core.registry import Registry
from socialnav.core.trajectories import Trajectories

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext

TimeAggregation = Literal["last", "sum", "max", "mean", "min"]

#: How much deeper (m) than the robot is now a trajectory may reach into a space it is already
#: inside (o-space, activity space) before it counts as intruding: the escape of the
#: ``illegal_inside`` rules, with room for the rollout's float32 rounding.
ESCAPE_TOLERANCE = 1e-3


class CriticUnavailable(SocialNavError):
    """Raised by ``prepare`` when a critic cannot score this cycle (e.g. goal off the costmap);
    the planner turns it into a status instead of crashing."""


@dataclass(frozen=True)
class CriticScore:
    """``cost (N,)``, finite and >= 0 on legal rows; ``illegal``: reason → ``(N,)`` mask."""

    cost: FloatArray
    illegal: Mapping[str, np.ndarray] = field(default_factory=dict)


class Critic(ABC):
    """One cost term; subclasses are frozen dataclasses registered in :data:`CRITICS`."""

    name: ClassVar[str]
    unit: ClassVar[str]

    def reset(self) -> None:  # noqa: B027 - optional hook
        """Forget state carried across cycles (most critics have none)."""

    def prepare(self, ctx: PlanningContext) -> None:  # noqa: B027 - optional hook
        """Per-cycle shared work; may raise :class:`CriticUnavailable`."""

    @abstractmethod
    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Raw cost of each trajectory, shape ``(N,)``."""


CRITICS: Registry[type[Critic]] = Registry("critic")


def aggregate_time(values: FloatArray, how: TimeAggregation) -> FloatArray:
    """Reduce per-step values ``(N, T)`` to ``(N,)``; ``last`` is the paper's end-point rule."""
    if how == "last":
        return values[:, -1]
    if how == "sum":
        return values.sum(axis=1)
    if how == "max":
        return values.max(axis=1)
    if how == "mean":
        return values.mean(axis=1)
    if how == "min":
        return values.min(axis=1)
    raise ValueError(f"unknown time aggregation {how!r}; use last, sum, max, mean or min")

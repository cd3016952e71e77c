"""Critics: one small unit per cost term, each behind the :class:`Critic` interface."""

from socialnav.planner.critics.base import (
    CRITICS,
    Critic,
    CriticScore,
    CriticUnavailable,
    aggregate_time,
)

__all__ = ["CRITICS", "Critic", "CriticScore", "CriticUnavailable", "aggregate_time"]

"""One path that measures an episode: every registered metric and every success condition.

``socialnav run``, the suites and the report all measure through :func:`measure_episode`, so a
run's ``metrics.json`` and its row in ``results.parquet`` cannot disagree.
"""

from __future__ import annotations

from dataclasses import dataclass

from socialnav.core.episode import EpisodeRecord
from socialnav.core.success import Condition
from socialnav.metrics.base import compute_metrics
from socialnav.metrics.success import success_conditions

__all__ = ["EpisodeMeasurement", "measure_episode"]


@dataclass(frozen=True)
class EpisodeMeasurement:
    """``metrics`` name → value (each metric's unit; NaN when undefined), ``conditions`` as
    judged (:attr:`EpisodeRecord.success`), ``success`` = every required condition passed."""

    metrics: dict[str, float]
    conditions: tuple[Condition, ...]

    @property
    def success(self) -> bool:
        """Whether every required condition passed."""
        return all(c.passed for c in self.conditions if c.required)

    def passed(self) -> dict[str, bool]:
        """Condition name → passed, plus ``"success"`` (the form of ``evaluate_success``)."""
        out = {c.name: c.passed for c in self.conditions}
        out["success"] = self.success
        return out


def measure_episode(record: EpisodeRecord) -> EpisodeMeasurement:
    """Every registered metric and every success condition of ``record``.

    Raises ``InvalidInputError`` on a malformed record or a condition whose structure is missing
    from the record's context, ``ConfigurationError`` on an unknown family or condition."""
    return EpisodeMeasurement(compute_metrics(record), tuple(success_conditions(record)))

"""Layer 3: metrics — pure functions of a recorded :class:`~socialnav.core.episode.EpisodeRecord`.

``METRICS`` holds every registered :class:`Metric` (importing this package registers them all);
``compute_metrics(record, names=None)`` evaluates them; ``evaluate_success(record)`` checks the
scenario suite's success conditions; ``measure_episode(record)`` does both, the one path every
command measures through. Never imports ``sim`` or ``planner``.
"""

from socialnav.metrics import (  # noqa: F401 (register)
    crowd,
    crowdnav,
    motion,
    proxemics,
    scenario,
    table1,
    task,
)
from socialnav.metrics.base import METRICS, Metric, compute_metrics, metric, validate_record
from socialnav.metrics.measure import EpisodeMeasurement, measure_episode
from socialnav.metrics.success import Condition, evaluate_success, success_conditions

__all__ = [
    "METRICS",
    "Condition",
    "EpisodeMeasurement",
    "Metric",
    "compute_metrics",
    "evaluate_success",
    "measure_episode",
    "metric",
    "success_conditions",
    "validate_record",
]

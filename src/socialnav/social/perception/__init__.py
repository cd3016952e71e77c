"""Social context from people's tracks: F-formations, walking groups, queues, artwork viewers.

:class:`ContextEstimator` (module :mod:`.estimator`) is the entry point; each structure kind is
one detector module registered in :data:`DETECTORS`.
"""

from socialnav.social.perception.base import (
    DETECTORS,
    Candidate,
    MapKnowledge,
    TrackFrame,
)
from socialnav.social.perception.estimator import (
    ContextEstimator,
    Estimate,
    EstimatorParams,
    Structure,
    estimate_once,
)
from socialnav.social.perception.tracking import HysteresisParams

__all__ = [
    "DETECTORS",
    "Candidate",
    "ContextEstimator",
    "Estimate",
    "EstimatorParams",
    "HysteresisParams",
    "MapKnowledge",
    "Structure",
    "TrackFrame",
    "estimate_once",
]

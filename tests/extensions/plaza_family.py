"""A scenario family in one module: an open plaza crossed by walkers.

It declares its success conditions: the common two and ``kept_clearance`` (every person's
centre stays at least the tolerance away, 0.8 m by default), whose check it registers.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.success import (
    CONDITIONS,
    FAMILIES,
    ConditionCheck,
    ConditionSpec,
    register_family,
)

NAME = "plaza"


def kept_clearance(record: EpisodeRecord, tolerance: float) -> bool:
    """Centre distance (m) to every person >= ``tolerance`` at every sample."""
    if record.people_positions.shape[1] == 0:
        return True
    gaps = record.people_positions - record.robot_xy[:, None, :]
    return bool(np.hypot(gaps[..., 0], gaps[..., 1]).min() >= tolerance)


if NAME not in FAMILIES:
    CONDITIONS.add(
        "kept_clearance", ConditionCheck(kept_clearance, 0.8, "m", "centre distance >= tolerance")
    )
    register_family(
        NAME,
        "an open plaza crossed by walkers",
        (
            ConditionSpec("reached_goal"),
            ConditionSpec("no_collision"),
            ConditionSpec("kept_clearance"),
        ),
    )

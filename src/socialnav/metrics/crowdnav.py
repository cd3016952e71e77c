"""CrowdNav's own episode measures (Chen et al., ICRA 2019, ``crowd_nav/utils/explorer.py``).

CrowdNav reports success rate, collision rate, timeout rate, the mean navigation time of
successful episodes and the *discomfort frequency*: the share of steps at which the robot is
closer than the discomfort distance (0.2 m) to a person, measured between bodies. Here bodies
are the robot's footprint polygon and the person's disc.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import signed_distance_to_polygon, world_to_body_frames
from socialnav.metrics.base import metric
from socialnav.metrics.series import convex_footprint

DISCOMFORT_DISTANCE = 0.2  # m, CrowdNav's ``discomfort_dist``


def body_gaps(record: EpisodeRecord) -> np.ndarray:
    """Gap (m) between the footprint and each person's disc at each sample ``(T, K)``."""
    body = world_to_body_frames(record.people_positions, record.robot_poses)
    return signed_distance_to_polygon(body, convex_footprint(record)) - record.people_radii[None]


@metric("discomfort", unit="1", direction="min", reference="Chen et al. 2019 (CrowdNav)")
def discomfort(record: EpisodeRecord) -> float:
    """Share of samples at which the body gap to some person is below 0.2 m (CrowdNav's
    discomfort frequency). NaN without people."""
    if record.people_ids.shape[0] == 0:
        return float("nan")
    return float(np.mean(body_gaps(record).min(axis=1) < DISCOMFORT_DISTANCE))

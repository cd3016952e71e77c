"""Walking groups: people moving together, to keep whole (never a place to join).

Method: two walking people are linked when they are close (``max_distance``) and move with
nearly the same velocity (``max_velocity_difference``, and both faster than ``min_speed``);
groups are the connected components of the links (``scipy.sparse.csgraph``). These are the
proxemic and velocity-coherence cues of group detection in crowds (Ge, Collins, Ruback,
"Vision-based analysis of small groups in pedestrian crowds", TPAMI 2012; Solera et al.,
TPAMI 2016, use the same cues as features). Temporal coherence — "together over time" — comes
from the tracker's hysteresis (:mod:`socialnav.social.perception.tracking`). The defaults were
set a priori (side-by-side walkers keep 0.5–1.5 m; a shared pace differs by well under
0.35 m/s), not tuned; they are reported on ETH hotel and UCY zara01
(``benchmarks/bench_context.py``).

A link's score is ``exp(−(d/max_distance)² − (Δv/max_velocity_difference)²)``; a group's score
is its weakest link in a spanning tree (the minimum over members of their best link).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_array
from scipy.sparse.csgraph import connected_components

from socialnav.social.perception.base import (
    DETECTORS,
    Candidate,
    MapKnowledge,
    ParamDetector,
    TrackFrame,
    unclaimed,
)


@dataclass(frozen=True)
class WalkingGroupParams:
    """Cues (module docstring): metres, metres per second."""

    max_distance: float = 2.0
    max_velocity_difference: float = 0.35
    min_speed: float = 0.3


class WalkingGroupDetector(ParamDetector[WalkingGroupParams]):
    """Registered as ``walking_group``."""

    params_type = WalkingGroupParams

    def __call__(
        self, frame: TrackFrame, knowledge: MapKnowledge, claimed: frozenset[int]
    ) -> list[Candidate]:
        """Candidates of one frame (see :data:`~socialnav.social.perception.base.Detector`)."""
        del knowledge
        p = self.params
        idx = unclaimed(frame, claimed, frame.speeds >= p.min_speed)
        if idx.size < 2:
            return []
        pos, vel = frame.positions[idx], frame.velocities[idx]
        dist = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
        dv = np.linalg.norm(vel[:, None] - vel[None], axis=-1)
        link = (dist <= p.max_distance) & (dv <= p.max_velocity_difference)
        np.fill_diagonal(link, False)
        score = np.exp(-((dist / p.max_distance) ** 2) - (dv / p.max_velocity_difference) ** 2)
        n, labels = connected_components(csr_array(link.astype(np.int8)), directed=False)
        out = []
        for c in range(n):
            members = np.flatnonzero(labels == c)
            if members.size < 2:
                continue
            sub = np.where(link[np.ix_(members, members)], score[np.ix_(members, members)], 0.0)
            out.append(
                Candidate(
                    "walking_group",
                    tuple(int(i) for i in frame.ids[idx[members]]),
                    float(sub.max(axis=1).min()),
                    geometry={"velocity": vel[members].mean(axis=0)},
                )
            )
        return out


DETECTORS.add("walking_group", WalkingGroupDetector)

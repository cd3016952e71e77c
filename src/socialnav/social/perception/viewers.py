"""Viewers of artworks: standing people in front of an artwork of the map, facing it.

Method: the artwork's geometry comes from the map (:class:`~socialnav.core.scene.Artwork`:
centre, width, facing); a person is a viewer when they stand in front of it (depth along its
normal ``min_depth``–``max_depth`` m), within the artwork's lateral extent widened by
``lateral_margin``, and their heading points at the artwork: the angle between the heading and
the direction to the nearest point of the artwork is below ``max_gaze_angle``. The distances
bracket the project's gallery scenarios (viewers 1–2.5 m from the wall, the generated range)
with a margin; the angular limit admits a 15° heading noise at about 2.5 σ. They are this
module's choices, not a paper's.
Score: ``cos`` of the gaze angle scaled to [0, 1] over the admitted range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socialnav.core.geometry import wrap_angle
from socialnav.social.perception.base import (
    DETECTORS,
    STANDING_SPEED,
    Candidate,
    MapKnowledge,
    ParamDetector,
    TrackFrame,
    unclaimed,
)
from socialnav.social.spaces import art_frame


@dataclass(frozen=True)
class ViewerParams:
    """Viewing cues (module docstring): metres and radians."""

    min_depth: float = 0.3
    max_depth: float = 3.5
    lateral_margin: float = 1.5
    max_gaze_angle: float = np.radians(40.0)
    standing_speed: float = STANDING_SPEED


class ViewerDetector(ParamDetector[ViewerParams]):
    """Registered as ``viewers``: one candidate per artwork with at least one viewer."""

    params_type = ViewerParams

    def __call__(
        self, frame: TrackFrame, knowledge: MapKnowledge, claimed: frozenset[int]
    ) -> list[Candidate]:
        """Candidates of one frame (see :data:`~socialnav.social.perception.base.Detector`)."""
        p = self.params
        idx = unclaimed(frame, claimed, frame.standing(p.standing_speed))
        out: list[Candidate] = []
        if idx.size == 0:
            return out
        pos, yaw = frame.positions[idx], frame.yaws[idx]
        for a, art in enumerate(knowledge.artworks):
            n, t = art_frame(art.facing)
            c = np.asarray(art.center, dtype=float)
            rel = pos - c
            depth, lateral = rel @ n, rel @ t
            along = np.clip(lateral, -0.5 * art.width, 0.5 * art.width)
            nearest = c + along[:, None] * t
            look = nearest - pos
            gaze = np.abs(wrap_angle(np.arctan2(look[:, 1], look[:, 0]) - yaw))
            ok = (
                (depth >= p.min_depth)
                & (depth <= p.max_depth)
                & (np.abs(lateral) <= 0.5 * art.width + p.lateral_margin)
                & (gaze <= p.max_gaze_angle)
            )
            if not ok.any():
                continue
            scores = np.cos(gaze[ok]) - np.cos(p.max_gaze_angle)
            scores /= 1.0 - np.cos(p.max_gaze_angle)
            out.append(
                Candidate(
                    "viewers",
                    tuple(int(i) for i in frame.ids[idx[ok]]),
                    float(np.clip(scores, 0.0, 1.0).mean()),
                    anchor=a,
                    geometry={"distances": np.linalg.norm(look[ok], axis=1)},
                )
            )
        return out


DETECTORS.add("viewers", ViewerDetector)

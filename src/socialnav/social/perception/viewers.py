"""Viewers of artworks: standing people in front of an artwork of the map, facing it.

Method: the artwork's geometry comes from the map (:class:`~socialnav.core.scene.Artwork`:
centre, width, facing); a person is a viewer when they stand in front of it (depth along its
normal ``min_depth``–``max_depth`` m), within the artwork's lateral extent widened by
``lateral_margin``, and their heading points at the artwork: the angle between the heading and
the artwork (0 when the heading ray hits it, else the angle to its nearer end;
:func:`subtended_gaze`) is below ``max_gaze_angle``. The distances
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


def subtended_gaze(
    positions: np.ndarray, yaws: np.ndarray, end_a: np.ndarray, end_b: np.ndarray
) -> np.ndarray:
    """Angle (rad, ``(K,)``) between each heading ``yaws (K,)`` at ``positions (K, 2)`` and
    the segment ``end_a``–``end_b (2,)``: 0 when the heading ray hits the segment, else the
    angle to the nearer end. A viewer looks at some point of the artwork, not necessarily the
    nearest one: with the nearest point, a viewer 1 m in front of one end of a 1.2 m artwork
    looking at its centre was 31° off, and heading noise pushed them past the limit."""
    rel = []
    for end in (end_a, end_b):
        d = np.asarray(end, dtype=float) - positions
        rel.append(wrap_angle(np.arctan2(d[:, 1], d[:, 0]) - yaws))
    ra, rb = rel
    # the segment subtends less than π from a point in front of it: the heading is inside
    # when the two ends lie on opposite sides of it, less than π apart
    inside = (np.sign(ra) != np.sign(rb)) & (np.abs(ra) + np.abs(rb) < np.pi)
    return np.where(inside, 0.0, np.minimum(np.abs(ra), np.abs(rb)))


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
            gaze = subtended_gaze(pos, yaw, c - 0.5 * art.width * t, c + 0.5 * art.width * t)
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

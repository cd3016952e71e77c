"""Hysteresis for detected structures: a group does not flicker in and out.

Each structure kind is tracked over time. A frame's candidates are matched to the tracks of the
same kind by the Jaccard index of their member sets (``>= match_jaccard``, best first). A
track's confidence is an exponential moving average of its candidates' scores with time
constant ``time_constant`` (s): ``c ← c + α (s − c)``, ``α = 1 − exp(−Δt/τ)``; an unmatched
track decays toward 0. A track becomes *active* when its confidence reaches ``on`` and stays
active until it falls below ``off`` < ``on`` (a Schmitt trigger), so one missed frame neither
creates nor removes a structure. With the defaults (τ = 0.5 s, on 0.5, off 0.25) a structure
seen with score 1 appears after 0.35 s and survives 0.7 s without evidence.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.social.perception.base import Candidate, StructureKind, check_number


@dataclass(frozen=True)
class HysteresisParams:
    """``time_constant`` (s), ``nominal_period`` (s, the Δt of the very first update),
    thresholds ``on`` > ``off`` in [0, 1], ``match_jaccard``, and ``forget`` (a track below this
    confidence is dropped)."""

    time_constant: float = 0.5
    nominal_period: float = 0.1
    on: float = 0.5
    off: float = 0.25
    match_jaccard: float = 0.5
    forget: float = 0.05


def check_hysteresis(params: object) -> None:
    """Raise :class:`~socialnav.core.errors.ConfigurationError` unless ``params`` is a
    :class:`HysteresisParams` with finite values, ``time_constant >= 0`` (0: no smoothing, as
    :func:`~socialnav.social.perception.estimator.estimate_once` uses), ``nominal_period > 0``,
    ``0 <= off <= on <= 1``, ``forget`` in [0, 1] and ``match_jaccard`` in (0, 1] (a NaN time
    constant confirmed nothing, ever)."""
    if not isinstance(params, HysteresisParams):
        raise ConfigurationError(f"hysteresis must be HysteresisParams, got {params!r}")
    p = params
    check_number("hysteresis time_constant (s)", p.time_constant)
    check_number("hysteresis nominal_period (s)", p.nominal_period, low_open=True)
    for name in ("on", "off", "forget"):
        check_number(f"hysteresis {name}", getattr(p, name), 0.0, 1.0)
    check_number("hysteresis match_jaccard", p.match_jaccard, 0.0, 1.0, low_open=True)
    if p.off > p.on:
        raise ConfigurationError(f"hysteresis needs off <= on: {p}")


@dataclass
class Track:
    """A structure followed over time (mutable: updated in place every frame)."""

    track_id: int
    kind: StructureKind
    members: tuple[int, ...]
    confidence: float
    anchor: Any = None
    geometry: dict[str, Any] = field(default_factory=dict)
    active: bool = False
    seen: float = 0.0


def jaccard(a: tuple[int, ...], b: tuple[int, ...]) -> float:
    """``|A ∩ B| / |A ∪ B|`` of two member sets (0 when both are empty)."""
    sa, sb = set(a), set(b)
    return len(sa & sb) / len(sa | sb) if sa | sb else 0.0


class StructureTracker:
    """Tracks of every kind; :meth:`update` takes one frame's candidates."""

    def __init__(self, params: HysteresisParams | None = None) -> None:
        self.params = params or HysteresisParams()
        check_hysteresis(self.params)
        self.reset()

    def reset(self) -> None:
        """Drop every track."""
        self.tracks: list[Track] = []
        self._next_id = 0
        self._time: float | None = None

    def update(self, time: float, candidates: list[Candidate]) -> list[Track]:
        """Fold in the candidates seen at ``time`` (s); returns the active tracks."""
        p = self.params
        dt = p.nominal_period if self._time is None else max(time - self._time, 0.0)
        if self._time is None and p.time_constant <= 0:
            dt = 0.0
        self._time = time
        # τ = 0 turns smoothing off (single-frame evaluation)
        alpha = 1.0 if p.time_constant <= 0 else 1.0 - float(np.exp(-dt / p.time_constant))
        pairs = []
        for ci, cand in enumerate(candidates):
            for ti, track in enumerate(self.tracks):
                same_anchor = cand.kind != "viewers" or track.anchor == cand.anchor
                if track.kind == cand.kind and same_anchor:
                    j = jaccard(cand.members, track.members)
                    if j >= p.match_jaccard:
                        pairs.append((-j, ci, ti))
        pairs.sort()
        used_c: set[int] = set()
        used_t: set[int] = set()
        for _, ci, ti in pairs:
            if ci in used_c or ti in used_t:
                continue
            used_c.add(ci)
            used_t.add(ti)
            cand, track = candidates[ci], self.tracks[ti]
            track.confidence += alpha * (cand.score - track.confidence)
            track.members, track.anchor, track.geometry = cand.members, cand.anchor, cand.geometry
            track.seen = time
        for ti, track in enumerate(self.tracks):
            if ti not in used_t:
                track.confidence *= 1.0 - alpha
        for ci, cand in enumerate(candidates):
            if ci not in used_c:
                self.tracks.append(
                    Track(
                        self._next_id,
                        cand.kind,
                        cand.members,
                        alpha * cand.score,
                        cand.anchor,
                        cand.geometry,
                        seen=time,
                    )
                )
                self._next_id += 1
        for track in self.tracks:
            track.active = track.confidence >= (p.off if track.active else p.on)
        self.tracks = [t for t in self.tracks if t.active or t.confidence >= p.forget]
        return [t for t in self.tracks if t.active]

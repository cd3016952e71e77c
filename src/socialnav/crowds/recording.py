"""A recorded crowd: people's tracks in the world frame, interpolated to any time.

A :class:`Recording` is what the loaders (``socialnav.crowds.loaders``) return and what replay,
episode generation and context estimation read. Positions are metres in the dataset's world frame
(the ground plane ``x, y``), times are seconds from the recording's frame 0
(``time = frame · frame_period``).

Interpolation (SocNavBench and CrowdNav replay people the same way):

- position: linear between consecutive samples of a track;
- velocity: the central finite difference of the positions at each sample (one-sided at a
  track's ends), linearly interpolated — the same for every format, so a file with recorded
  velocities (obsmat) and one without (four-column, Trajnet++) replay alike;
- heading: the direction of the velocity; while a person stands (speed below
  :data:`STANDING_SPEED`) the last heading while walking is held (the first one before they walk);
- presence: a person is present from their first to their last sample, except across gaps in
  their track longer than ``max_gap`` seconds (an occlusion or a re-identification), where they
  are absent. Absent people read NaN.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from socialnav.core.geometry import FloatArray

#: speed (m/s) below which a person is standing: their heading is held, not recomputed
STANDING_SPEED = 0.1
#: default longest gap (s) in a track bridged by interpolation (five 0.4 s annotation periods)
DEFAULT_MAX_GAP = 2.0


@dataclass(frozen=True)
class Track:
    """One person's samples: ``times (M,)`` s strictly increasing, ``positions (M, 2)`` m."""

    id: int
    times: FloatArray
    positions: FloatArray
    velocities: FloatArray = field(init=False, repr=False)
    headings: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        t = np.asarray(self.times, dtype=float).reshape(-1)
        p = np.asarray(self.positions, dtype=float).reshape(-1, 2)
        if t.shape[0] != p.shape[0] or t.shape[0] == 0:
            raise ValueError(f"track {self.id}: {t.shape[0]} times for {p.shape[0]} positions")
        if np.any(np.diff(t) <= 0):
            raise ValueError(f"track {self.id}: times must be strictly increasing")
        v = np.gradient(p, t, axis=0) if t.shape[0] > 1 else np.zeros_like(p)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "positions", p)
        object.__setattr__(self, "velocities", v)
        object.__setattr__(self, "headings", _held_headings(v))

    @property
    def start_time(self) -> float:
        """Time of the first sample (s)."""
        return float(self.times[0])

    @property
    def end_time(self) -> float:
        """Time of the last sample (s)."""
        return float(self.times[-1])


def _held_headings(velocities: FloatArray) -> FloatArray:
    """Heading per sample ``(M,)``, unwrapped; held through samples slower than STANDING_SPEED."""
    speed = np.hypot(velocities[:, 0], velocities[:, 1])
    raw = np.arctan2(velocities[:, 1], velocities[:, 0])
    moving = speed >= STANDING_SPEED
    if not moving.any():
        return np.zeros(len(raw))
    idx = np.where(moving, np.arange(len(raw)), -1)
    idx = np.maximum.accumulate(idx)  # last moving sample so far
    idx[idx < 0] = int(np.argmax(moving))  # before the first walk: the first walking heading
    return np.unwrap(raw[idx])


@dataclass(frozen=True)
class CrowdState:
    """Everyone of a recording at ``T`` instants, ``P`` people (``ids`` order).

    ``positions (T, P, 2)`` m, ``velocities (T, P, 2)`` m/s (world frame), ``headings (T, P)``
    rad in ``(-π, π]``, ``present (T, P)`` bool; NaN wherever a person is absent.
    """

    times: FloatArray
    ids: NDArray[np.int64]
    positions: FloatArray
    velocities: FloatArray
    headings: FloatArray
    present: NDArray[np.bool_]


@dataclass(frozen=True)
class Area:
    """The annotated area: the axis-aligned box ``[xmin, xmax] × [ymin, ymax]`` (m) of every
    recorded position."""

    xmin: float
    ymin: float
    xmax: float
    ymax: float

    @property
    def size(self) -> tuple[float, float]:
        """``(width, height)`` of the area (m)."""
        return self.xmax - self.xmin, self.ymax - self.ymin

    def contains(self, xy: FloatArray, margin: float = 0.0) -> NDArray[np.bool_]:
        """Whether points ``(..., 2)`` lie inside the area shrunk by ``margin`` (m)."""
        p = np.asarray(xy, dtype=float)
        return (
            (p[..., 0] >= self.xmin + margin)
            & (p[..., 0] <= self.xmax - margin)
            & (p[..., 1] >= self.ymin + margin)
            & (p[..., 1] <= self.ymax - margin)
        )

    def border_distance(self, xy: FloatArray) -> FloatArray:
        """Distance (m) from points ``(..., 2)`` to the area's border (negative outside)."""
        p = np.asarray(xy, dtype=float)
        return np.minimum.reduce(
            [
                p[..., 0] - self.xmin,
                self.xmax - p[..., 0],
                p[..., 1] - self.ymin,
                self.ymax - p[..., 1],
            ]
        )


@dataclass(frozen=True)
class Recording:
    """A recorded crowd: ``tracks`` by id, ``groups`` (ids that walk together), the
    ``frame_period`` (s per frame number) used to convert frames to times, the file it came from
    and its ``format`` (``obsmat``, ``four_column``, ``trajnet``). ``max_gap`` (s) is the longest
    gap in a track bridged by interpolation."""

    tracks: tuple[Track, ...]
    frame_period: float
    groups: tuple[tuple[int, ...], ...] = ()
    source: Path | None = None
    format: str = ""
    max_gap: float = DEFAULT_MAX_GAP
    _index: dict[int, int] = field(init=False, repr=False, compare=False)

    def __repr__(self) -> str:
        # the dataclass repr printed every track's samples (300 000 characters for ETH hotel)
        return (
            f"Recording({self.name!r}, format={self.format!r}, {len(self.tracks)} tracks, "
            f"{len(self.groups)} groups, {self.start_time:g}–{self.end_time:g} s, "
            f"frame_period={self.frame_period:g})"
        )

    def __post_init__(self) -> None:
        if not self.tracks:
            raise ValueError(f"{self.name}: a recording needs at least one track")
        index = {tr.id: i for i, tr in enumerate(self.tracks)}
        if len(index) != len(self.tracks):
            raise ValueError(f"{self.name}: duplicate track ids")
        object.__setattr__(self, "_index", index)

    @property
    def name(self) -> str:
        """The file's stem, or ``recording``."""
        return self.source.stem if self.source is not None else "recording"

    @property
    def ids(self) -> NDArray[np.int64]:
        """Track ids ``(P,)`` in the recording's order."""
        return np.array([tr.id for tr in self.tracks], dtype=np.int64)

    def track(self, person_id: int) -> Track:
        """The track of ``person_id`` (raises KeyError for an unknown id)."""
        return self.tracks[self._index[int(person_id)]]

    @property
    def start_time(self) -> float:
        """Time of the recording's first sample (s)."""
        return min(tr.start_time for tr in self.tracks)

    @property
    def end_time(self) -> float:
        """Time of the recording's last sample (s)."""
        return max(tr.end_time for tr in self.tracks)

    @property
    def area(self) -> Area:
        """The annotated area (bounding box of all recorded positions)."""
        allp = np.concatenate([tr.positions for tr in self.tracks])
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        return Area(float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    def active_ids(self, t0: float, t1: float) -> NDArray[np.int64]:
        """Ids ``(Q,)`` of the tracks that have any sample span overlapping ``[t0, t1]`` (s)."""
        return np.array(
            [tr.id for tr in self.tracks if tr.end_time >= t0 and tr.start_time <= t1],
            dtype=np.int64,
        )

    def states(self, times: FloatArray, ids: NDArray[np.int64] | None = None) -> CrowdState:
        """Everyone (or ``ids``) at ``times (T,)`` s; see the module docstring for the rules."""
        t = np.asarray(times, dtype=float).reshape(-1)
        chosen = self.ids if ids is None else np.asarray(ids, dtype=np.int64).reshape(-1)
        n, p = t.shape[0], chosen.shape[0]
        pos = np.full((n, p, 2), np.nan)
        vel = np.full((n, p, 2), np.nan)
        head = np.full((n, p), np.nan)
        for j, pid in enumerate(chosen):
            tr = self.track(int(pid))
            present = self._present(tr, t)
            if not present.any():
                continue
            tt = t[present]
            for d in range(2):
                pos[present, j, d] = np.interp(tt, tr.times, tr.positions[:, d])
                vel[present, j, d] = np.interp(tt, tr.times, tr.velocities[:, d])
            head[present, j] = np.interp(tt, tr.times, tr.headings)
        head = np.where(np.isnan(head), np.nan, np.angle(np.exp(1j * np.nan_to_num(head))))
        return CrowdState(t, chosen, pos, vel, head, ~np.isnan(pos[..., 0]))

    def state_at(self, time: float, ids: NDArray[np.int64] | None = None) -> CrowdState:
        """:meth:`states` at one instant (``T = 1``)."""
        return self.states(np.array([float(time)]), ids)

    def _present(self, tr: Track, t: FloatArray) -> NDArray[np.bool_]:
        inside = (t >= tr.start_time) & (t <= tr.end_time)
        if len(tr.times) < 2:
            return inside
        k = np.clip(np.searchsorted(tr.times, t, side="right") - 1, 0, len(tr.times) - 2)
        gap = tr.times[k + 1] - tr.times[k]
        on_sample = np.isclose(t, tr.times[k]) | np.isclose(t, tr.times[k + 1])
        return inside & ((gap <= self.max_gap + 1e-9) | on_sample)

    def destination(self, person_id: int) -> FloatArray:
        """A person's recorded destination: their last position ``(2,)`` m."""
        return self.track(person_id).positions[-1].copy()

    def main_flow(self) -> FloatArray:
        """Unit vector ``(2,)`` of the crowd's main walking axis: the principal axis of every
        track's displacement (first to last sample), sign-free (a flow and its reverse)."""
        disp = np.array([tr.positions[-1] - tr.positions[0] for tr in self.tracks])
        disp = disp[np.hypot(disp[:, 0], disp[:, 1]) > 1.0]
        if len(disp) == 0:
            return np.array([1.0, 0.0])
        _, _, vt = np.linalg.svd(disp, full_matrices=False)
        axis = vt[0] / np.linalg.norm(vt[0])
        return axis if axis[np.argmax(np.abs(axis))] > 0 else -axis

    def groups_at(self, present_ids: NDArray[np.int64]) -> tuple[tuple[int, ...], ...]:
        """Groups restricted to ``present_ids``; groups with fewer than two present dropped."""
        keep = {int(i) for i in present_ids}
        out = []
        for g in self.groups:
            members = tuple(m for m in g if m in keep)
            if len(members) >= 2:
                out.append(members)
        return tuple(out)

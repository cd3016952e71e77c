"""People tracks from anonymous detections: ids by association, velocities by an α-β filter.

A ``geometry_msgs/PoseArray`` on ``/people`` carries positions (and maybe orientations) but no
ids and no velocities; the planner needs both (the social context's :class:`Person` has an
``id`` and a ``velocity``). This module turns one detection set per message into stable tracks.
It has no ROS imports, so it is tested in the main environment.

Method:
- **Prediction**: each track moves at its estimated velocity to the message time.
- **Association**: the globally cheapest one-to-one assignment of detections to predicted
  tracks (Hungarian algorithm, ``scipy.optimize.linear_sum_assignment``) on Euclidean distance,
  gated: a pair farther apart than ``gate`` (m) is never assigned. This is global nearest
  neighbour (GNN) data association (Blackman & Popoli, *Design and Analysis of Modern Tracking
  Systems*, 1999, §6.2).
- **Velocity**: an α-β filter (Kalata, "The tracking index", IEEE TAES 20(2), 1984) on position,
  ``x ← x̂ + α r``, ``v ← v + (β / dt) r`` with residual ``r = z − x̂``. A new track's velocity is
  zero; its second observation sets it to the finite difference, the filter runs from the third.
  Speeds are clipped to ``max_speed`` (a tracker glitch must not become a 10 m/s person).
- **Orientation**: a person moving faster than ``moving_speed`` faces the direction of motion;
  a slower one keeps the orientation the detection carries (``yaws``), or the last one known.
- **Lifetime**: a track unseen for ``timeout`` s is dropped; ids are never reused.

Units: metres, seconds, radians, in the frame of the detections (the node's global frame).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import linear_sum_assignment

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.scene import HUMAN_RADIUS, Person

__all__ = ["PeopleTracker", "Track", "TrackerParams"]


@dataclass(frozen=True)
class TrackerParams:
    """``gate`` (m), ``timeout`` (s), ``alpha``, ``beta`` (dimensionless, 0 < α ≤ 1,
    0 < β < 2), ``max_speed`` (m/s), ``moving_speed`` (m/s), ``radius`` (m) of every person."""

    gate: float = 1.0
    timeout: float = 1.0
    alpha: float = 0.5
    beta: float = 0.2
    max_speed: float = 3.0
    moving_speed: float = 0.2
    radius: float = HUMAN_RADIUS

    def __post_init__(self) -> None:
        for name in ("gate", "timeout", "max_speed", "radius"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigurationError(f"tracker {name} must be positive, got {value}")
        if not (0 < self.alpha <= 1):
            raise ConfigurationError(f"tracker alpha must be in (0, 1], got {self.alpha}")
        if not (0 < self.beta < 2):
            raise ConfigurationError(f"tracker beta must be in (0, 2), got {self.beta}")
        if not (math.isfinite(self.moving_speed) and self.moving_speed >= 0):
            raise ConfigurationError(f"tracker moving_speed must be >= 0, got {self.moving_speed}")


@dataclass
class Track:
    """One person: ``position (2,)`` m, ``velocity (2,)`` m/s, ``yaw`` rad, ``last_seen`` s,
    ``hits`` (observations so far)."""

    id: int
    position: FloatArray
    velocity: FloatArray
    yaw: float
    last_seen: float
    hits: int = 1


class PeopleTracker:
    """Keeps :class:`Track` s across detection messages (see the module docstring).

    ``update`` never raises on well-typed input: non-finite detections are dropped and counted
    in ``dropped``; a message not newer than the previous one is ignored.
    """

    def __init__(self, params: TrackerParams | None = None) -> None:
        self.params = params or TrackerParams()
        self.tracks: list[Track] = []
        self.dropped = 0
        self._next_id = 1
        self._time = -math.inf

    def reset(self) -> None:
        """Forget every track (ids keep counting up)."""
        self.tracks = []
        self._time = -math.inf

    @property
    def time(self) -> float:
        """Stamp (s) of the last accepted message; ``-inf`` before the first."""
        return self._time

    def update(self, time: float, positions: ArrayLike, yaws: ArrayLike | None = None) -> None:
        """Fold in one detection set: ``positions (K, 2)`` m and optional ``yaws (K,)`` rad
        (``NaN`` = unknown orientation), all observed at ``time`` s."""
        time = float(time)
        if not math.isfinite(time) or time <= self._time:
            return
        z = np.asarray(positions, dtype=float).reshape(-1, 2)
        yaw_in = np.full(z.shape[0], np.nan) if yaws is None else np.asarray(yaws, dtype=float)
        yaw_in = yaw_in.reshape(-1)
        if yaw_in.shape[0] != z.shape[0]:
            raise ConfigurationError(f"{z.shape[0]} positions but {yaw_in.shape[0]} yaws")
        finite = np.all(np.isfinite(z), axis=1) & (np.abs(z) < 1e7).all(axis=1)
        self.dropped += int(np.count_nonzero(~finite))
        z, yaw_in = z[finite], yaw_in[finite]
        p = self.params
        self.tracks = [t for t in self.tracks if time - t.last_seen <= p.timeout]
        dts = np.array([time - t.last_seen for t in self.tracks])
        predicted = np.array(
            [t.position + t.velocity * dt for t, dt in zip(self.tracks, dts, strict=True)]
        ).reshape(-1, 2)
        assigned: dict[int, int] = {}
        if self.tracks and z.shape[0]:
            cost = np.hypot(*(predicted[:, None, :] - z[None, :, :]).transpose(2, 0, 1))
            # Gate by making out-of-gate pairs too expensive to be worth taking.
            big = 1e6
            rows, cols = linear_sum_assignment(np.where(cost <= p.gate, cost, big))
            assigned = {
                int(c): int(r) for r, c in zip(rows, cols, strict=True) if cost[r, c] <= p.gate
            }
        for j in range(z.shape[0]):
            if j in assigned:
                track = self.tracks[assigned[j]]
                self._correct(track, predicted[assigned[j]], z[j], yaw_in[j], time)
            else:
                yaw = float(yaw_in[j]) if math.isfinite(yaw_in[j]) else 0.0
                self.tracks.append(Track(self._next_id, z[j].copy(), np.zeros(2), yaw, time))
                self._next_id += 1
        self._time = time

    def _correct(
        self, track: Track, predicted: FloatArray, z: FloatArray, yaw: float, time: float
    ) -> None:
        p = self.params
        dt = time - track.last_seen
        if track.hits == 1:
            velocity = (z - track.position) / dt
            position = z.copy()
        else:
            residual = z - predicted
            position = predicted + p.alpha * residual
            velocity = track.velocity + (p.beta / dt) * residual
        speed = float(np.hypot(*velocity))
        if speed > p.max_speed:
            velocity = velocity * (p.max_speed / speed)
            speed = p.max_speed
        if speed > p.moving_speed:
            track.yaw = math.atan2(velocity[1], velocity[0])
        elif math.isfinite(yaw):
            track.yaw = float(yaw)
        track.position, track.velocity = position, velocity
        track.last_seen, track.hits = time, track.hits + 1

    def people(self, time: float | None = None) -> tuple[Person, ...]:
        """The tracks as planner :class:`Person` s, predicted to ``time`` s (default: the last
        message's stamp), ordered by id."""
        out = []
        for t in sorted(self.tracks, key=lambda t: t.id):
            dt = 0.0 if time is None else max(0.0, float(time) - t.last_seen)
            xy = t.position + t.velocity * dt
            out.append(
                Person(
                    id=t.id,
                    position=(float(xy[0]), float(xy[1])),
                    velocity=(float(t.velocity[0]), float(t.velocity[1])),
                    yaw=float(t.yaw),
                    radius=self.params.radius,
                )
            )
        return tuple(out)

"""The per-cycle social-context estimator: people's tracks in, a :class:`SocialContext` out.

Banisetty et al. assume "the robot has prior knowledge of the on-going interaction" and name
removing that assumption as future work; this module removes it. Every control cycle:

1. **Tracks.** Each track is smoothed by a constant-velocity α filter (Kalata, "The tracking
   index", IEEE T-AES 1984): the position predicted from the last estimate and the measured
   velocity is corrected by ``smoothing`` × the innovation; velocity and heading likewise. A
   standing person's estimate is the running mean of their observations (gain ``1/n``,
   floored at ``standing_smoothing``). An innovation beyond ``gate`` (m: an id switch, a new
   person; ``standing_gate`` for a person standing: their noise is all it may hold) or a
   heading turn beyond 90° restarts the track at the measurement. People missed
   for at most ``coast_time`` (s) are coasted at their last velocity, so missed detections do
   not break up a group. Without smoothing, a 0.05 m position noise on three members of an
   arc makes their fitted circle, and so the join spot, jump by metres. A track slower than
   ``still_speed`` is reported with zero velocity: what is left of the velocity noise after
   smoothing (about 1 cm/s) otherwise made a standing person "oncoming" to the planner, which
   then held back beside them (paper ``hallway_stationary``, Pioneer, stalled to the time
   limit).

   **Velocity from positions** (``velocity_source="positions"``, for sources whose velocities
   are missing or are raw finite differences). A tracker that differences consecutive
   positions turns a standing person's few centimetres of jitter into a speed of jitter / Δt
   (5.5 cm at 10 Hz: 0.55 m/s, "walking"), so the standing test depends on the frame rate.
   Instead, each track's velocity is the least-squares slope of its raw positions over the
   last ``velocity_window`` seconds (at least the last ``velocity_min_samples`` samples, so a
   slow frame rate still has a fit), and a person counts as moving only when the slope's
   lower confidence bound, ``|v̂| − motion_z · SE``, reaches the standing speed and the
   fitted displacement over the window, ``|v̂| · span``, reaches ``leave_distance`` (0.5 m,
   about the width of the ring an F-formation's members stand in, Kendon's p-space: members
   shift within it while they converse; a walker at 1 m/s covers it in 0.5 s);
   ``SE = s / √Σ(t − t̄)²`` is the slope's standard error, ``s`` the residual standard
   deviation of the fit floored at ``position_jitter`` (a constant-velocity model over the
   window; the standard error of an ordinary least-squares slope, Draper and Smith,
   *Applied Regression Analysis*, 3rd ed., 1998, ch. 1). The
   test asks whether the displacement over the history is larger than the jitter explains,
   which a frame spacing cannot change: the noise of the slope falls as the window spans
   more time, whether in many short steps or few long ones. A new track (one sample) is
   standing until it has shown motion. Moving tracks report the slope (not filtered again:
   the α filter's gain is per update, so its lag would depend on the frame rate), standing
   ones zero. The price is latency: a walker is found walking once they have covered
   ``leave_distance`` beyond the jitter (0.4–1 s), so on ETH hotel and UCY zara01, whose
   files carry velocities, walking-group recall falls from 0.86 / 0.85 to 0.75 / 0.73
   (``bench_context.py``); the default stays ``measured``, the simulator's and a filtering
   tracker's velocities.
2. **Detection**, in pipeline order, each detector seeing only people that earlier ones did not
   claim: queues at a desk of the map, artwork viewers (:mod:`.viewers`), queues without a
   desk (:mod:`.queues`; a line of people facing an artwork is its viewers), F-formations
   (:mod:`.fformations`, GCFF), walking groups (:mod:`.walking`). Detectors are registry
   entries (:data:`~socialnav.social.perception.base.DETECTORS`), one module each.
3. **Hysteresis** (:mod:`.tracking`): structures carry a confidence and switch on and off with
   two thresholds.
4. **Output**: the planner's own types, so it consumes them unchanged — F-formations as
   :class:`~socialnav.core.scene.Group` (``mode`` = ``group_mode``), walking groups as groups
   with ``mode="walking"`` (kept whole, never joined), queues as
   :class:`~socialnav.core.scene.Queue` (head → tail, service point from the map or the head's
   heading), viewers as the ``viewer_ids`` of the map's artworks. A person is in at most one
   structure (the most confident wins).

Positions in metres in the world frame, yaw CCW from +x; times in seconds.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.geometry import FloatArray
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.social.perception import (  # noqa: F401
    dominant_sets,
    fformations,
    queues,
    viewers,
    walking,
)
from socialnav.social.perception.base import (
    DETECTORS,
    STANDING_SPEED,
    Candidate,
    Detector,
    MapKnowledge,
    StructureKind,
    TrackFrame,
    check_number,
)
from socialnav.social.perception.tracking import (
    HysteresisParams,
    StructureTracker,
    check_hysteresis,
)

DEFAULT_PIPELINE: tuple[str, ...] = (
    "desk_queue",
    "viewers",
    "queue",
    "fformation",
    "walking_group",
)
#: Queue spacing handed to the planner is clipped to this range (m): the tail slot must stay a
#: plausible place to stand even when the members' gaps are noisy.
SPACING_RANGE = (0.5, 1.2)


def _still(p: Person, speed: float) -> Person:
    """``p`` with its velocity zeroed when it is below ``speed`` (m/s)."""
    if math.hypot(*p.velocity) >= speed:
        return p
    return Person(p.id, p.position, (0.0, 0.0), p.yaw, p.radius)


VelocitySource = Literal["measured", "positions"]


def history_velocity(
    times: FloatArray,
    positions: FloatArray,
    *,
    jitter: float,
    z: float,
    min_displacement: float = 0.0,
    standing_speed: float = STANDING_SPEED,
) -> tuple[float, float]:
    """The velocity (m/s, world frame) of one track from its raw positions ``(N, 2)`` (m) at
    ``times (N,)`` (s): the least-squares slope when its lower confidence bound
    ``|v̂| − z · SE`` reaches ``standing_speed`` and the fitted displacement over the samples'
    time span, ``|v̂| · (t_N − t_1)``, reaches ``min_displacement`` (m), else ``(0, 0)``
    (standing: the motion is no larger than the jitter explains, or the person has not left
    their spot). ``SE = s / √Σ(t − t̄)²``, ``s`` the residual standard deviation per axis
    (``N − 2`` degrees of freedom) floored at ``jitter`` (m). Fewer than two samples, or all
    at one time, give ``(0, 0)``. See the module docstring."""
    t = np.asarray(times, dtype=float)
    xy = np.asarray(positions, dtype=float).reshape(-1, 2)
    n = t.size
    if n < 2:
        return (0.0, 0.0)
    dt = t - t.mean()
    sxx = float(dt @ dt)
    if sxx <= 1e-12:
        return (0.0, 0.0)
    centred = xy - xy.mean(axis=0)
    v = dt @ centred / sxx
    s = jitter
    if n > 2:
        residual = centred - np.outer(dt, v)
        s = max(jitter, float(np.sqrt((residual * residual).sum() / (2.0 * (n - 2)))))
    speed = float(np.hypot(v[0], v[1]))
    if speed - z * s / np.sqrt(sxx) < standing_speed or speed * (t[-1] - t[0]) < min_displacement:
        return (0.0, 0.0)
    return (float(v[0]), float(v[1]))


def _wrap(angle: float) -> float:
    """:func:`~socialnav.core.geometry.wrap_angle` of one float (the same formula)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@dataclass(frozen=True)
class EstimatorParams:
    """``coast_time`` (s), ``smoothing`` (α in (0, 1]; 1 = raw measurements),
    ``standing_smoothing`` (the floor of α for standing people), ``gate`` (m),
    ``standing_gate`` (m: the gate of a standing person's track, about 6 σ of the default
    0.05 m position noise of :mod:`socialnav.sim.perception`), ``still_speed`` (m/s: a track
    slower than this is reported still, velocity zero), ``velocity_source`` (``measured``:
    the tracks' own velocities, as a filtering tracker reports them; ``positions``: each
    track's velocity and standing test from its position history, :func:`history_velocity`,
    for raw or velocity-less tracks), with ``velocity_window`` (s),
    ``velocity_min_samples``, ``position_jitter`` (m: the floor of the position noise, the
    default 0.05 m of :mod:`socialnav.sim.perception`) and ``motion_z`` (the confidence
    multiplier of the slope's standard error: 2, about 97.7 % one-sided), ``leave_distance``
    (m: the displacement over the window that a moving person must have covered, 0.5 m),
    the detector ``pipeline`` (registry names, in order),
    ``detector_params`` (name → keyword overrides), ``hysteresis``, ``group_mode`` (mode of
    detected F-formations: ``join`` or ``lead``, the robot's task with a group)."""

    coast_time: float = 0.6
    smoothing: float = 0.2
    standing_smoothing: float = 0.02
    gate: float = 1.0
    standing_gate: float = 0.3
    still_speed: float = 0.05
    velocity_source: VelocitySource = "measured"
    velocity_window: float = 1.0
    velocity_min_samples: int = 3
    position_jitter: float = 0.05
    motion_z: float = 2.0
    leave_distance: float = 0.5
    pipeline: tuple[str, ...] = DEFAULT_PIPELINE
    detector_params: dict[str, dict[str, Any]] = field(default_factory=dict)
    hysteresis: HysteresisParams = field(default_factory=HysteresisParams)
    group_mode: str = "join"


#: the numeric estimator parameters and their admissible ranges: (low, high, low excluded)
_RANGES: dict[str, tuple[float, float, bool]] = {
    "coast_time": (0.0, math.inf, False),
    "smoothing": (0.0, 1.0, True),
    "standing_smoothing": (0.0, 1.0, True),
    "gate": (0.0, math.inf, True),
    "standing_gate": (0.0, math.inf, True),
    "still_speed": (0.0, math.inf, False),
    "position_jitter": (0.0, math.inf, False),
    "motion_z": (0.0, math.inf, False),
    "leave_distance": (0.0, math.inf, False),
    "velocity_window": (0.0, math.inf, False),
}


def _check_ranges(params: EstimatorParams) -> None:
    """Raise ConfigurationError naming the first parameter outside its range (NaN included),
    a pipeline that is not a sequence of detector names, ``detector_params`` for a detector
    the pipeline does not run, or hysteresis settings out of range."""
    if isinstance(params.pipeline, str) or not all(isinstance(n, str) for n in params.pipeline):
        raise ConfigurationError(
            f"estimator pipeline must be a sequence of detector names, got {params.pipeline!r}"
        )
    stray = sorted(set(params.detector_params) - set(params.pipeline))
    if stray:
        raise ConfigurationError(
            f"detector_params for {', '.join(stray)}, which the pipeline "
            f"({', '.join(params.pipeline)}) does not run"
        )
    count = params.velocity_min_samples
    if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 2:
        raise ConfigurationError(f"velocity_min_samples must be an integer >= 2, got {count!r}")
    check_hysteresis(params.hysteresis)
    for name, (low, high, low_open) in _RANGES.items():
        check_number(
            f"estimator parameter {name}", getattr(params, name), low, high, low_open=low_open
        )


@dataclass(frozen=True)
class Structure:
    """One estimated structure: ``kind``, ``members`` (ids present in the context),
    ``confidence`` in [0, 1], ``track_id`` (stable over time), ``geometry``."""

    kind: StructureKind
    members: tuple[int, ...]
    confidence: float
    track_id: int
    geometry: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Estimate:
    """The estimator's answer at ``time``: ``context`` for the planner, ``structures`` with
    their confidences, and the ``candidates`` of this frame (before hysteresis)."""

    time: float
    context: SocialContext
    structures: tuple[Structure, ...]
    candidates: tuple[Candidate, ...] = ()


class ContextEstimator:
    """Stateful: call :meth:`update` once per cycle with the tracked people.

    ``knowledge``: artworks and service points from the map. Raises
    :class:`~socialnav.core.errors.ConfigurationError` for an unknown detector name.
    """

    def __init__(
        self, knowledge: MapKnowledge | None = None, params: EstimatorParams | None = None
    ) -> None:
        self.knowledge = knowledge or MapKnowledge()
        self.params = params or EstimatorParams()
        if self.params.group_mode not in ("join", "lead"):
            raise ConfigurationError(f"group_mode must be join or lead: {self.params.group_mode}")
        if self.params.velocity_source not in ("measured", "positions"):
            raise ConfigurationError(
                f"velocity_source must be measured or positions: {self.params.velocity_source}"
            )
        _check_ranges(self.params)
        self.detectors: list[tuple[str, Detector]] = [
            (name, DETECTORS.get(name)(**self.params.detector_params.get(name, {})))
            for name in self.params.pipeline
        ]
        self.tracker = StructureTracker(self.params.hysteresis)
        self.reset()

    def reset(self) -> None:
        """Forget every track and structure (a new episode)."""
        self.tracker.reset()
        for _, detector in self.detectors:
            reset = getattr(detector, "reset", None)  # detectors with state across cycles
            if callable(reset):
                reset()
        self._last_seen: dict[int, tuple[float, Person]] = {}
        self._standing: dict[int, int] = {}
        self._history: dict[int, deque[tuple[float, float, float]]] = {}

    def _from_history(self, time: float, p: Person) -> Person:
        """``p`` with its velocity replaced by :func:`history_velocity` of its track's raw
        positions over the window (``velocity_source="positions"``)."""
        prm = self.params
        h = self._history.setdefault(p.id, deque())
        if h and time <= h[-1][0]:
            h.pop()  # a repeated time: the newer measurement replaces it
        h.append((time, float(p.position[0]), float(p.position[1])))
        # the samples of the last velocity_window seconds, but never fewer than min_samples
        while len(h) > prm.velocity_min_samples and h[0][0] < time - prm.velocity_window - 1e-9:
            h.popleft()
        arr = np.array(h)
        v = history_velocity(
            arr[:, 0],
            arr[:, 1:],
            jitter=prm.position_jitter,
            z=prm.motion_z,
            min_displacement=prm.leave_distance,
        )
        return Person(p.id, p.position, v, p.yaw, p.radius)

    def _standing_track_at(
        self, pid: int, x: float, y: float, counts: dict[int, int]
    ) -> tuple[Person, int] | None:
        """The last estimate and count of the standing track (another id) nearest ``(x, y)``
        within ``standing_gate``, or None."""
        best: tuple[float, Person, int] | None = None
        for other, (_, q) in self._last_seen.items():
            n = counts.get(other, 0)
            if other == pid or n == 0:
                continue
            d = math.hypot(x - q.position[0], y - q.position[1])
            if d <= self.params.standing_gate and (best is None or d < best[0]):
                best = (d, q, n)
        return None if best is None else (best[1], best[2])

    def _smooth(self, time: float, p: Person, counts: dict[int, int]) -> Person:
        last = self._last_seen.get(p.id)
        a = self.params.smoothing
        if last is None or a >= 1.0 or time <= last[0]:
            self._standing[p.id] = 0
            return p
        # plain floats: one person's 2-vectors are far cheaper than NumPy calls here
        dt, q = time - last[0], last[1]
        px = q.position[0] + dt * q.velocity[0]
        py = q.position[1] + dt * q.velocity[1]
        zx, zy = float(p.position[0]), float(p.position[1])
        innovation = math.hypot(zx - px, zy - py)
        standing = max(math.hypot(*p.velocity), math.hypot(*q.velocity)) < STANDING_SPEED
        n_prior = counts.get(p.id, 0)
        if standing and n_prior > 0:
            # gated at where they stood: an id switch between neighbours 0.5-1 m apart is
            # inside ``gate`` but far outside the noise; averaged in, it slid both tracks
            # across for seconds and bent the group's circle. The measurement takes over the
            # estimate of the standing track it falls on (the id switched, the person did
            # not move), else the track restarts.
            innovation = math.hypot(zx - q.position[0], zy - q.position[1])
            if innovation > self.params.standing_gate:
                other = self._standing_track_at(p.id, zx, zy, counts)
                if other is None:
                    self._standing[p.id] = 0
                    return p
                q, n_prior = other
                px, py, innovation = q.position[0], q.position[1], 0.0
        if innovation > self.params.gate:
            self._standing[p.id] = 0
            return p
        if standing:
            # a standing person: the running mean of their observations (the Kalman gain of a
            # static target, 1/n), floored at standing_smoothing so they can still move away.
            # Predicted where they stood: integrating the (noise-only) velocity estimate would
            # drift the mean by (1 - a) / a · dt · v, 4-5 cm at the floor gain.
            px, py = float(q.position[0]), float(q.position[1])
            n = n_prior + 1
            self._standing[p.id] = n
            a = max(1.0 / (n + 1), self.params.standing_smoothing)
        else:
            self._standing[p.id] = 0
        x = (px + a * (zx - px), py + a * (zy - py))
        if self.params.velocity_source == "positions":
            v = p.velocity  # already a fit over the window: another filter only adds lag
        else:
            v = (
                q.velocity[0] + a * (p.velocity[0] - q.velocity[0]),
                q.velocity[1] + a * (p.velocity[1] - q.velocity[1]),
            )
        turn = _wrap(p.yaw - q.yaw)
        # a turn beyond 90° is taken as measured (averaging opposite headings never flips)
        yaw = p.yaw if abs(turn) > math.pi / 2 else _wrap(q.yaw + a * turn)
        return Person(
            p.id, (float(x[0]), float(x[1])), (float(v[0]), float(v[1])), float(yaw), p.radius
        )

    def _tracks(self, time: float, people: Sequence[Person]) -> list[Person]:
        if self.params.velocity_source == "positions":
            people = [self._from_history(time, p) for p in people]
        counts = dict(self._standing)  # before this cycle: id switches look up each other
        people = [self._smooth(time, p, counts) for p in people]
        for p in people:
            self._last_seen[p.id] = (time, p)
        seen = {p.id for p in people}
        out = list(people)
        for pid, (t, p) in list(self._last_seen.items()):
            if pid in seen:
                continue
            age = time - t
            if age > self.params.coast_time or age < 0:
                del self._last_seen[pid]
                self._history.pop(pid, None)
                continue
            x = (p.position[0] + age * p.velocity[0], p.position[1] + age * p.velocity[1])
            out.append(Person(p.id, x, p.velocity, p.yaw, p.radius))
        return out

    def detect(self, frame: TrackFrame) -> list[Candidate]:
        """Every detector's candidates for one frame, claims passed down the pipeline."""
        claimed: set[int] = set()
        out: list[Candidate] = []
        for _, detector in self.detectors:
            found = detector(frame, self.knowledge, frozenset(claimed))
            for cand in found:
                claimed.update(cand.members)
            out.extend(found)
        return out

    def update(self, time: float, people: Sequence[Person]) -> Estimate:
        """The estimate at ``time`` (s) from the people tracked now (``Person`` objects).

        Structures are confirmed and dropped over time (the hysteresis of
        :class:`~socialnav.social.perception.tracking.HysteresisParams`), so calls must advance
        ``time``: calls at one repeated time confirm nothing; a time earlier than the last one
        restarts the tracks. Raises :class:`~socialnav.core.errors.InvalidInputError` for a
        time that is not a finite number, or ids repeated within the frame.
        """
        if (
            isinstance(time, bool)
            or not isinstance(time, int | float | np.number)
            or not (math.isfinite(float(time)))
        ):
            raise InvalidInputError(
                f"estimator time must be a finite number of seconds, got {time!r}"
            )
        tracked = [_still(p, self.params.still_speed) for p in self._tracks(float(time), people)]
        frame = TrackFrame.from_people(tracked, float(time))
        candidates = self.detect(frame)
        active = self.tracker.update(float(time), candidates)
        present = {p.id for p in tracked}
        used: set[int] = set()
        structures: list[Structure] = []
        groups: list[Group] = []
        queue_list: list[Queue] = []
        viewers_of: dict[int, list[int]] = {}
        for track in sorted(active, key=lambda t: (-t.confidence, t.track_id)):
            members = tuple(m for m in track.members if m in present and m not in used)
            minimum = 1 if track.kind in ("viewers", "queue") else 2
            if len(members) < minimum:
                continue
            if track.kind == "queue" and len(members) == 1 and not track.geometry.get("from_map"):
                continue
            used.update(members)
            structures.append(
                Structure(track.kind, members, track.confidence, track.track_id, track.geometry)
            )
            if track.kind == "fformation":
                groups.append(Group(members, self.params.group_mode))
            elif track.kind == "walking_group":
                groups.append(Group(members, "walking"))
            elif track.kind == "queue":
                spacing = float(np.clip(track.geometry.get("spacing", 0.8), *SPACING_RANGE))
                queue_list.append(Queue(members, tuple(track.anchor), spacing))
            elif track.kind == "viewers":
                viewers_of.setdefault(int(track.anchor), []).extend(members)
        artworks = tuple(
            Artwork(a.center, a.width, a.facing, tuple(viewers_of.get(i, ())))
            for i, a in enumerate(self.knowledge.artworks)
        )
        context = SocialContext(tuple(tracked), tuple(groups), tuple(queue_list), artworks)
        return Estimate(float(time), context, tuple(structures), tuple(candidates))


def estimate_once(
    people: Sequence[Person],
    knowledge: MapKnowledge | None = None,
    params: EstimatorParams | None = None,
) -> Estimate:
    """The estimate from one frame alone, without hysteresis: every candidate is a structure
    with its frame score as confidence (offline evaluation of single images)."""
    est = ContextEstimator(
        knowledge,
        params or EstimatorParams(hysteresis=HysteresisParams(time_constant=0.0, on=0.0, off=0.0)),
    )
    return est.update(0.0, people)

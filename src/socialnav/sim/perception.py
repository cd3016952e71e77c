"""A people detector and tracker as the robot would have it: noisy, lossy tracks.

The simulator knows every person exactly; a robot sees tracks from a detector (laser leg
detector, camera) and a tracker. :class:`PerceptionModel` turns the true people of one control
cycle into such tracks. Each effect is a seeded option (all off when 0):

- ``position_sigma`` (m): Gaussian noise on each position, per axis;
- ``heading_sigma`` (rad): Gaussian noise on each heading (body orientation);
- ``velocity_sigma`` (m/s): Gaussian noise on each velocity, per axis;
- ``miss_probability``: a person is not reported this cycle (independently per person and cycle);
- ``false_positive_rate``: expected false detections per cycle (Poisson), placed uniformly in
  ``bounds``, standing, with fresh ids that never collide with people's ids;
- ``id_switch_probability``: per cycle, the chance that two people closer than
  ``id_switch_distance`` (m) swap track ids for the rest of the episode (a tracker's classic
  association error).

The defaults (:data:`DEFAULT_PERCEPTION`: 0.05 m, 10°, 0.05 m/s, 3 % misses, 0.02 false
positives per cycle, 0.2 % id switches per cycle) are an assumption for a good people tracker
at a few metres (2D laser leg detection or RGB-D body detection), not a measurement of a
particular sensor. The suites' ``--context detected`` runs use them; other values go through
the Python API (``run_episode(..., context="detected", perception=PerceptionNoise(...))``,
``run_crowd_episode(..., perception=...)``), and ``socialnav detect --noise none`` turns
them all off.
Positions in metres, world frame; yaw CCW from +x.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.scene import HUMAN_RADIUS, Person

#: Track ids of false positives start here (scenario ids are small integers).
FALSE_POSITIVE_ID_BASE = 1_000_000


@dataclass(frozen=True)
class PerceptionNoise:
    """The options of the module docstring."""

    position_sigma: float = 0.05
    heading_sigma: float = np.radians(10.0)
    velocity_sigma: float = 0.05
    miss_probability: float = 0.03
    false_positive_rate: float = 0.02
    id_switch_probability: float = 0.002
    id_switch_distance: float = 1.0

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            if not np.isfinite(value) or value < 0:
                raise ValueError(f"perception option {name} must be finite and >= 0: {value}")
        if self.miss_probability > 1 or self.id_switch_probability > 1:
            raise ValueError("probabilities must be at most 1")


DEFAULT_PERCEPTION = PerceptionNoise()
#: Perfect perception: tracks equal the true people.
EXACT_PERCEPTION = PerceptionNoise(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


class PerceptionModel:
    """Stateful (id switches persist): call :meth:`observe` once per control cycle.

    ``bounds`` ``(xmin, ymin, xmax, ymax)`` (m) is where false positives appear; ``seed`` seeds
    every random choice.
    """

    def __init__(
        self,
        noise: PerceptionNoise = DEFAULT_PERCEPTION,
        bounds: tuple[float, float, float, float] = (0.0, 0.0, 10.0, 10.0),
        seed: int = 0,
    ) -> None:
        x0, y0, x1, y1 = (float(v) for v in bounds)
        # False positives are drawn uniformly in the bounds: NaN or infinite ones (a record's
        # absent people) would fail inside NumPy's sampler, mid-episode.
        if not all(np.isfinite(v) for v in (x0, y0, x1, y1)) or x1 < x0 or y1 < y0:
            raise ValueError(f"perception bounds must be finite with min ≤ max, got {bounds}")
        self.noise = noise
        self.bounds = (x0, y0, x1, y1)
        self.seed = seed
        self.reset()

    def reset(self) -> None:
        self.rng = np.random.default_rng(self.seed)
        self._alias: dict[int, int] = {}
        self._next_fp = FALSE_POSITIVE_ID_BASE

    def observe(
        self,
        ids: np.ndarray,
        positions: FloatArray,
        velocities: FloatArray,
        yaws: FloatArray,
        radii: FloatArray | None = None,
    ) -> list[Person]:
        """Tracks from the true ``ids (K,)``, ``positions (K, 2)``, ``velocities (K, 2)``,
        ``yaws (K,)`` and ``radii (K,)`` of one cycle."""
        n, rng = self.noise, self.rng
        k = len(ids)
        ids = np.asarray(ids, dtype=np.int64)
        pos = np.asarray(positions, dtype=float).reshape(k, 2)
        vel = np.asarray(velocities, dtype=float).reshape(k, 2)
        yaw = np.asarray(yaws, dtype=float).reshape(k)
        rad = np.full(k, HUMAN_RADIUS) if radii is None else np.asarray(radii, dtype=float)
        if k >= 2 and n.id_switch_probability > 0 and rng.random() < n.id_switch_probability:
            d = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
            np.fill_diagonal(d, np.inf)
            close = np.argwhere(np.triu(d < n.id_switch_distance))
            if close.size:
                a, b = (int(ids[i]) for i in close[rng.integers(close.shape[0])])
                ta, tb = self._alias.get(a, a), self._alias.get(b, b)
                self._alias[a], self._alias[b] = tb, ta
        pos = pos + rng.normal(0.0, n.position_sigma, pos.shape) if n.position_sigma else pos
        vel = vel + rng.normal(0.0, n.velocity_sigma, vel.shape) if n.velocity_sigma else vel
        yaw = wrap_angle(yaw + rng.normal(0.0, n.heading_sigma, k)) if n.heading_sigma else yaw
        seen = rng.random(k) >= n.miss_probability if n.miss_probability else np.ones(k, bool)
        out = [
            Person(
                self._alias.get(int(i), int(i)),
                (float(p[0]), float(p[1])),
                (float(v[0]), float(v[1])),
                float(y),
                float(r),
            )
            for i, p, v, y, r, s in zip(ids, pos, vel, yaw, rad, seen, strict=True)
            if s
        ]
        for _ in range(int(rng.poisson(n.false_positive_rate)) if n.false_positive_rate else 0):
            x0, y0, x1, y1 = self.bounds
            where = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)))
            out.append(Person(self._next_fp, where, yaw=float(rng.uniform(-np.pi, np.pi))))
            self._next_fp += 1
        return out

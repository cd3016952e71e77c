"""The recorded episode: what metrics read. Metrics never see the simulator or the planner."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.scene import SocialContext
from socialnav.core.success import ConditionSpec


@dataclass
class EpisodeRecord:
    """One run, sampled every ``dt`` seconds (``T`` samples, ``K`` people).

    Robot:
      ``times (T,)``, ``robot_poses (T, 3)``, ``robot_twists (T, 3)`` (body-frame command
      applied after each sample), ``robot_footprint (V, 2)`` (body frame), ``robot_radius``
      (circumscribed, m).
    People:
      ``people_ids (K,)``, ``people_positions (T, K, 2)``, ``people_velocities (T, K, 2)``,
      ``people_radii (K,)``; ``context`` holds groups, queues and artworks at the start.
      People present for part of an episode (replayed crowds): their positions and velocities
      are NaN at the samples where they are absent; ``people_present (T, K)`` bool is that
      mask (derived from the positions, so it can never disagree with them). Metrics and
      figures ignore absent samples (a distance to an absent person is ``+inf``).
    Task:
      ``start (3,)``; ``goal (3,)`` the goal the robot was given; ``target (3,)`` the pose at
      which success is measured (the target the controller recorded driving to: the social
      goal where the scenario has one, else ``goal``); ``waypoint (2,) | None`` a social
      waypoint to pass (gallery activity); ``goal_tolerance`` (m); ``time_limit`` (s);
      ``family`` (a :data:`~socialnav.core.success.FAMILIES` name) and ``scenario`` name.
    World:
      ``walls (S, 2, 2)`` segments; ``obstacles`` polygons ``(V, 2)``.
    Outcome per sample:
      ``collision_person (T,)``, ``collision_obstacle (T,)`` booleans; ``status (T,)``
      planner status names; ``meta`` free-form (planner, robot, seed, timings).
    Judgement:
      ``success`` the conditions the episode is judged on (family, structures and scenario
      overrides; :mod:`socialnav.core.success`); empty = the family's and structures' defaults.
    """

    dt: float
    times: FloatArray
    robot_poses: FloatArray
    robot_twists: FloatArray
    robot_footprint: FloatArray
    robot_radius: float
    people_ids: np.ndarray
    people_positions: FloatArray
    people_velocities: FloatArray
    people_radii: FloatArray
    start: FloatArray
    goal: FloatArray
    target: FloatArray
    goal_tolerance: float
    time_limit: float
    family: str
    scenario: str
    context: SocialContext = field(default_factory=SocialContext)
    waypoint: FloatArray | None = None
    walls: FloatArray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    obstacles: tuple[FloatArray, ...] = ()
    collision_person: np.ndarray | None = None
    collision_obstacle: np.ndarray | None = None
    status: np.ndarray | None = None
    meta: dict[str, Any] = field(default_factory=dict)
    success: tuple[ConditionSpec, ...] = ()

    def __post_init__(self) -> None:
        steps = self.times.shape[0]
        if self.collision_person is None:
            self.collision_person = np.zeros(steps, dtype=bool)
        if self.collision_obstacle is None:
            self.collision_obstacle = np.zeros(steps, dtype=bool)
        if self.status is None:
            self.status = np.full(steps, "OK", dtype=object)
        k = self.people_ids.shape[0]
        expected = {
            "robot_poses": (steps, 3),
            "robot_twists": (steps, 3),
            "people_positions": (steps, k, 2),
            "people_velocities": (steps, k, 2),
            "people_radii": (k,),
            "collision_person": (steps,),
            "collision_obstacle": (steps,),
            "status": (steps,),
        }
        for name, shape in expected.items():
            if getattr(self, name).shape != shape:
                raise ValueError(f"{name} has shape {getattr(self, name).shape}, expected {shape}")

    @property
    def num_steps(self) -> int:
        """Number of samples ``T``."""
        return int(self.times.shape[0])

    @property
    def people_present(self) -> np.ndarray:
        """``(T, K)`` bool: where each person is present (their position is finite)."""
        return np.asarray(np.isfinite(self.people_positions).all(axis=-1), dtype=bool)

    @property
    def robot_xy(self) -> FloatArray:
        """Robot positions ``(T, 2)`` (m, world frame)."""
        return self.robot_poses[:, :2]

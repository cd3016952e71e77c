"""Forward simulation of every sampled twist at once (ROS ``SimpleTrajectoryGenerator``).

Marder-Eppstein et al. 2010; Banisetty et al., "Trajectory Planning": "for each sampled velocity,
perform a forward simulation from the robot's current state for a short duration".

Decisions and deviations:
- DWA mode: each sample is held constant for the whole ``sim_time`` (no ramp from the current
  velocity); ``velocity`` is accepted for interface symmetry and to size the window elsewhere.
- One **shared** time grid for all samples: the number of steps is ROS's per-sample rule
  ``ceil(max(|v_xy| T / sim_granularity, |w| T / angular_sim_granularity))`` taken at the
  maximum over the batch, so slow samples are simulated more finely than ROS would. The shared
  grid is what lets every critic be plain ``(N, T)`` array code.
- Euler integration body → world with the heading of the previous step, exactly as ROS; poses
  include ``t = 0`` (the current pose), so ``T = steps + 1``. Yaw is wrapped to ``[-pi, pi)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.core.trajectories import Trajectories


class RolloutConfig(Protocol):
    """What :func:`rollout` reads (``RolloutParams`` and ``LocalPlannerParams`` both fit)."""

    @property
    def sim_time(self) -> float:
        """Rollout horizon (s)."""

    @property
    def sim_granularity(self) -> float:
        """Largest translation between rollout poses (m)."""

    @property
    def angular_sim_granularity(self) -> float:
        """Largest rotation between rollout poses (rad)."""


@dataclass(frozen=True)
class RolloutParams:
    """``sim_time`` (s) and the step granularities (m, rad), ROS defaults."""

    sim_time: float = 1.7
    sim_granularity: float = 0.025
    angular_sim_granularity: float = 0.1

    def __post_init__(self) -> None:
        validate_rollout(self)


def validate_rollout(params: RolloutConfig) -> None:
    """Raise ``ValueError`` on non-positive or non-finite rollout parameters."""
    for name in ("sim_time", "sim_granularity", "angular_sim_granularity"):
        value = getattr(params, name)
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be positive, got {value}")


def num_steps(twists: FloatArray, params: RolloutConfig) -> int:
    """Shared number of integration steps (>= 1) for a batch ``(N, 3)``."""
    if twists.shape[0] == 0:
        return 1
    trans = float(np.hypot(twists[:, 0], twists[:, 1]).max())
    rot = float(np.abs(twists[:, 2]).max())
    steps = max(
        trans * params.sim_time / params.sim_granularity,
        rot * params.sim_time / params.angular_sim_granularity,
    )
    return max(1, math.ceil(steps - 1e-9))


def rollout(
    pose: FloatArray,
    velocity: FloatArray,
    twists: FloatArray,
    robot: RobotModel,
    params: RolloutConfig,
    dtype: type = np.float64,
) -> Trajectories:
    """Roll out ``twists (N, 3)`` from ``pose (3,)``: ``Trajectories`` with ``poses (N, T, 3)``.

    ``dtype=np.float32`` halves memory traffic for large batches (positions stay accurate to
    ~1e-6 m within a 10 m window); ``twists`` and ``t`` stay float64.
    """
    del velocity, robot  # DWA mode: constant twist; both kept for the agreed signature
    twists = np.asarray(twists, dtype=float).reshape(-1, 3)
    steps = num_steps(twists, params)
    t = np.linspace(0.0, params.sim_time, steps + 1)
    dt = params.sim_time / steps
    n = twists.shape[0]
    vx: FloatArray
    vy: FloatArray
    w: FloatArray
    vx, vy, w = (twists[:, i : i + 1].astype(dtype) for i in range(3))
    # Heading is exact for a constant twist; position uses the previous step's heading (Euler).
    th = (pose[2] + w * t.astype(dtype)[None, :]).astype(dtype)
    c, s = np.cos(th[:, :-1]), np.sin(th[:, :-1])
    poses: FloatArray = np.empty((n, steps + 1, 3), dtype=dtype)
    poses[:, 0, 0] = pose[0]
    poses[:, 0, 1] = pose[1]
    np.cumsum((vx * c - vy * s) * dtype(dt), axis=1, out=poses[:, 1:, 0])
    np.cumsum((vx * s + vy * c) * dtype(dt), axis=1, out=poses[:, 1:, 1])
    poses[:, 1:, 0] += dtype(pose[0])
    poses[:, 1:, 1] += dtype(pose[1])
    poses[:, :, 2] = wrap_angle(th)
    return Trajectories(twists, poses, t)

"""The batch of candidate trajectories every critic scores at once."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socialnav.core.geometry import FloatArray


@dataclass(frozen=True)
class Trajectories:
    """``N`` candidate rollouts on one shared time grid.

    - ``twists (N, 3)``: the sampled body-frame command ``(vx, vy, wz)`` of each candidate.
    - ``poses (N, T, 3)``: world poses ``(x, y, yaw)``; ``poses[:, k]`` is the pose at ``t[k]``.
      ``t[0] == 0`` is the robot's current pose, so ``poses[:, -1]`` is the end point the paper
      scores.
    - ``t (T,)``: seconds from now, increasing.
    """

    twists: FloatArray
    poses: FloatArray
    t: FloatArray

    def __post_init__(self) -> None:
        n, steps = self.poses.shape[0], self.poses.shape[1]
        shapes_ok = self.twists.shape == (n, 3) and self.t.shape == (steps,)
        if not shapes_ok or self.poses.shape != (n, steps, 3):
            raise ValueError(
                f"inconsistent shapes: twists {self.twists.shape}, poses {self.poses.shape}, "
                f"t {self.t.shape}"
            )

    def __len__(self) -> int:
        return int(self.poses.shape[0])

    @property
    def xy(self) -> FloatArray:
        """``(N, T, 2)`` positions."""
        return self.poses[..., :2]

    @property
    def end_poses(self) -> FloatArray:
        """``(N, 3)`` final poses."""
        return self.poses[:, -1]

    def take(self, index: np.ndarray) -> Trajectories:
        """A subset (or permutation) of the candidates."""
        return Trajectories(self.twists[index], self.poses[index], self.t)

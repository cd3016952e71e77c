"""Time to collision with people and an evasive move within the robot's kinematics.

When a person approaches on a collision course (time to collision below a threshold) and the
local planner has nothing that keeps clear, the robot steps out of the way instead of standing
still: the candidate twists are the robot's own — sideways and diagonal translations for a
holonomic base, turn-and-go arcs for a differential drive — rolled out for ``horizon`` s with
people forecast at constant velocity, and the one keeping the largest minimum gap wins
(ties: the larger progress along the way to the goal). Candidates whose footprint meets a
static obstacle (the occupancy critic on the local costmap, people excluded) are discarded.
Reference: constant-velocity time to collision as in velocity-obstacle methods (Fiorini and
Shiller 1998; van den Berg et al. ORCA, 2011).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.trajectories import Trajectories
from socialnav.planner.rollout import RolloutParams, rollout


def time_to_collision(
    position: ArrayLike,
    velocity: ArrayLike,
    people: ArrayLike,
    people_velocities: ArrayLike,
    radii: ArrayLike,
) -> FloatArray:
    """Seconds until each person's disc meets the robot's, both at constant world velocity.

    ``position (2,)`` m and ``velocity (2,)`` m/s of the robot (world frame); ``people (K, 2)``,
    ``people_velocities (K, 2)``; ``radii (K,)`` the sum of robot and person radii (m).
    Returns ``(K,)``: 0 when already overlapping, ``inf`` when never.
    """
    p = np.asarray(people, dtype=float).reshape(-1, 2) - np.asarray(position, dtype=float)
    v = np.asarray(people_velocities, dtype=float).reshape(-1, 2) - np.asarray(
        velocity, dtype=float
    )
    r = np.asarray(radii, dtype=float).reshape(-1)
    a = (v * v).sum(axis=1)
    b = (p * v).sum(axis=1)  # closing when < 0
    c = (p * p).sum(axis=1) - r * r
    disc = b * b - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (-b - np.sqrt(np.maximum(disc, 0.0))) / a
    ttc = np.where((a > 0) & (b < 0) & (disc >= 0), t, np.inf)
    return np.where(c <= 0, 0.0, np.maximum(ttc, 0.0))


def evasion_twists(robot: RobotModel, speeds: int = 2, directions: int = 16) -> FloatArray:
    """Candidate body twists ``(N, 3)``: holonomic translations in ``directions`` directions,
    or differential-drive arcs (forward, reverse and in-place turns), all within the limits."""
    if robot.holonomic:
        ang = np.arange(directions) * (2 * np.pi / directions)
        out = []
        for f in np.linspace(1.0, 0.5, speeds):
            vx = np.clip(f * robot.max_vel_x * np.cos(ang), robot.min_vel_x, robot.max_vel_x)
            vy = f * robot.max_vel_y * np.sin(ang)
            out.append(np.column_stack([vx, vy, np.zeros_like(vx)]))
        return np.concatenate(out)
    w = np.linspace(-robot.max_vel_theta, robot.max_vel_theta, 9)
    vs = [robot.max_vel_x, 0.5 * robot.max_vel_x, robot.min_vel_x]
    arcs = [np.column_stack([np.full_like(w, v), np.zeros_like(w), w]) for v in vs]
    spin = np.array([[0.0, 0.0, robot.max_vel_theta], [0.0, 0.0, -robot.max_vel_theta]])
    return np.concatenate([*arcs, spin])


def evasion_gaps(
    pose: FloatArray,
    twists: FloatArray,
    robot: RobotModel,
    people: FloatArray,
    people_velocities: FloatArray,
    people_radii: FloatArray,
    horizon: float,
) -> tuple[FloatArray, Trajectories]:
    """Minimum gap (m, robot circumscribed disc to person disc) over ``horizon`` s for each of
    ``twists (N, 3)``, people at constant velocity; also the rollouts."""
    trajs = rollout(pose, np.zeros(3), twists, robot, RolloutParams(sim_time=horizon))
    forecast = people[None] + trajs.t[:, None, None] * people_velocities[None]  # (T, K, 2)
    d = np.linalg.norm(trajs.xy[:, :, None, :] - forecast[None], axis=-1)  # (N, T, K)
    gap = d - people_radii[None, None] - robot.circumscribed_radius
    return gap.min(axis=(1, 2)) if gap.size else np.full(len(twists), np.inf), trajs

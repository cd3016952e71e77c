"""Time to collision with people and an evasive move within the robot's kinematics.

When a person approaches on a collision course (time to collision below a threshold) and the
local planner has nothing that keeps clear, the robot steps out of the way instead of standing
still: the candidate twists are the robot's own — sideways and diagonal translations for a
holonomic base (and forward arcs when giving way), turn-and-go arcs for a differential
drive — rolled out for ``horizon`` s with people forecast at constant velocity, and the one
keeping the largest minimum gap wins (ties: the larger progress along the way to the goal).
Candidates whose footprint meets a static obstacle (the occupancy critic on the local
costmap, people excluded) are discarded. Giving way (:func:`move_and_hold`) also tries each
twist driven for a while and then held still, judged over the whole encounter.
Reference: constant-velocity time to collision as in velocity-obstacle methods (Fiorini and
Shiller 1998; van den Berg et al. ORCA, 2011).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
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


def evasion_twists(
    robot: RobotModel, speeds: int = 2, directions: int = 16, arcs: bool = False
) -> FloatArray:
    """Candidate body twists ``(N, 3)``: holonomic translations in ``directions`` directions
    and, with ``arcs``, full-speed forward arcs (turning while driving outruns a 0.3 m/s
    sidestep: recorded
    crowds, PR2, dev seeds 0–29, passive-contact episodes 23 → 19 of 60 with giving way on),
    or differential-drive arcs (forward, reverse and in-place turns), all within the limits."""
    if robot.holonomic:
        ang = np.arange(directions) * (2 * np.pi / directions)
        out = []
        for f in np.linspace(1.0, 0.5, speeds):
            vx = np.clip(f * robot.max_vel_x * np.cos(ang), robot.min_vel_x, robot.max_vel_x)
            vy = f * robot.max_vel_y * np.sin(ang)
            out.append(np.column_stack([vx, vy, np.zeros_like(vx)]))
        if arcs:
            w = np.linspace(-robot.max_vel_theta, robot.max_vel_theta, 9)
            out.append(np.column_stack([np.full_like(w, robot.max_vel_x), np.zeros_like(w), w]))
        return np.concatenate(out)
    w = np.linspace(-robot.max_vel_theta, robot.max_vel_theta, 9)
    vs = [robot.max_vel_x, 0.5 * robot.max_vel_x, robot.min_vel_x]
    drive = [np.column_stack([np.full_like(w, v), np.zeros_like(w), w]) for v in vs]
    spin = np.array([[0.0, 0.0, robot.max_vel_theta], [0.0, 0.0, -robot.max_vel_theta]])
    return np.concatenate([*drive, spin])


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
    gap = person_gap_minima(trajs, robot, people, people_velocities, people_radii)
    return gap.min(axis=1) if gap.size else np.full(len(twists), np.inf), trajs


def closest_approach(
    position: ArrayLike, velocity: ArrayLike, people: ArrayLike, people_velocities: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Closest approach of each person to the robot, both at constant world velocity:
    ``(distance (K,), time (K,))`` (m centre to centre, s from now; time 0 when they are
    separating). Arguments as :func:`time_to_collision`."""
    p = np.asarray(people, dtype=float).reshape(-1, 2) - np.asarray(position, dtype=float)
    v = np.asarray(people_velocities, dtype=float).reshape(-1, 2) - np.asarray(
        velocity, dtype=float
    )
    a = (v * v).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(a > 0, np.maximum(-(p * v).sum(axis=1) / a, 0.0), 0.0)
    return np.hypot(*(p + t[:, None] * v).T), t


def move_and_hold(trajs: Trajectories, durations: ArrayLike) -> Trajectories:
    """Each rollout of ``trajs`` (``N`` twists over one time grid ``(T,)``) driven for each of
    ``durations (M,)`` s and then held still at the pose it reached: ``N * M`` trajectories on
    the same grid, duration-major (row ``m * N + n`` is twist ``n`` for ``durations[m]``).
    A robot that steps out of a walker's lane and stops there is judged over the whole
    encounter, not only while it keeps moving (a constant twist over a long horizon would run
    into a wall and be discarded)."""
    taus = np.asarray(durations, dtype=float).reshape(-1)
    idx = np.arange(trajs.t.size)
    poses = []
    for tau in taus:
        last = int(np.searchsorted(trajs.t, tau + 1e-9) - 1)
        poses.append(trajs.poses[:, np.minimum(idx, max(last, 0))])
    twists = np.tile(trajs.twists, (taus.size, 1))
    return Trajectories(twists, np.concatenate(poses), trajs.t)


def squared_distance_minima(trajs: Trajectories, forecast: FloatArray) -> FloatArray:
    """``(N, K)`` minimum over time of the squared distance (m²) between each trajectory and
    each person's ``forecast (T, K, 2)`` on the trajectories' time grid. With the compiled
    kernels, the same values without the ``(N, T, K)`` temporaries (giving way judges
    hundreds of long rollouts)."""
    if kernels.enabled():
        out = np.empty((trajs.poses.shape[0], forecast.shape[1]))
        kernels.min_squared_distances(trajs.poses, forecast, np.arange(forecast.shape[1]), out)
        return out
    d2: FloatArray = ((trajs.xy[:, :, None, :] - forecast[None]) ** 2).sum(axis=-1).min(axis=1)
    return d2


def person_gap_minima(
    trajs: Trajectories,
    robot: RobotModel,
    people: FloatArray,
    people_velocities: FloatArray,
    people_radii: FloatArray,
) -> FloatArray:
    """``(N, K)`` minimum over the rollout of the gap (m, robot circumscribed disc to person
    disc) between each trajectory and each person forecast at constant velocity."""
    forecast = people[None] + trajs.t[:, None, None] * people_velocities[None]  # (T, K, 2)
    d = np.sqrt(squared_distance_minima(trajs, forecast))
    return d - people_radii[None] - robot.circumscribed_radius

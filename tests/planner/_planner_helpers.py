"""Small hand-built worlds and contexts for the planner tests."""

from __future__ import annotations

import numpy as np

from socialnav.core.geometry import points_in_polygon
from socialnav.core.robot import RobotModel
from socialnav.core.trajectories import Trajectories
from socialnav.planner.context import PlanningContext
from socialnav.world.grid import FREE, LETHAL, Costmap, GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize


def blank(rows: int, cols: int, res: float = 0.05, origin=(0.0, 0.0)) -> Costmap:
    return Costmap(
        np.full((rows, cols), FREE, dtype=np.uint8), GridGeometry((rows, cols), res, origin)
    )


def world(
    width: float, height: float, segments, robot: RobotModel, res: float = 0.05, polygons=()
) -> tuple[Costmap, np.ndarray]:
    """Inflated costmap of walls ``segments (S, 2, 2)`` and ``polygons``; also the obstacle mask."""
    geom = GridGeometry((round(height / res), round(width / res)), res)
    occ = rasterize(
        geom,
        segments=np.asarray(segments, dtype=float).reshape(-1, 2, 2),
        polygons=[np.asarray(p, dtype=float) for p in polygons],
        thickness=0.1,
    )
    return inflate(occ, geom, robot.inscribed_radius), occ


def context(
    costmap: Costmap,
    robot: RobotModel,
    pose=(0.0, 0.0, 0.0),
    path=None,
    goal=None,
    velocity=(0.0, 0.0, 0.0),
    **kw,
) -> PlanningContext:
    pose = np.asarray(pose, dtype=float)
    goal = np.asarray(goal if goal is not None else (*pose[:2], 0.0), dtype=float)
    path = np.asarray(path if path is not None else [pose[:2], goal[:2]], dtype=float)
    return PlanningContext(
        pose=pose,
        velocity=np.asarray(velocity, dtype=float),
        goal=goal,
        global_path=path,
        costmap=costmap,
        robot=robot,
        **kw,
    )


def straight(ends: np.ndarray, start=(0.0, 0.0), yaw: float = 0.0, steps: int = 5) -> Trajectories:
    """Straight-line trajectories from ``start`` to each of ``ends (N, 2)``, constant ``yaw``."""
    ends = np.asarray(ends, dtype=float).reshape(-1, 2)
    s = np.linspace(0.0, 1.0, steps)
    xy = np.asarray(start)[None, None] + s[None, :, None] * (ends[:, None] - np.asarray(start))
    poses = np.concatenate([xy, np.full((*xy.shape[:2], 1), yaw)], axis=2)
    return Trajectories(np.zeros((ends.shape[0], 3)), poses, s)


def collides(pose: np.ndarray, robot: RobotModel, occ: np.ndarray, geom: GridGeometry) -> bool:
    """True when an obstacle cell centre lies inside the robot footprint at ``pose``."""
    rc = np.argwhere(occ)
    if rc.size == 0:
        return False
    centres = geom.cell_to_world(rc)
    c, s = np.cos(pose[2]), np.sin(pose[2])
    poly = robot.polygon @ np.array([[c, s], [-s, c]]) + pose[:2]
    near = np.hypot(*(centres - pose[:2]).T) <= robot.circumscribed_radius + geom.resolution
    return bool(points_in_polygon(centres[near], poly).any()) if near.any() else False


def step_pose(pose: np.ndarray, cmd: np.ndarray, dt: float = 0.1) -> np.ndarray:
    c, s = np.cos(pose[2]), np.sin(pose[2])
    return pose + dt * np.array([c * cmd[0] - s * cmd[1], s * cmd[0] + c * cmd[1], cmd[2]])


__all__ = ["LETHAL", "blank", "collides", "context", "step_pose", "straight", "world"]


def straight_lines(velocities, duration: float = 1.5, steps: int = 16) -> Trajectories:
    """Straight constant-velocity trajectories from the origin, one per ``(vx, vy)`` (m/s),
    sampled ``steps`` times over ``duration`` s, heading 0."""
    v = np.asarray(velocities, dtype=float).reshape(-1, 2)
    t = np.linspace(0.0, duration, steps)
    xy = t[None, :, None] * v[:, None, :]
    poses = np.concatenate([xy, np.zeros((*xy.shape[:2], 1))], axis=-1)
    return Trajectories(np.column_stack([v, np.zeros(len(v))]), poses, t)

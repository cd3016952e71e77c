"""Plain-array conversions between ROS messages' fields and socialnav's types (no ROS imports).

- :func:`costmap_from_occupancy`: ``nav_msgs/OccupancyGrid`` fields → inflated :class:`Costmap`,
  read as Nav2's static layer reads a map (``data`` −1 unknown, ≥ 100 lethal, row-major from the
  origin cell) and inflated as its inflation layer does.
- :func:`yaw_from_quaternion` / :func:`quaternion_from_yaw`: planar orientation (rad, CCW about
  +z) ↔ ``geometry_msgs/Quaternion`` ``(x, y, z, w)``.
- :func:`compose`: a pose through the fixed ``odom_to_global`` transform.
- :func:`decelerate`: a stop that respects the acceleration limits (the safety stop).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.world.grid import Costmap, GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.mapio import OccupancyMap

__all__ = [
    "compose",
    "costmap_from_occupancy",
    "decelerate",
    "quaternion_from_yaw",
    "yaw_from_quaternion",
]

MAX_MAP_CELLS = 50_000_000  # 7000 x 7000 at 5 cm: a 350 m building; beyond it, refuse


def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """Yaw (rad, ``(-π, π]``) of a quaternion; roll and pitch are ignored (planar robot)."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def quaternion_from_yaw(yaw: float) -> tuple[float, float, float, float]:
    """``(x, y, z, w)`` of a rotation by ``yaw`` rad about +z."""
    return (0.0, 0.0, math.sin(0.5 * yaw), math.cos(0.5 * yaw))


def compose(frame_pose: ArrayLike, pose: ArrayLike) -> FloatArray:
    """``pose (3,)`` given in a frame whose own pose is ``frame_pose (3,)`` → the parent frame
    (both ``[x m, y m, yaw rad]``)."""
    f = np.asarray(frame_pose, dtype=float)
    p = np.asarray(pose, dtype=float)
    c, s = math.cos(f[2]), math.sin(f[2])
    return np.array(
        [f[0] + c * p[0] - s * p[1], f[1] + s * p[0] + c * p[1], float(wrap_angle(f[2] + p[2]))]
    )


def costmap_from_occupancy(
    data: ArrayLike,
    width: int,
    height: int,
    resolution: float,
    origin: ArrayLike,
    robot: RobotModel,
    inflation_radius: float = 0.55,
    cost_scaling_factor: float = 10.0,
) -> Costmap:
    """The inflated costmap of an occupancy grid.

    ``data`` is ``nav_msgs/OccupancyGrid.data`` (``width * height`` int8, row-major, row 0 at
    the origin), ``resolution`` m/cell, ``origin`` ``[x m, y m, yaw rad]`` of cell (0, 0)'s
    corner. Unknown cells (−1) stay UNKNOWN, cells ≥ 100 are lethal (costmap_2d's
    ``lethal_cost_threshold``), obstacles are inflated by ``inflation_radius`` m with decay
    ``cost_scaling_factor`` for ``robot``'s inscribed radius. Raises
    :class:`~socialnav.core.errors.InvalidInputError` for sizes that do not match, a rotated
    origin (costmap_2d ignores its yaw; we refuse rather than misplace obstacles) or a grid of
    more than :data:`MAX_MAP_CELLS` cells.
    """
    width, height = int(width), int(height)
    if width <= 0 or height <= 0 or width * height > MAX_MAP_CELLS:
        raise InvalidInputError(f"map size {width} x {height} is empty or too large")
    values = np.asarray(data)
    if values.size != width * height:
        raise InvalidInputError(f"map data has {values.size} cells, expected {width * height}")
    o = np.asarray(origin, dtype=float)
    if o.shape != (3,) or not np.all(np.isfinite(o)):
        raise InvalidInputError(f"map origin must be a finite [x, y, yaw], got {origin!r}")
    if abs(float(wrap_angle(o[2]))) > 1e-6:
        raise InvalidInputError(f"map origin yaw {o[2]} rad: rotated maps are not supported")
    geometry = GridGeometry((height, width), float(resolution), (float(o[0]), float(o[1])))
    grid = values.astype(np.int8).reshape(height, width)
    omap = OccupancyMap(grid, geometry)
    return inflate(
        omap.occupied_mask(),
        geometry,
        robot.inscribed_radius,
        inflation_radius,
        cost_scaling_factor,
        unknown=omap.unknown_mask(),
    )


def decelerate(cmd: ArrayLike, robot: RobotModel, dt: float) -> FloatArray:
    """The next command of a stop from ``cmd (3,)`` (body ``vx, vy, wz``): every component
    moves toward zero by at most its acceleration limit × ``dt`` s (the limits of ``robot``;
    a zero limit stops that axis at once, as a robot without it cannot hold the speed)."""
    c = np.asarray(cmd, dtype=float).copy()
    if c.shape != (3,) or not np.all(np.isfinite(c)):
        return np.zeros(3)
    for k, acc in enumerate((robot.acc_lim_x, robot.acc_lim_y, robot.acc_lim_theta)):
        step = acc * max(float(dt), 0.0)
        c[k] = 0.0 if step <= 0 else math.copysign(max(abs(c[k]) - step, 0.0), c[k])
    return c

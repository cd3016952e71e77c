"""The scene of a recorded crowd: open space bounded by the annotated area.

The recordings come with no map; the robot drives in open space, and the border of the
annotated area (the box of every recorded position, :attr:`Recording.area`) is a wall, so no
plan leaves the part of the world where people were observed.
"""

from __future__ import annotations

import math

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.crowds.recording import Area
from socialnav.world.grid import Costmap, GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize

#: free border (m) drawn around the area's walls in the costmap grid
GRID_MARGIN = 1.0


def area_walls(area: Area) -> FloatArray:
    """The area's border as four wall segments ``(4, 2, 2)`` (m, world frame), CCW."""
    corners = np.array(
        [
            [area.xmin, area.ymin],
            [area.xmax, area.ymin],
            [area.xmax, area.ymax],
            [area.xmin, area.ymax],
        ]
    )
    return np.stack([corners, np.roll(corners, -1, axis=0)], axis=1)


def open_space_costmap(
    area: Area,
    inscribed_radius: float,
    resolution: float = 0.05,
    inflation_radius: float = 0.55,
    cost_scaling_factor: float = 10.0,
    margin: float = GRID_MARGIN,
) -> Costmap:
    """The static costmap of a recorded scene: free inside ``area``, its border a wall.

    The grid covers the area plus ``margin`` (m) on each side at ``resolution`` (m/cell); the
    four border segments are rasterized like scenario walls and inflated as costmap_2d's
    inflation layer does (``inscribed_radius``, ``inflation_radius`` m,
    ``cost_scaling_factor`` 1/m). People are not in it: the planner sees them in the social
    context. Raises :class:`ConfigurationError` for a non-positive resolution or empty area.
    """
    if not (math.isfinite(resolution) and resolution > 0):
        raise ConfigurationError(f"resolution must be positive, got {resolution}")
    width, height = area.size
    if not (width > 0 and height > 0):
        raise ConfigurationError(f"the annotated area is empty: {area}")
    xmin, ymin = area.xmin - margin, area.ymin - margin
    shape = (
        math.ceil((area.ymax + margin - ymin) / resolution),
        math.ceil((area.xmax + margin - xmin) / resolution),
    )
    geometry = GridGeometry(shape, resolution, (xmin, ymin))
    occupied = rasterize(geometry, segments=area_walls(area))
    return inflate(occupied, geometry, inscribed_radius, inflation_radius, cost_scaling_factor)

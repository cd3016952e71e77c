"""A 2-D grid in the world frame, shared by occupancy maps and costmaps.

Cell ``[row, col]`` covers ``x in [ox + col*res, ox + (col+1)*res)`` and
``y in [oy + row*res, oy + (row+1)*res)``: row 0 is the *bottom* row (ROS convention after the
image row flip), ``origin`` is the world position of the lower-left corner of cell ``[0, 0]``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core.errors import InvalidInputError

# costmap_2d cost values
FREE = 0
INSCRIBED = 253
LETHAL = 254
UNKNOWN = 255


@dataclass(frozen=True)
class GridGeometry:
    """Where a ``(rows, cols)`` grid sits in the world: ``resolution`` m/cell, ``origin`` (x, y)."""

    shape: tuple[int, int]
    resolution: float
    origin: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.resolution) and self.resolution > 0):
            raise InvalidInputError(f"resolution must be positive, got {self.resolution}")
        if not np.all(np.isfinite(self.origin)):
            raise InvalidInputError("origin contains NaN or infinite values")
        if len(self.shape) != 2 or min(self.shape) <= 0:
            raise InvalidInputError(f"grid shape must be two positive sizes, got {self.shape}")

    @property
    def width_m(self) -> float:
        """Grid width (m, x)."""
        return self.shape[1] * self.resolution

    @property
    def height_m(self) -> float:
        """Grid height (m, y)."""
        return self.shape[0] * self.resolution

    def world_to_cell(self, xy: ArrayLike) -> NDArray[np.intp]:
        """``(..., 2)`` world points → ``(..., 2)`` integer ``(row, col)`` (maybe off-grid)."""
        p = np.asarray(xy, dtype=float)
        if p.shape == (2,):  # one point (the per-cycle boxes): Python floats, the same values
            fc = (float(p[0]) - float(self.origin[0])) / float(self.resolution)
            fr = (float(p[1]) - float(self.origin[1])) / float(self.resolution)
            if abs(fc) < 1e15 and abs(fr) < 1e15:  # finite and well inside intp
                return np.array([math.floor(fr), math.floor(fc)], dtype=np.intp)
        col = np.floor((p[..., 0] - self.origin[0]) / self.resolution).astype(np.intp)
        row = np.floor((p[..., 1] - self.origin[1]) / self.resolution).astype(np.intp)
        return np.stack([row, col], axis=-1)

    def cell_to_world(self, rc: ArrayLike) -> NDArray[np.float64]:
        """``(..., 2)`` ``(row, col)`` → world coordinates of the cell centres."""
        c = np.asarray(rc, dtype=float)
        x = self.origin[0] + (c[..., 1] + 0.5) * self.resolution
        y = self.origin[1] + (c[..., 0] + 0.5) * self.resolution
        return np.stack([x, y], axis=-1)

    def in_bounds(self, rc: ArrayLike) -> NDArray[np.bool_]:
        """``(...)`` whether cells ``rc (..., 2)`` (row, col) lie on the grid."""
        c = np.asarray(rc)
        return (
            (c[..., 0] >= 0)
            & (c[..., 0] < self.shape[0])
            & (c[..., 1] >= 0)
            & (c[..., 1] < self.shape[1])
        )

    def cell_centers(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Meshgrid ``(X, Y)`` of cell-centre world coordinates, each ``(rows, cols)``."""
        xs = self.origin[0] + (np.arange(self.shape[1]) + 0.5) * self.resolution
        ys = self.origin[1] + (np.arange(self.shape[0]) + 0.5) * self.resolution
        return np.meshgrid(xs, ys)


@dataclass(frozen=True)
class Costmap:
    """A costmap_2d-style layer: ``costs (rows, cols) uint8`` with FREE/INSCRIBED/LETHAL/UNKNOWN."""

    costs: NDArray[np.uint8]
    geometry: GridGeometry

    def __post_init__(self) -> None:
        if self.costs.dtype != np.uint8 or self.costs.shape != self.geometry.shape:
            raise InvalidInputError(
                f"costs must be uint8 of shape {self.geometry.shape}, got {self.costs.dtype} "
                f"{self.costs.shape}"
            )

    @property
    def resolution(self) -> float:
        """Cell size (m)."""
        return self.geometry.resolution

    def cost_at(self, xy: ArrayLike, outside: int = LETHAL) -> NDArray[np.uint8]:
        """Cost at ``(..., 2)`` world points; points off the map read ``outside``."""
        rc = self.geometry.world_to_cell(xy)
        inside = self.geometry.in_bounds(rc)
        rows = np.where(inside, rc[..., 0], 0)
        cols = np.where(inside, rc[..., 1], 0)
        return np.where(inside, self.costs[rows, cols], np.uint8(outside)).astype(np.uint8)

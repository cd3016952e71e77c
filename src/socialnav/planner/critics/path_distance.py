"""Path-distance critic: BFS distance to the nearest cell of the global plan.

ROS ``base_local_planner`` ``PathCostFunction`` / Nav2 DWB ``PathDistCritic`` (Marder-Eppstein
et al. 2010), the paper's ``Compute_Path_Dist`` (Banisetty et al., eq. "Cost function", term
Δ_path). The grid machinery and its decisions are in :mod:`~socialnav.planner.critics.map_grid`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import NDArray

from socialnav.planner.critics.base import CRITICS
from socialnav.planner.critics.map_grid import MapGridCritic

if TYPE_CHECKING:
    from socialnav.planner.cache import CycleCache


@CRITICS.register("path_distance")
@dataclass(frozen=True)
class PathDistanceCritic(MapGridCritic):
    """Distance (m, 4-connected BFS) from the trajectory's end point to the nearest cell of the
    global plan inside the local costmap. No parameters: the weight is the objective's
    ``path_distance_bias``."""

    name: ClassVar[str] = "path_distance"

    def seeds(self, cells: NDArray[np.intp]) -> NDArray[np.intp]:
        """Every plan cell in view (ROS ``setTargetCells``)."""
        return cells

    def cached_grid(self, cache: CycleCache) -> NDArray[np.float32] | None:
        """``cache.path_distance_grid``."""
        return cache.path_distance_grid

    def keep_grid(self, cache: CycleCache, grid: NDArray[np.float32]) -> None:
        """Set ``cache.path_distance_grid``."""
        cache.path_distance_grid = grid

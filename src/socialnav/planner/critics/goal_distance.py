"""Goal-distance critic: BFS distance to the local goal (ROS ``GoalCostFunction`` / MapGrid,
Nav2 DWB ``GoalDistCritic``).

Marder-Eppstein et al. 2010; the paper's ``Compute_Goal_Dist`` (Banisetty et al., Δ_goal).

Decisions and deviations (shared with :mod:`~socialnav.planner.critics.path_distance`, see
:mod:`~socialnav.planner.critics.map_grid`): meter scoring; the local goal is the last cell of the
plan's first contiguous in-map, non-UNKNOWN stretch; a trajectory ending on a blocked/unreached
cell is illegal (``unreachable``), off the map ``off_map``.
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


@CRITICS.register("goal_distance")
@dataclass(frozen=True)
class GoalDistanceCritic(MapGridCritic):
    """Distance (m, 4-connected BFS) from the trajectory's end point to the local goal."""

    name: ClassVar[str] = "goal_distance"

    def seeds(self, cells: NDArray[np.intp]) -> NDArray[np.intp]:
        """The last plan cell in view (ROS ``setLocalGoal``)."""
        return cells[-1:]

    def cached_grid(self, cache: CycleCache) -> NDArray[np.float32] | None:
        """``cache.goal_distance_grid``."""
        return cache.goal_distance_grid

    def keep_grid(self, cache: CycleCache, grid: NDArray[np.float32]) -> None:
        """Set ``cache.goal_distance_grid``."""
        cache.goal_distance_grid = grid

"""The per-cycle critic cache: values several critics (or several batches) of one control cycle
share, computed once in ``prepare`` or on first use.

One :class:`CycleCache` hangs off each :class:`~socialnav.planner.context.PlanningContext`; the
context itself stays frozen. Every shared value is a typed field (``None`` until computed), so a
critic reading another's work is checked by the type checker instead of a string key. The model
is Nav2 DWB's per-cycle ``prepare`` with critics that own their grids (``MapGridCritic``); here
the grids are shared because the path and goal grids flood the same graph.

The fields listed in :data:`REUSABLE` depend only on the costmap, the robot, its pose, the plan,
the goal and ``reach``; :class:`~socialnav.planner.objectives.PreparedReuse` carries them to the
next cycle when all of those are identical.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from socialnav.core.geometry import FloatArray

if TYPE_CHECKING:
    from socialnav.core.trajectories import Trajectories
    from socialnav.planner.critics.map_grid import GridGraph


@dataclass(frozen=True)
class HeadingPlan:
    """The plan ahead of the robot for the heading critic: ``dense (P, 2)`` world vertices (m),
    ``s (P,)`` arc length (m) from the first vertex, ``tangent (P,)`` direction (rad, world) of
    the segment arriving at each vertex."""

    dense: FloatArray
    s: FloatArray
    tangent: FloatArray


@dataclass
class PeopleDistances:
    """Min-over-time squared distances between one trajectory batch and the forecast people
    (:func:`~socialnav.planner.critics.interpersonal.min_squared_distances`).

    ``trajs`` is the batch (compared by identity); ``forecast (T, K, 2)`` people positions (m,
    world); ``bound (K,)`` lower bound (m) on each person's distance to the batch;
    ``covered (K,)`` the distance (m) up to which each column of ``d2min (N, K)`` (m²) is exact
    (``-inf``: not computed, all ``inf``; ``inf``: exact everywhere; otherwise an entry is exact
    or, beyond ``covered``, may be ``inf``).
    """

    trajs: Trajectories
    forecast: FloatArray
    bound: FloatArray
    covered: FloatArray
    d2min: FloatArray


@dataclass
class CycleCache:
    """Typed per-cycle shared data (all ``None`` until computed).

    - ``reach``: metres the rollouts can travel from the robot this cycle (set by the local
      planner from the sampled speeds × ``sim_time``); bounds the grid work.
    - Map grid (:mod:`~socialnav.planner.critics.map_grid`): ``footprint_cells`` and
      ``passable_cells (rows, cols)`` bool masks, ``grid_graph`` the BFS graph over them,
      ``local_plan_cells (K, 2)`` (row, col) seeds, ``path_distance_grid`` and
      ``goal_distance_grid (rows, cols)`` float32 BFS steps.
    - ``heading_plan``: :class:`HeadingPlan`.
    - Occupancy (:mod:`~socialnav.planner.critics.occupancy`): ``occupancy_outline (K, 2)`` body
      frame (m, far first) and its radii ``occupancy_outline_rho (K,)`` (cells),
      ``occupancy_codes`` the padded hit-code map and its pad (cells), ``occupancy_clearance
      (rows, cols)`` index into ``occupancy_need (L,)``, ``occupancy_sdf (rows, cols)`` (m),
      ``occupancy_wall_sdf (rows, cols)`` (m; it depends on the tracked people too, so it is
      not reusable).
    - ``people_distances``: :class:`PeopleDistances` of the last scored batch.
    """

    reach: float | None = None
    footprint_cells: NDArray[np.bool_] | None = None
    passable_cells: NDArray[np.bool_] | None = None
    grid_graph: GridGraph | None = None
    local_plan_cells: NDArray[np.intp] | None = None
    path_distance_grid: NDArray[np.float32] | None = None
    goal_distance_grid: NDArray[np.float32] | None = None
    heading_plan: HeadingPlan | None = None
    occupancy_outline: FloatArray | None = None
    occupancy_outline_rho: FloatArray | None = None
    occupancy_codes: tuple[NDArray[np.uint8], int] | None = None
    occupancy_clearance: NDArray[np.uint16] | None = None
    occupancy_need: NDArray[np.intp] | None = None
    occupancy_sdf: FloatArray | None = None
    occupancy_wall_sdf: FloatArray | None = None
    people_distances: PeopleDistances | None = None

    def reusable(self) -> CycleCache:
        """A cache holding only this one's :data:`REUSABLE` fields (the arrays are shared)."""
        return CycleCache(**{name: getattr(self, name) for name in REUSABLE})

    def fill(self, other: CycleCache) -> None:
        """Take each :data:`REUSABLE` field of ``other`` that is still ``None`` here (a cycle's
        own values win)."""
        for name in REUSABLE:
            if getattr(self, name) is None:
                setattr(self, name, getattr(other, name))


# Depend only on the costmap, the robot, its pose, the plan, the goal and the reach.
REUSABLE: tuple[str, ...] = (
    "occupancy_outline",
    "occupancy_outline_rho",
    "occupancy_codes",
    "occupancy_clearance",
    "occupancy_need",
    "occupancy_sdf",
    "footprint_cells",
    "passable_cells",
    "local_plan_cells",
    "path_distance_grid",
    "goal_distance_grid",
    "heading_plan",
)
assert set(REUSABLE) <= {f.name for f in fields(CycleCache)}

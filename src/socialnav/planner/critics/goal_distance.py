"""Goal-distance critic: BFS distance to the local goal (ROS ``GoalCostFunction`` / MapGrid).

Marder-Eppstein et al. 2010; the paper's ``Compute_Goal_Dist`` (Banisetty et al., Δ_goal).

Decisions and deviations (shared with :mod:`path_distance`): meter scoring; the local goal is the
last cell of the plan's first contiguous in-map, non-UNKNOWN stretch; a trajectory ending on a
blocked/unreached cell is illegal (``unreachable``), off the map ``off_map``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from socialnav.core.trajectories import Trajectories
from socialnav.planner.critics.base import CRITICS, Critic, CriticScore, CriticUnavailable
from socialnav.planner.critics.path_distance import (
    grid_graph,
    local_plan_cells,
    score_end_points,
    settle_region,
)

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


@CRITICS.register("goal_distance")
@dataclass(frozen=True)
class GoalDistanceCritic(Critic):
    """Distance (m, 4-connected BFS) from the trajectory's end point to the local goal."""

    name: ClassVar[str] = "goal_distance"
    unit: ClassVar[str] = "m"

    def prepare(self, ctx: PlanningContext) -> None:
        """Build the cycle's goal-distance grid (``CriticUnavailable``: no plan cell in view)."""
        if "goal_distance_grid" in ctx.extras:  # idempotent within one cycle
            return
        cells = ctx.extras.get("local_plan_cells")
        if cells is None:
            cells = local_plan_cells(ctx.costmap, ctx.global_path)
            ctx.extras["local_plan_cells"] = cells
        if cells.shape[0] == 0:
            raise CriticUnavailable("no global plan cell inside the local costmap")
        ctx.extras["goal_distance_grid"] = grid_graph(ctx).distance(cells[-1:], settle_region(ctx))

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Distance (m) from each end point to the local goal ``(N,)``; illegal masks."""
        if "goal_distance_grid" not in ctx.extras:
            self.prepare(ctx)
        return score_end_points(ctx.extras["goal_distance_grid"], trajs, ctx)

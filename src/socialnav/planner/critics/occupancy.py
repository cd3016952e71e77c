"""Occupancy critic: the highest costmap cost the robot crosses (ROS ``ObstacleCostFunction``).

Marder-Eppstein et al. 2010; the paper's ``Compute_Occ_Cost`` (Banisetty et al., Δ_occ), and the
paper's rule "discard all the trajectories that lead to a collision".

Decisions and deviations:
- Cost = max over the rollout's poses ``t > 0`` of the centre cell's cost (costmap units 0..252
  on legal rows). The current pose ``t = 0`` is not scored: it is a fact, not a choice, and
  counting it would leave a robot that touched the inflation with no legal move (ROS counts it).
- Deviation from ROS: the footprint outline decides legality only; its cells do not raise the
  cost (ROS takes the max over outline cells too). The inflation already encodes the robot's
  size around the centre, so adding the outline double-counts clearance — with ROS weights a
  robot then prefers standing still to passing a doorway — and only a centre-cell cost keeps the
  shortcut below exact (skipped poses would otherwise change the cost, not just the legality).
- Illegal: ``collision`` when the centre cell is INSCRIBED/LETHAL or an outline cell is LETHAL;
  ``unknown`` when the centre or an outline cell is UNKNOWN or off the map (ROS ``pointCost``).
- Outline: the body-frame footprint polygon sampled every ``≤ resolution / 2`` along its edges
  (instead of Bresenham lines), transformed to each checked pose.
- ``meter_scoring`` (default, ROS ``TrajectoryPlannerROS``): the cost is multiplied by the costmap
  resolution (m/cell), exactly as ROS multiplies ``occdist_scale`` by it under meter scoring, so
  ``occdist_scale = 0.01`` weighs a cost of 252 as 0.126 — comparable to 0.16 m of goal distance
  at ``goal_distance_bias = 0.8``. Without it (DWA's convention) the raw unit is plain cost.
- Shortcut (Nav2 MPPI): the outline is only checked where it can touch an obstacle. With
  ``circumscribed_cost`` given (``socialnav.world.inflation.circumscribed_cost`` for the
  costmap's inflation parameters), where the centre cost ``>= circumscribed_cost``; by default
  (``None``) an exact per-cycle mask is used instead: cells within the circumscribed radius (a
  square superset) of a LETHAL/UNKNOWN cell or the map edge — valid for any costmap.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter

from socialnav.core.geometry import FloatArray
from socialnav.core.trajectories import Trajectories
from socialnav.planner.critics.base import CRITICS, Critic, CriticScore
from socialnav.world.grid import INSCRIBED, LETHAL, UNKNOWN

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


def footprint_outline(polygon: FloatArray, spacing: float) -> FloatArray:
    """Points ``(K, 2)`` along the closed polygon ``(V, 2)``, at most ``spacing`` apart."""
    a = polygon
    b = np.roll(polygon, -1, axis=0)
    pieces = []
    for p, q in zip(a, b, strict=True):
        n = max(1, math.ceil(float(np.linalg.norm(q - p)) / spacing))
        s = np.arange(n)[:, None] / n
        pieces.append(p + s * (q - p))
    return np.concatenate(pieces)


@CRITICS.register("occupancy")
@dataclass(frozen=True)
class OccupancyCritic(Critic):
    """Max centre-cell cost (0..252; × resolution with ``meter_scoring``) along the trajectory;
    footprint collisions are illegal.

    - ``footprint``: check the footprint outline (``False``: centre cell only, a circular robot
      whose inscribed radius the inflation already encodes).
    - ``circumscribed_cost``: cost threshold for the outline shortcut, or ``None`` for the exact
      per-cycle obstacle-proximity mask.
    - ``meter_scoring``: multiply by the resolution (m/cell), the ROS meter-scoring convention.
    """

    name: ClassVar[str] = "occupancy"
    unit: ClassVar[str] = "cost·m/cell"

    footprint: bool = True
    circumscribed_cost: int | None = None
    meter_scoring: bool = True

    def prepare(self, ctx: PlanningContext) -> None:
        if not self.footprint or "occupancy_near" in ctx.extras:
            return
        res = ctx.costmap.resolution
        ctx.extras["occupancy_outline"] = footprint_outline(ctx.robot.polygon, 0.5 * res)
        if self.circumscribed_cost is None:
            # Centre cells from which a footprint of circumscribed radius R can reach a
            # LETHAL/UNKNOWN cell or leave the map: a (2r+1)² max filter, r = ceil(R/res)+1,
            # over the map or — when the planner published its ``reach`` — only the box the
            # rollouts can enter (poses outside it are then always checked).
            r = math.ceil(ctx.robot.circumscribed_radius / res) + 1
            rows, cols = ctx.costmap.geometry.shape
            r0, r1, c0, c1 = 0, rows, 0, cols
            reach = ctx.extras.get("reach")
            if reach is not None:
                lo = ctx.costmap.geometry.world_to_cell(ctx.pose[:2] - reach)
                hi = ctx.costmap.geometry.world_to_cell(ctx.pose[:2] + reach)
                r0, c0 = max(int(lo[0]) - 1, 0), max(int(lo[1]) - 1, 0)
                r1, c1 = min(int(hi[0]) + 2, rows), min(int(hi[1]) + 2, cols)
            near = np.ones((rows, cols), dtype=bool)
            if r0 < r1 and c0 < c1:
                # the filter needs the obstacles up to r cells beyond the box
                a0, a1 = max(r0 - r, 0), min(r1 + r, rows)
                b0, b1 = max(c0 - r, 0), min(c1 + r, cols)
                # cval=1: off-map is an obstacle; the sub-array's inner borders lie beyond
                # every window centred in the box, so they do not leak in.
                hard = (ctx.costmap.costs[a0:a1, b0:b1] >= LETHAL).view(np.uint8)
                filt = maximum_filter(hard, size=2 * r + 1, mode="constant", cval=1)
                near[r0:r1, c0:c1] = filt[r0 - a0 : r1 - a0, c0 - b0 : c1 - b0].astype(bool)
            ctx.extras["occupancy_near"] = near

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        geom = ctx.costmap.geometry
        costs = ctx.costmap.costs
        n = len(trajs)
        poses = trajs.poses[:, 1:] if trajs.poses.shape[1] > 1 else trajs.poses
        inv = 1.0 / geom.resolution
        col = np.floor((poses[..., 0] - geom.origin[0]) * inv).astype(np.intp)
        row = np.floor((poses[..., 1] - geom.origin[1]) * inv).astype(np.intp)
        rows, cols = geom.shape
        inside = (row >= 0) & (row < rows) & (col >= 0) & (col < cols)
        np.clip(row, 0, rows - 1, out=row)
        np.clip(col, 0, cols - 1, out=col)
        centre = np.where(inside, costs[row, col], np.uint8(UNKNOWN))
        unknown = (centre == UNKNOWN).any(axis=1)
        collision = ((centre >= INSCRIBED) & (centre != UNKNOWN)).any(axis=1)
        worst = np.where(centre < INSCRIBED, centre, 0).max(axis=1).astype(float)

        if self.footprint:
            if "occupancy_outline" not in ctx.extras:
                self.prepare(ctx)
            if self.circumscribed_cost is None:
                check = ctx.extras["occupancy_near"][row, col] | ~inside
            else:
                check = centre >= self.circumscribed_cost
            # Only poses of still-legal trajectories need the expensive outline test.
            check &= ~(unknown | collision)[:, None]
            ti, tk = np.nonzero(check)
            if ti.size:
                hit, unk = self._outline(ctx, poses[ti, tk], n, ti)
                collision |= hit
                unknown |= unk
        illegal = collision | unknown
        if self.meter_scoring:
            worst = worst * geom.resolution
        cost = np.where(illegal, np.inf, worst)
        return CriticScore(cost, {"collision": collision, "unknown": unknown & ~collision})

    @staticmethod
    def _outline(
        ctx: PlanningContext, poses: FloatArray, n: int, owner: NDArray[np.intp]
    ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """Outline LETHAL / UNKNOWN hits for ``poses (M, 3)``, reduced per trajectory
        ``owner (M,)`` → ``(n,)`` each."""
        geom = ctx.costmap.geometry
        outline = ctx.extras["occupancy_outline"].astype(poses.dtype)  # (K, 2)
        c = np.cos(poses[:, 2:3])
        s = np.sin(poses[:, 2:3])
        ox, oy = outline[None, :, 0], outline[None, :, 1]
        inv = 1.0 / geom.resolution
        x = (poses[:, 0:1] + c * ox - s * oy - geom.origin[0]) * inv
        y = (poses[:, 1:2] + s * ox + c * oy - geom.origin[1]) * inv
        col = np.floor(x).astype(np.intp)
        row = np.floor(y).astype(np.intp)
        rows, cols = geom.shape
        inside = (row >= 0) & (row < rows) & (col >= 0) & (col < cols)
        np.clip(row, 0, rows - 1, out=row)
        np.clip(col, 0, cols - 1, out=col)
        cost = np.where(inside, ctx.costmap.costs[row, col], np.uint8(UNKNOWN))
        per_pose_unknown = (cost == UNKNOWN).any(axis=1)
        per_pose_hit = (cost == LETHAL).any(axis=1)
        # ``owner`` comes from np.nonzero, so it is sorted: segment reductions per trajectory.
        ids, start = np.unique(owner, return_index=True)
        hit = np.zeros(n, dtype=bool)
        unk = np.zeros(n, dtype=bool)
        hit[ids] = np.logical_or.reduceat(per_pose_hit, start)
        unk[ids] = np.logical_or.reduceat(per_pose_unknown, start)
        return hit, unk

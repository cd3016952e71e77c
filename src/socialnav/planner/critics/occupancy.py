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
  (``None``) an exact per-cycle bound is used instead, valid for any costmap: the Euclidean
  distance ``D`` (cells) from each cell centre to the nearest LETHAL/UNKNOWN/off-map cell. An
  outline point ``ρ`` cells from a pose in that cell can only land in such a cell when
  ``ρ >= D - √2`` (the pose and the hit point are each within ``√2 / 2`` cells of their cell
  centres), so a pose is checked only against the outline points that far out — none when
  ``D > max ρ + √2``. Skipping a point that cannot hit never changes the result.
- Exact early exit: a trajectory whose outline hit a LETHAL cell is ``collision`` whatever its
  later poses do, so poses are checked in time chunks and such trajectories are dropped (an
  UNKNOWN hit does not stop the check: a later LETHAL hit still makes the reason
  ``collision``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import distance_transform_edt

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
        """Per-cycle costmap lookups shared by every batch of the cycle."""
        if not self.footprint:
            return
        if "occupancy_outline" not in ctx.extras:
            _prepare_outline(ctx)
        if self.circumscribed_cost is None and "occupancy_clearance" not in ctx.extras:
            _prepare_clearance(ctx)

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Costmap cost ``(N,)`` along each rollout; collisions illegal."""
        geom = ctx.costmap.geometry
        costs = ctx.costmap.costs
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
            self.prepare(ctx)
            if self.circumscribed_cost is None:
                # Outline points per pose that can reach a LETHAL/UNKNOWN cell (module doc);
                # off-map centres are already ``unknown`` trajectories, skipped below.
                need = ctx.extras["occupancy_need"][ctx.extras["occupancy_clearance"][row, col]]
            else:
                k = ctx.extras["occupancy_outline"].shape[0]
                need = np.where(centre >= self.circumscribed_cost, k, 0).astype(np.intp)
            # Only poses of still-legal trajectories need the expensive outline test.
            need[unknown | collision] = 0
            hit, unk = _outline_hits(ctx, poses, need)
            collision |= hit
            unknown |= unk
        illegal = collision | unknown
        if self.meter_scoring:
            worst = worst * geom.resolution
        cost = np.where(illegal, np.inf, worst)
        return CriticScore(cost, {"collision": collision, "unknown": unknown & ~collision})


# Margin (cells) on the clearance bound: covers rounding of the outline transform, in float32
# poses too (an ulp at 1 km is ~1e-3 cells at 5 cm). A larger margin only checks more points.
_CLEARANCE_MARGIN = 0.05
# Steps per early-exit chunk: trajectories with a LETHAL hit are dropped between chunks.
_CHUNK_STEPS = 8
_HIT, _UNSEEN = np.uint8(1), np.uint8(2)


def _prepare_outline(ctx: PlanningContext) -> None:
    """The body-frame outline sorted by distance from the centre (far first) and the padded
    hit-code map: 0 free, 1 LETHAL, 2 UNKNOWN or off the map."""
    res = ctx.costmap.resolution
    outline = footprint_outline(ctx.robot.polygon, 0.5 * res)
    rho = np.hypot(outline[:, 0], outline[:, 1]) / res  # cells
    order = np.argsort(-rho, kind="stable")
    ctx.extras["occupancy_outline"] = outline[order]
    ctx.extras["occupancy_outline_rho"] = rho[order]
    # Checked poses have their centre on the map, so every outline point lies within the
    # circumscribed radius of the map: a border that wide replaces clipping and the in-map test.
    pad = math.ceil(float(rho.max(initial=0.0))) + 2
    costs = ctx.costmap.costs
    # LETHAL (254) → 1, UNKNOWN (255) → 2, anything lower → 0
    codes = np.pad(np.maximum(costs, INSCRIBED) - np.uint8(INSCRIBED), pad, constant_values=_UNSEEN)
    ctx.extras["occupancy_codes"] = (codes, pad)


def _prepare_clearance(ctx: PlanningContext) -> None:
    """``occupancy_clearance (rows, cols)`` int index into ``occupancy_need (L,)``: how many of
    the sorted outline points a pose in that cell must check (module docstring).

    The clearance ``D`` (cells, a lower bound on the distance from the cell centre to the nearest
    LETHAL/UNKNOWN/off-map cell) comes from a Euclidean distance transform over the map or —
    when the planner published its ``reach`` — only the box the rollouts can enter (poses
    outside it then check every point).
    """
    if "occupancy_outline" not in ctx.extras:
        _prepare_outline(ctx)
    rho = ctx.extras["occupancy_outline_rho"]
    rows, cols = ctx.costmap.geometry.shape
    # Window margin e: a hard cell outside the window is >= e + 1 cells away, beyond any reach.
    e = math.ceil(float(rho.max(initial=0.0)) + math.sqrt(2.0) + _CLEARANCE_MARGIN) + 1
    r0, r1, c0, c1 = 0, rows, 0, cols
    reach = ctx.extras.get("reach")
    if reach is not None:
        lo = ctx.costmap.geometry.world_to_cell(ctx.pose[:2] - reach)
        hi = ctx.costmap.geometry.world_to_cell(ctx.pose[:2] + reach)
        r0, c0 = max(int(lo[0]) - 1, 0), max(int(lo[1]) - 1, 0)
        r1, c1 = min(int(hi[0]) + 2, rows), min(int(hi[1]) + 2, cols)
    # Index of the clearance level (1/16 cell, rounded down); 0 (check every point) outside
    # the box.
    step = 1.0 / 16.0
    clear = np.zeros((rows, cols), dtype=np.uint16)
    if r0 < r1 and c0 < c1:
        a0, a1 = max(r0 - e, 0), min(r1 + e, rows)
        b0, b1 = max(c0 - e, 0), min(c1 + e, cols)
        free = ctx.costmap.costs[a0:a1, b0:b1] < LETHAL
        # A ring of hard cells where the window meets the map edge: off-map counts as hard.
        edges = ((int(a0 == 0), int(a1 == rows)), (int(b0 == 0), int(b1 == cols)))
        free = np.pad(free, edges, constant_values=False)
        if free.all():  # no hard cell in reach (the transform needs one)
            dist = np.full(free.shape, float(e + 1))
        else:
            dist = np.minimum(distance_transform_edt(free), float(e + 1))
        i0, j0 = r0 - a0 + edges[0][0], c0 - b0 + edges[1][0]
        box = dist[i0 : i0 + r1 - r0, j0 : j0 + c1 - c0]
        clear[r0:r1, c0:c1] = np.floor(box * (1.0 / step))
    # Points with rho >= D - √2 - margin may hit; rho is sorted descending. Rounding D down to
    # a level checks more points: still exact.
    levels = np.arange((e + 1) * 16 + 1) * step
    need = np.count_nonzero(
        rho[None, :] >= (levels - math.sqrt(2.0) - _CLEARANCE_MARGIN)[:, None], axis=1
    )
    ctx.extras["occupancy_clearance"] = clear
    ctx.extras["occupancy_need"] = need.astype(np.intp)


def _outline_hits(
    ctx: PlanningContext, poses: FloatArray, need: NDArray[np.intp]
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Outline LETHAL / UNKNOWN hits ``(N,)`` each for ``poses (N, T, 3)``, checking the first
    ``need (N, T)`` sorted outline points of each pose (0: skip the pose)."""
    geom = ctx.costmap.geometry
    n, steps = need.shape
    outline = ctx.extras["occupancy_outline"].astype(poses.dtype)  # (K, 2), far first
    codes, pad = ctx.extras["occupancy_codes"]
    flat_codes = codes.ravel()
    width = codes.shape[1]
    k_all = outline.shape[0]
    # Poses are grouped by how many points they need, rounded up to K, K/2, K/4, ...
    sizes = sorted({max(1, math.ceil(k_all / 2**j)) for j in range(5)})
    sizes_arr = np.array(sizes)
    inv = 1.0 / geom.resolution
    hit = np.zeros(n, dtype=bool)
    unk = np.zeros(n, dtype=bool)
    for t0 in range(0, steps, _CHUNK_STEPS):
        block = need[:, t0 : t0 + _CHUNK_STEPS]
        ti, tk = np.nonzero((block > 0) & ~hit[:, None])
        if not ti.size:
            continue
        group = np.searchsorted(sizes_arr, block[ti, tk])
        for g in np.unique(group):
            sel = group == g
            owner = ti[sel]
            p = poses[owner, tk[sel] + t0]
            o = outline[: sizes[g]]
            c = np.cos(p[:, 2:3])
            s = np.sin(p[:, 2:3])
            ox, oy = o[None, :, 0], o[None, :, 1]
            # The same expression as the centre-cell lookup: bit-identical cells.
            x = (p[:, 0:1] + c * ox - s * oy - geom.origin[0]) * inv
            y = (p[:, 1:2] + s * ox + c * oy - geom.origin[1]) * inv
            cell = (np.floor(y).astype(np.intp) + pad) * width
            cell += np.floor(x).astype(np.intp) + pad
            per_pose = np.bitwise_or.reduce(flat_codes.take(cell, mode="clip"), axis=1)
            hit[owner[(per_pose & _HIT) != 0]] = True
            unk[owner[(per_pose & _UNSEEN) != 0]] = True
    return hit, unk

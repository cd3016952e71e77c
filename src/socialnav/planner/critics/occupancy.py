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
- Escape from overlap: when the current pose is already in collision (a person stepped into
  the footprint), every rollout would be ``collision``. Then a trajectory is legal instead when
  its clearance never decreases: the clearance of a pose is the smallest signed distance (m,
  from a distance transform of the LETHAL cells: positive outside, negative inside) over its
  footprint outline, and the centre's signed distance minus the inscribed radius, so driving
  away from someone touching the robot is always possible; pushing deeper is not. Walls get a
  second check as well (``_above_wall_floor``): that per-cell distance is flat inside a
  cell and rises again beyond a wall one cell thick, so a corner could be pushed through it.
- Exact early exit: a trajectory whose outline hit a LETHAL cell is ``collision`` whatever its
  later poses do, so poses are checked in time chunks and such trajectories are dropped (an
  UNKNOWN hit does not stop the check: a later LETHAL hit still makes the reason
  ``collision``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import distance_transform_edt, label, map_coordinates

from socialnav.core.geometry import FloatArray
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
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
        if ctx.cache.occupancy_outline is None:
            _prepare_outline(ctx)
        if self.circumscribed_cost is None and ctx.cache.occupancy_clearance is None:
            _prepare_clearance(ctx)

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Costmap cost ``(N,)`` along each rollout; collisions illegal."""
        geom = ctx.costmap.geometry
        poses = trajs.poses[:, 1:] if trajs.poses.shape[1] > 1 else trajs.poses
        if kernels.enabled() and poses.dtype == np.float64:
            worst, collision, unknown = self._scan_compiled(ctx, trajs.poses)
        else:
            worst, collision, unknown = self._scan_reference(ctx, poses)
        if collision.any() and _start_in_collision(ctx, trajs.poses[0, 0], self.footprint):
            # Escape from overlap: starting in collision, a trajectory that never reduces its
            # clearance is legal (module docstring), so the robot can always back away.
            legal = _never_closer(ctx, trajs.poses, self.footprint)
            collision = ~_above_wall_floor(ctx, trajs.poses, self.footprint, legal)
        illegal = collision | unknown
        if self.meter_scoring:
            worst = worst * geom.resolution
        cost = np.where(illegal, np.inf, worst)
        return CriticScore(cost, {"collision": collision, "unknown": unknown & ~collision})

    def _scan_compiled(
        self, ctx: PlanningContext, poses: FloatArray
    ) -> tuple[FloatArray, NDArray[np.bool_], NDArray[np.bool_]]:
        """:meth:`_scan_reference` as one compiled pass over all ``poses (N, T, 3)``
        (the first skipped when T > 1; bit-identical)."""
        geom = ctx.costmap.geometry
        outline_data, clearance = None, None
        if self.footprint:
            self.prepare(ctx)
            outline, _, codes, pad = _outline(ctx)
            outline_data = (outline, codes.reshape(-1), pad, codes.shape[1])
            if self.circumscribed_cost is None:
                clearance = _clearance(ctx)
        cached = ctx.cache.occupancy_outline
        return kernels.occupancy_scan(
            poses,
            1 if poses.shape[1] > 1 else 0,
            ctx.costmap.costs,
            (float(geom.origin[0]), float(geom.origin[1])),
            geom.resolution,
            outline_data,
            clearance,
            self.circumscribed_cost,
            np.array(_outline_sizes(_NO_OUTLINE if cached is None else cached), np.intp),
            _CHUNK_STEPS,
        )

    def _scan_reference(
        self, ctx: PlanningContext, poses: FloatArray
    ) -> tuple[FloatArray, NDArray[np.bool_], NDArray[np.bool_]]:
        """Worst centre cost ``(N,)``, ``collision (N,)`` and ``unknown (N,)`` masks of the
        scored ``poses (N, S, 3)`` (NumPy; the reference for the compiled kernel)."""
        geom = ctx.costmap.geometry
        costs = ctx.costmap.costs
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
                clear, need_of = _clearance(ctx)
                need = need_of[clear[row, col]]
            else:
                k = _outline(ctx)[0].shape[0]
                need = np.where(centre >= self.circumscribed_cost, k, 0).astype(np.intp)
            # Only poses of still-legal trajectories need the expensive outline test.
            need[unknown | collision] = 0
            hit, unk = _outline_hits(ctx, poses, need)
            collision |= hit
            unknown |= unk
        return worst, collision, unknown


# Margin (cells) on the clearance bound: covers rounding of the outline transform, in float32
# poses too (an ulp at 1 km is ~1e-3 cells at 5 cm). A larger margin only checks more points.
_CLEARANCE_MARGIN = 0.05
# Steps per early-exit chunk: trajectories with a LETHAL hit are dropped between chunks.
_CHUNK_STEPS = 8
_HIT, _UNSEEN = np.uint8(1), np.uint8(2)
_NO_OUTLINE = np.zeros((1, 2))


def _start_in_collision(ctx: PlanningContext, pose: FloatArray, footprint: bool) -> bool:
    """Whether the pose ``(3,)`` is in collision by this critic's rules (centre or outline)."""
    geom = ctx.costmap.geometry
    rc = geom.world_to_cell(np.asarray(pose[:2], dtype=float))
    if not geom.in_bounds(rc):
        return False
    centre = int(ctx.costmap.costs[rc[0], rc[1]])
    if INSCRIBED <= centre < UNKNOWN:
        return True
    if not footprint:
        return False
    need = np.full((1, 1), _outline(ctx)[0].shape[0], dtype=np.intp)
    hit, _ = _outline_hits(ctx, np.asarray(pose, dtype=float)[None, None], need)
    return bool(hit[0])


def _never_closer(ctx: PlanningContext, poses: FloatArray, footprint: bool) -> NDArray[np.bool_]:
    """``(N,)``: the clearance of ``poses (N, T, 3)`` never decreases along the trajectory.

    Checked in time chunks; a trajectory is dropped at its first decrease (rare work: only when
    the robot starts in collision). The outline is sampled at the cell size here.
    """
    geom = ctx.costmap.geometry
    res = geom.resolution
    sdf = ctx.cache.occupancy_sdf
    if sdf is None:
        sdf = _signed_distance(ctx.costmap.costs == LETHAL, res, np.inf)
        ctx.cache.occupancy_sdf = sdf
    rows, cols = geom.shape
    inv = 1.0 / res
    flat_sdf = sdf.ravel()
    outline = footprint_outline(ctx.robot.polygon, res) if footprint else np.zeros((0, 2))

    def clearance(p: FloatArray) -> FloatArray:
        """``(M, S)`` clearance of poses ``(M, S, 3)``."""
        x = p[..., 0:1]
        y = p[..., 1:2]
        if outline.shape[0]:
            c, s = np.cos(p[..., 2:3]), np.sin(p[..., 2:3])
            x = np.concatenate([x, p[..., 0:1] + c * outline[:, 0] - s * outline[:, 1]], axis=-1)
            y = np.concatenate([y, p[..., 1:2] + s * outline[:, 0] + c * outline[:, 1]], axis=-1)
        col = np.floor((x - geom.origin[0]) * inv).astype(np.intp)
        row = np.floor((y - geom.origin[1]) * inv).astype(np.intp)
        inside = (row >= 0) & (row < rows) & (col >= 0) & (col < cols)
        value = flat_sdf.take(np.clip(row, 0, rows - 1) * cols + np.clip(col, 0, cols - 1))
        value = np.where(inside, value, -np.inf)
        value[..., 0] -= ctx.robot.inscribed_radius
        return value.min(axis=-1)

    n, steps = poses.shape[:2]
    ok = np.ones(n, dtype=bool)
    alive = np.arange(n)
    prev = clearance(poses[:, :1].astype(float))[:, 0]
    for t0 in range(1, steps, _CHUNK_STEPS):
        if not alive.size:
            break
        block = clearance(poses[alive, t0 : t0 + _CHUNK_STEPS].astype(float))  # (M, S)
        seq = np.concatenate([prev[:, None], block], axis=1)
        # Equal infinities (no LETHAL cell in the window: +inf; off the map: -inf) give
        # inf - inf = NaN, which is no decrease; only a real drop makes a step closer.
        with np.errstate(invalid="ignore"):
            good = ~np.any(np.diff(seq, axis=1) < -1e-9, axis=1)
        ok[alive[~good]] = False
        alive, prev = alive[good], block[good, -1]
    return ok


def _above_wall_floor(
    ctx: PlanningContext, poses: FloatArray, footprint: bool, candidates: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """``(N,)``: the ``candidates (N,)`` among ``poses (N, T, 3)`` (escape from overlap) whose
    clearance from the walls never falls below ``min(its start, -SHALLOW_OVERLAP)``.

    The walls (:func:`_walls`) are the LETHAL cells no tracked person marks and the free cells
    that free space does not join to the robot's own: :func:`_never_closer` reads a signed
    distance per cell, flat inside a cell and rising again beyond a wall one cell thick, so on
    its own it let a corner be pushed through such a wall. Here the distance is interpolated
    between cell centres (checked at the poses and at outline points a cell apart: the deepest
    point of a convex footprint against a straight wall is a vertex). A floor, not "never
    decreases": a robot braking beside a wall may come a little nearer, and one flush against
    a wall can still make a gentle turn. Known limit: a wall one cell thick whose far side
    free space joins to the robot's within the window (a free-standing partition, a wall's
    end) with the footprint already at its line: the clearance is lowest on the line, so a
    corner there can be pushed across.
    """
    ok = candidates.copy()
    idx = np.flatnonzero(ok)
    if not idx.size:
        return ok
    geom = ctx.costmap.geometry
    res = geom.resolution
    sdf = ctx.cache.occupancy_wall_sdf
    if sdf is None:
        sdf = _signed_distance(_walls(ctx, poses[0, 0]), res, _FAR)
        ctx.cache.occupancy_wall_sdf = sdf
    outline = footprint_outline(ctx.robot.polygon, res) if footprint else np.zeros((0, 2))

    def value(xy: FloatArray) -> FloatArray:
        """Interpolated wall clearance at world points ``xy (..., 2)`` (off the map: inf)."""
        f = (xy - np.asarray(geom.origin)) / res
        # index i is the centre of cell i, at i + 0.5 cells
        at = np.stack([f[..., 1].ravel() - 0.5, f[..., 0].ravel() - 0.5])
        v = map_coordinates(sdf, at, order=1, mode="nearest").reshape(f.shape[:-1])
        on = (f[..., 0] >= 0) & (f[..., 0] < geom.shape[1]) & (f[..., 1] >= 0)
        return np.where(on & (f[..., 1] < geom.shape[0]), v, np.inf)

    def clearance(p: FloatArray) -> FloatArray:
        """``(Q,)`` wall clearance of poses ``p (Q, 3)``: the outline's and the centre's."""
        c, s = np.cos(p[:, 2:3]), np.sin(p[:, 2:3])
        pts = np.stack(
            [
                p[:, :1] + c * outline[:, 0] - s * outline[:, 1],
                p[:, 1:2] + s * outline[:, 0] + c * outline[:, 1],
            ],
            axis=-1,
        )
        centre = value(p[:, :2]) - ctx.robot.inscribed_radius
        return np.minimum(centre, value(pts).min(axis=-1)) if outline.size else centre

    p = np.asarray(poses[idx], dtype=float)  # (M, T, 3)
    floor = min(float(clearance(p[0, :1])[0]), -SHALLOW_OVERLAP) - 1e-9
    # The interpolated distance changes at most √2 per unit: a pose whose centre is that far
    # beyond the circumscribed radius from every wall cannot reach the floor (below zero).
    near = value(p[..., :2]) < np.sqrt(2.0) * ctx.robot.circumscribed_radius
    low = np.zeros(near.shape, dtype=bool)
    low[near] = clearance(p[near]) < floor
    ok[idx[low.any(axis=1)]] = False
    return ok


def _signed_distance(inside: NDArray[np.bool_], res: float, far: float) -> FloatArray:
    """``(rows, cols)`` signed distance (m) of each cell centre to the boundary of ``inside``
    (positive outside, negative inside); ``far`` everywhere outside when nothing is inside,
    ``-res`` everywhere when everything is."""
    if inside.all() or not inside.any():
        return np.where(inside, -res, far)
    return (distance_transform_edt(~inside) - distance_transform_edt(inside)) * res


def _walls(ctx: PlanningContext, pose: FloatArray) -> NDArray[np.bool_]:
    """``(rows, cols)``: the LETHAL cells no tracked person marks, and the free cells that free
    space does not join to the cell of ``pose (3,)`` (4-connected; people's cells block the
    way too, so a person against a thin wall opens no way round it)."""
    cm = ctx.costmap
    lethal = cm.costs == LETHAL
    wall = lethal.copy()
    if ctx.social.people and wall.any():
        rc = np.argwhere(wall)
        centres = cm.geometry.cell_to_world(rc)
        grown = ctx.social.radii() + cm.resolution * (np.sqrt(2.0) / 2.0 + 1e-6)
        rel = centres[:, None, :] - ctx.social.positions()[None]
        theirs = (np.hypot(rel[..., 0], rel[..., 1]) <= grown[None]).any(axis=1)
        wall[rc[theirs, 0], rc[theirs, 1]] = False
    cell = cm.geometry.world_to_cell(np.asarray(pose[:2], dtype=float))
    if not cm.geometry.in_bounds(cell) or lethal[cell[0], cell[1]]:
        return wall
    labels, _ = label(~lethal)
    return wall | ((labels != labels[cell[0], cell[1]]) & ~lethal)


#: Escape from overlap (:func:`_above_wall_floor`): how far below zero (m) the clearance from
#: the walls may fall. Interpolated between cell centres, it falls twice as fast as the
#: distance across a wall one cell thick: 0.02 lets an outline point 1 cm into that cell, short
#: of the wall line it was marked for (at least resolution · (√2 − 1) / 2 ≈ 1.04 cm in at 5 cm
#: cells; ``world.raster``).
SHALLOW_OVERLAP = 0.02

#: Clearance (m) where the window has no wall: finite, so that interpolation stays exact.
_FAR = 1e9


@lru_cache(maxsize=16)
def _sorted_outline(polygon: bytes, vertices: int, res: float) -> tuple[FloatArray, FloatArray]:
    """The outline at half-cell spacing sorted far first and its radii (cells): it depends on
    the footprint and the resolution only, so cycles share it (never written to)."""
    poly = np.frombuffer(polygon, dtype=float).reshape(vertices, 2)
    outline = footprint_outline(poly, 0.5 * res)
    rho = np.hypot(outline[:, 0], outline[:, 1]) / res  # cells
    order = np.argsort(-rho, kind="stable")
    return outline[order], rho[order]


def _prepare_outline(ctx: PlanningContext) -> None:
    """The body-frame outline sorted by distance from the centre (far first) and the padded
    hit-code map: 0 free, 1 LETHAL, 2 UNKNOWN or off the map."""
    res = ctx.costmap.resolution
    polygon = np.ascontiguousarray(ctx.robot.polygon, dtype=float)
    outline, rho = _sorted_outline(polygon.tobytes(), polygon.shape[0], float(res))
    ctx.cache.occupancy_outline = outline
    ctx.cache.occupancy_outline_rho = rho
    # Checked poses have their centre on the map, so every outline point lies within the
    # circumscribed radius of the map: a border that wide replaces clipping and the in-map test.
    pad = math.ceil(float(rho.max(initial=0.0))) + 2
    costs = ctx.costmap.costs
    rows, cols = costs.shape
    # LETHAL (254) → 1, UNKNOWN (255) → 2, anything lower → 0; the border reads UNKNOWN.
    if kernels.enabled() and costs.dtype == np.uint8:  # one compiled pass, the same codes
        codes = kernels.hit_codes(costs, INSCRIBED, int(_UNSEEN), pad)
    else:
        codes = np.full((rows + 2 * pad, cols + 2 * pad), _UNSEEN, dtype=np.uint8)
        inner = codes[pad : pad + rows, pad : pad + cols]
        np.subtract(np.maximum(costs, np.uint8(INSCRIBED)), np.uint8(INSCRIBED), out=inner)
    ctx.cache.occupancy_codes = (codes, pad)


@lru_cache(maxsize=16)
def _outline_need(rho: bytes, e: int) -> NDArray[np.intp]:
    """``need (L,)``: outline points (of the sorted radii ``rho``, cells) a pose at each
    clearance level (1/16 cell, up to ``e + 1`` cells) must check; shared, never written to."""
    radii = np.frombuffer(rho, dtype=float)
    step = 1.0 / 16.0
    levels = np.arange((e + 1) * 16 + 1) * step
    need = np.count_nonzero(
        radii[None, :] >= (levels - math.sqrt(2.0) - _CLEARANCE_MARGIN)[:, None], axis=1
    ).astype(np.intp)
    return need


def _prepare_clearance(ctx: PlanningContext) -> None:
    """``occupancy_clearance (rows, cols)`` int index into ``occupancy_need (L,)``: how many of
    the sorted outline points a pose in that cell must check (module docstring).

    The clearance ``D`` (cells, a lower bound on the distance from the cell centre to the nearest
    LETHAL/UNKNOWN/off-map cell) comes from a Euclidean distance transform over the map or —
    when the planner published its ``reach`` — only the box the rollouts can enter (poses
    outside it then check every point).
    """
    rho = _outline(ctx)[1]
    rows, cols = ctx.costmap.geometry.shape
    # Window margin e: a hard cell outside the window is >= e + 1 cells away, beyond any reach.
    e = math.ceil(float(rho.max(initial=0.0)) + math.sqrt(2.0) + _CLEARANCE_MARGIN) + 1
    r0, r1, c0, c1 = 0, rows, 0, cols
    reach = ctx.cache.reach
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
        # A ring of hard cells where the window meets the map edge: off-map counts as hard.
        edges = ((int(a0 == 0), int(a1 == rows)), (int(b0 == 0), int(b1 == cols)))
        free = np.zeros((a1 - a0 + sum(edges[0]), b1 - b0 + sum(edges[1])), dtype=bool)
        inner = free[
            edges[0][0] : free.shape[0] - edges[0][1], edges[1][0] : free.shape[1] - edges[1][1]
        ]
        np.less(ctx.costmap.costs[a0:a1, b0:b1], LETHAL, out=inner)
        i0, j0 = r0 - a0 + edges[0][0], c0 - b0 + edges[1][0]
        if free.all():  # no hard cell in reach (the transform needs one)
            clear[r0:r1, c0:c1] = np.floor(float(e + 1) * (1.0 / step))
        elif kernels.enabled():  # exact transform and levels in one compiled pass
            kernels.clearance_levels(free, float(e + 1), i0, j0, clear[r0:r1, c0:c1])
        else:
            dist = np.minimum(distance_transform_edt(free), float(e + 1))
            box = dist[i0 : i0 + r1 - r0, j0 : j0 + c1 - c0]
            clear[r0:r1, c0:c1] = np.floor(box * (1.0 / step))
    # Points with rho >= D - √2 - margin may hit; rho is sorted descending. Rounding D down to
    # a level checks more points: still exact.
    ctx.cache.occupancy_clearance = clear
    ctx.cache.occupancy_need = _outline_need(np.ascontiguousarray(rho, dtype=float).tobytes(), e)


def _outline(ctx: PlanningContext) -> tuple[FloatArray, FloatArray, NDArray[np.uint8], int]:
    """The cycle's sorted outline ``(K, 2)``, its radii ``(K,)`` (cells), the padded hit-code
    map and its pad (cells); prepared on first use."""
    cache = ctx.cache
    if cache.occupancy_outline is None:
        _prepare_outline(ctx)
    outline, rho, packed = (
        cache.occupancy_outline,
        cache.occupancy_outline_rho,
        cache.occupancy_codes,
    )
    assert outline is not None and rho is not None and packed is not None
    return outline, rho, packed[0], packed[1]


def _clearance(ctx: PlanningContext) -> tuple[NDArray[np.uint16], NDArray[np.intp]]:
    """The cycle's ``occupancy_clearance`` and ``occupancy_need``; prepared on first use."""
    cache = ctx.cache
    if cache.occupancy_clearance is None:
        _prepare_clearance(ctx)
    clear, need = cache.occupancy_clearance, cache.occupancy_need
    assert clear is not None and need is not None
    return clear, need


def _outline_sizes(outline: FloatArray) -> list[int]:
    """Poses are grouped by how many outline points they need, rounded up to K, K/2, K/4, ..."""
    k_all = outline.shape[0]
    return sorted({max(1, math.ceil(k_all / 2**j)) for j in range(5)})


def _outline_hits(
    ctx: PlanningContext, poses: FloatArray, need: NDArray[np.intp]
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Outline LETHAL / UNKNOWN hits ``(N,)`` each for ``poses (N, T, 3)``, checking the first
    ``need (N, T)`` sorted outline points of each pose (0: skip the pose)."""
    geom = ctx.costmap.geometry
    n, steps = need.shape
    outline_k, _, codes, pad = _outline(ctx)
    outline = outline_k.astype(poses.dtype)  # (K, 2), far first
    flat_codes = codes.ravel()
    width = codes.shape[1]
    sizes = _outline_sizes(outline)
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

"""A navfn / global_planner-style grid planner: Dijkstra over the costmap.

Each 8-connected move between neighbouring cells ``u → v`` costs
``step · (neutral_cost + cost_factor · (c_u + c_v) / 2)``, with ``step`` the move length in
metres (``res`` or ``res·√2``) and ``c`` the costmap values (ROS global_planner defaults
neutral 50, factor 3). So a path through free space costs ``50 ×`` its length in metres.
Cells with cost ``>= lethal_cost`` (253: inscribed and lethal) are blocked, and UNKNOWN (255)
too unless ``allow_unknown``. Diagonal moves may not cut the corner of a blocked cell.

The search is ``scipy.sparse.csgraph.dijkstra`` from the start cell on a CSR graph with exactly
eight slots per cell, built with array code (absent edges carry weight ``inf``, so no sorting or
duplicate summing is needed). On a 500 × 500 grid (25 m at 0.05 m) graph + search take about
0.06–0.17 s (``benchmarks/bench_world.py``; 4–5× less at 0.1 m), fast enough for
replanning every few seconds, so no coarser planning grid is used.

Differences from ROS: the edge cost averages the two cells' costs (symmetric, so the plan does
not depend on the search direction); the path is the cell-centre chain (no gradient descent
over the potential field as navfn does), with the exact start and goal points at its ends and
collinear interior points kept (one point per cell, as ROS plans are dense). As ROS's
global_planner clears the robot's own cell, a start cell that is INSCRIBED is allowed; only a
LETHAL (or off-map) start is ``START_BLOCKED``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csr_array
from scipy.sparse.csgraph import dijkstra

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import as_points
from socialnav.planner import kernels
from socialnav.world.grid import LETHAL, UNKNOWN, Costmap, GridGeometry

PlanStatus = Literal["OK", "NO_PATH", "START_BLOCKED", "GOAL_BLOCKED"]
#: ``"scipy"``: Dijkstra over the whole grid (``scipy.sparse.csgraph``, holds the GIL; the
#: default). ``"compiled"``: A* with the octile lower bound (numba, no GIL, stops at the goal;
#: needs the compiled kernels, else falls back to ``"scipy"``). Both give the optimal cost
#: (equal to rounding) and the same statuses and substitute goals; where several paths cost
#: exactly the same they may pick different ones, so ``"compiled"`` is opt-in.
GlobalSearch = Literal["scipy", "compiled"]

# Neighbour offsets (d_row, d_col); one CSR slot each (the compiled A*'s order too).
_OFFSETS = kernels.ASTAR_OFFSETS


@dataclass(frozen=True)
class GlobalPlan:
    """``path (P, 2)`` world points from start to goal (``None`` unless ``status == "OK"``),
    its ``cost`` (cost units × m; ``inf`` when there is no path) and the ``goal (2,)`` it ends at
    (the requested goal, or its substitute under ``tolerance``; ``None`` without a path)."""

    path: NDArray[np.float64] | None
    status: PlanStatus
    cost: float
    goal: NDArray[np.float64] | None = None


def traversable(
    costs: NDArray[np.uint8], lethal_cost: int = 253, allow_unknown: bool = False
) -> NDArray[np.bool_]:
    """Cells the planner may enter ``(rows, cols)``."""
    ok = costs < lethal_cost
    if allow_unknown:
        ok |= costs == UNKNOWN
    return ok


def grid_graph(
    costs: NDArray[np.uint8],
    resolution: float,
    passable: NDArray[np.bool_],
    neutral_cost: float = 50.0,
    cost_factor: float = 3.0,
) -> csr_array:
    """8-connected directed graph ``(rows·cols, rows·cols)`` over the grid, node = row·cols + col.

    Edges exist between passable neighbours (diagonals only if both corner cells are passable).
    Passable UNKNOWN cells enter the weight with their raw value 255: usable but expensive.
    """
    rows, cols = costs.shape
    n = rows * cols
    index, indptr = _grid_structure(rows, cols)
    if kernels.enabled():  # one compiled pass, the same weights bit for bit
        steps = np.array([resolution * float(np.hypot(dr, dc)) for dr, dc in _OFFSETS])
        w8 = kernels.grid_weights(
            costs, passable, np.array(_OFFSETS), steps, neutral_cost, cost_factor
        )
        return csr_array((w8.reshape(-1), index.reshape(-1), indptr), shape=(n, n))
    c = costs.astype(np.float64)
    pad_ok = np.pad(passable, 1, constant_values=False)
    pad_c = np.pad(c, 1)
    weights = np.full((rows, cols, 8), np.inf)
    for k, (dr, dc) in enumerate(_OFFSETS):
        nb = (slice(1 + dr, 1 + dr + rows), slice(1 + dc, 1 + dc + cols))
        ok = passable & pad_ok[nb]
        if dr and dc:
            ok &= pad_ok[1 + dr : 1 + dr + rows, 1 : 1 + cols]
            ok &= pad_ok[1 : 1 + rows, 1 + dc : 1 + dc + cols]
        step = resolution * float(np.hypot(dr, dc))
        w = step * (neutral_cost + cost_factor * 0.5 * (c + pad_c[nb]))
        weights[..., k] = np.where(ok, w, np.inf)
    return csr_array((weights.reshape(-1), index.reshape(-1), indptr), shape=(n, n))


@lru_cache(maxsize=8)
def _grid_structure(rows: int, cols: int) -> tuple[NDArray[np.integer], NDArray[np.integer]]:
    """The CSR column indices ``(rows, cols, 8)`` and row pointers of the 8-slot grid graph:
    they depend on the shape only, so replanning on the same map reuses them (read-only)."""
    n = rows * cols
    rr = np.arange(rows)[:, None]
    cc = np.arange(cols)[None, :]
    index = np.empty((rows, cols, 8), dtype=np.int32 if n < 2**31 else np.int64)
    for k, (dr, dc) in enumerate(_OFFSETS):
        # Border slots point at a clipped (valid) node; their weight is inf, so never used.
        index[..., k] = np.clip(rr + dr, 0, rows - 1) * cols + np.clip(cc + dc, 0, cols - 1)
    indptr = np.arange(0, 8 * n + 1, 8, dtype=index.dtype)
    index.setflags(write=False)
    indptr.setflags(write=False)
    return index, indptr


def plan_path(
    costmap: Costmap,
    start_xy: ArrayLike,
    goal_xy: ArrayLike,
    neutral_cost: float = 50.0,
    cost_factor: float = 3.0,
    lethal_cost: int = 253,
    allow_unknown: bool = False,
    tolerance: float = 0.0,
    substitutes: NDArray[np.bool_] | None = None,
    search: GlobalSearch = "scipy",
) -> GlobalPlan:
    """Cheapest 8-connected path from ``start_xy (2,)`` to ``goal_xy (2,)`` (m) over ``costmap``.

    Statuses: ``START_BLOCKED`` (start off the map or on a LETHAL cell; any other start cell is
    treated as free, like ROS clearing the robot cell), ``GOAL_BLOCKED``
    (goal off the map or on a blocked cell), ``NO_PATH`` (disconnected), ``OK``.

    ``tolerance`` (m) is navfn's ``default_tolerance``: when the goal is blocked or not reachable,
    the plan ends instead at the cell centre nearest the goal, within ``tolerance``, that is
    *reachable from the start* (navfn searches the potential it propagated from the robot); the
    status is then ``OK`` and ``GlobalPlan.goal`` is that substitute. A goal off the map gets
    one too when a reachable cell lies within the tolerance. ``substitutes (rows, cols)``
    optionally restricts which cells may be substitutes (e.g. those with room for the whole
    footprint in any orientation). ``search``: :data:`GlobalSearch`.
    Raises ``InvalidInputError`` only on malformed input (NaN, wrong shape, bad parameters).
    """
    start = as_points(start_xy, "start_xy")
    goal = as_points(goal_xy, "goal_xy")
    if start.shape != (2,) or goal.shape != (2,):
        raise InvalidInputError("start_xy and goal_xy must have shape (2,)")
    if not (np.isfinite(neutral_cost) and neutral_cost > 0):
        raise InvalidInputError(f"neutral_cost must be positive, got {neutral_cost}")
    if not (np.isfinite(cost_factor) and cost_factor >= 0):
        raise InvalidInputError(f"cost_factor must be >= 0, got {cost_factor}")
    if not 1 <= lethal_cost <= UNKNOWN:
        raise InvalidInputError(f"lethal_cost must be in [1, 255], got {lethal_cost}")
    if not (np.isfinite(tolerance) and tolerance >= 0):
        raise InvalidInputError(f"tolerance must be finite and >= 0, got {tolerance}")
    if search not in ("scipy", "compiled"):
        raise InvalidInputError(f"search must be 'scipy' or 'compiled', got {search!r}")

    geo = costmap.geometry
    costs = costmap.costs
    s_rc = geo.world_to_cell(start)
    g_rc = geo.world_to_cell(goal)
    if not geo.in_bounds(s_rc) or costs[s_rc[0], s_rc[1]] == LETHAL:
        return GlobalPlan(None, "START_BLOCKED", float("inf"))
    passable = traversable(costs, lethal_cost, allow_unknown)
    goal_ok = bool(geo.in_bounds(g_rc)) and bool(passable[g_rc[0], g_rc[1]])
    if not goal_ok and tolerance <= 0:
        return GlobalPlan(None, "GOAL_BLOCKED", float("inf"))
    # The robot's own cell is always enterable/leavable (ROS clears it).
    passable = passable.copy()
    passable[s_rc[0], s_rc[1]] = True

    cols = geo.shape[1]
    s_idx = int(s_rc[0] * cols + s_rc[1])
    g_idx = int(g_rc[0] * cols + g_rc[1]) if goal_ok else -1
    if s_idx == g_idx:
        return GlobalPlan(np.stack([start, goal]), "OK", 0.0, goal)

    if search == "compiled" and kernels.enabled():
        steps = np.array([geo.resolution * float(np.hypot(dr, dc)) for dr, dc in _OFFSETS])
        dist, pred = kernels.astar(
            costs,
            passable,
            s_idx,
            g_idx,
            steps,
            neutral_cost,
            cost_factor,
            geo.resolution,
            reuse=True,  # this thread's kept arrays: read below, before any other search
        )
    else:
        graph = grid_graph(costs, geo.resolution, passable, neutral_cost, cost_factor)
        dist, pred = dijkstra(graph, directed=True, indices=s_idx, return_predecessors=True)
    if g_idx < 0 or not np.isfinite(dist[g_idx]):
        substitute = _reachable_within(geo, dist, goal, tolerance, substitutes)
        if substitute is None:
            return GlobalPlan(None, "GOAL_BLOCKED" if not goal_ok else "NO_PATH", float("inf"))
        g_idx = int(substitute)
        goal = geo.cell_to_world(np.array([g_idx // cols, g_idx % cols]))
        if g_idx == s_idx:
            return GlobalPlan(np.stack([start, goal]), "OK", 0.0, goal)

    if kernels.enabled():
        nodes = kernels.predecessor_chain(pred, s_idx, g_idx)
    else:
        chain = [g_idx]
        node = g_idx
        while node != s_idx:
            node = int(pred[node])
            chain.append(node)
        nodes = np.asarray(chain[::-1])
    centres = geo.cell_to_world(np.stack([nodes // cols, nodes % cols], axis=-1))
    path = np.concatenate([start[None], centres[1:-1], goal[None]], axis=0)
    return GlobalPlan(path, "OK", float(dist[g_idx]), goal)


def path_cost(
    costmap: Costmap,
    path: ArrayLike,
    start_xy: ArrayLike | None = None,
    neutral_cost: float = 50.0,
    cost_factor: float = 3.0,
    lethal_cost: int = 253,
) -> float:
    """The cost of following the polyline ``path (P, 2)`` (m, world) over ``costmap``, in the
    search's units: ``∫ (neutral_cost + cost_factor · c(x)) ds`` sampled every half cell, so
    a plan and another route are compared on the same costmap alike. ``inf`` when a sample
    is off the map or on a cell the search may not enter (``>= lethal_cost``), except the
    cell of ``start_xy (2,)`` (the robot's own cell, which the search clears too)."""
    return path_costs(costmap, path, start_xy, neutral_cost, cost_factor, lethal_cost)[0]


def path_length(path: ArrayLike) -> float:
    """Length (m) of the polyline ``path (P, 2)`` (0 for fewer than two points). Raises
    ``InvalidInputError`` on another shape (poses ``(P, 3)`` included) or a non-finite point."""
    xy = as_points(path, "path")
    if xy.ndim != 2:
        raise InvalidInputError(f"path must have shape (P, 2), got {xy.shape}")
    return float(np.hypot(*np.diff(xy, axis=0).T).sum())


def path_costs(
    costmap: Costmap,
    path: ArrayLike,
    start_xy: ArrayLike | None = None,
    neutral_cost: float = 50.0,
    cost_factor: float = 3.0,
    lethal_cost: int = 253,
) -> tuple[float, int]:
    """:func:`path_cost` and the highest cell cost (0–255) the path crosses, outside the
    cell of ``start_xy``: ``(inf, 255)`` when it is blocked or leaves the map."""
    pts = as_points(path, "path").reshape(-1, 2)
    if pts.shape[0] < 2:
        return 0.0, 0
    geo = costmap.geometry
    seg = np.diff(pts, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    n = np.maximum(np.ceil(length / (0.5 * geo.resolution)).astype(int), 1)
    # Midpoints of n equal pieces per segment, each weighted by its piece length.
    k = np.repeat(np.arange(len(n)), n)
    frac = (np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n) + 0.5) / n[k]
    samples = pts[k] + frac[:, None] * seg[k]
    ds = (length / n)[k]
    cells = geo.world_to_cell(samples)
    if not np.all(geo.in_bounds(cells)):
        return float("inf"), 255
    c = costmap.costs[cells[:, 0], cells[:, 1]]
    outside = np.ones(len(c), dtype=bool)
    if start_xy is not None:
        s_rc = geo.world_to_cell(as_points(start_xy, "start_xy"))
        outside = ~((cells[:, 0] == s_rc[0]) & (cells[:, 1] == s_rc[1]))
    if np.any(outside & (c >= lethal_cost)):
        return float("inf"), 255
    peak = int(c[outside].max()) if outside.any() else 0
    return float(np.sum(ds * (neutral_cost + cost_factor * c.astype(np.float64)))), peak


def _reachable_within(
    geo: GridGeometry,
    dist: NDArray[np.float64],
    goal: NDArray[np.float64],
    tolerance: float,
    allowed: NDArray[np.bool_] | None,
) -> int | None:
    """Flat index of the reached cell nearest ``goal`` within ``tolerance`` m (window search)."""
    if tolerance <= 0:
        return None
    res = geo.resolution
    rows, cols = geo.shape
    ox, oy = geo.origin
    # Only the cells of the tolerance's bounding box, clipped to the grid: bounded work.
    c0 = max(int(np.floor((goal[0] - tolerance - ox) / res)), 0)
    c1 = min(int(np.floor((goal[0] + tolerance - ox) / res)) + 1, cols)
    r0 = max(int(np.floor((goal[1] - tolerance - oy) / res)), 0)
    r1 = min(int(np.floor((goal[1] + tolerance - oy) / res)) + 1, rows)
    if r0 >= r1 or c0 >= c1:
        return None
    rr, cc = np.mgrid[r0:r1, c0:c1]
    d = np.hypot(ox + (cc + 0.5) * res - goal[0], oy + (rr + 0.5) * res - goal[1])
    reached = np.isfinite(dist.reshape(rows, cols)[r0:r1, c0:c1]) & (d <= tolerance)
    if allowed is not None:
        reached &= allowed[r0:r1, c0:c1]
    if not reached.any():
        return None
    k = int(np.argmin(np.where(reached, d, np.inf)))
    return int(rr.reshape(-1)[k] * cols + cc.reshape(-1)[k])


def nearest_free(
    costmap: Costmap, xy: ArrayLike, tolerance: float, lethal_cost: int = 253
) -> NDArray[np.float64] | None:
    """The traversable cell centre nearest ``xy`` within ``tolerance`` m, or None.

    navfn's ``default_tolerance``: a goal inside an obstacle (a person standing on it) is
    replaced by the closest reachable point, as the ROS planner does.
    """
    p = np.asarray(xy, dtype=float)
    geometry = costmap.geometry
    xs, ys = geometry.cell_centers()
    distance = np.hypot(xs - p[0], ys - p[1])
    candidates = traversable(costmap.costs, lethal_cost) & (distance <= tolerance)
    if not candidates.any():
        return None
    flat = np.where(candidates, distance, np.inf).argmin()
    row, col = np.unravel_index(flat, distance.shape)
    return np.array([xs[row, col], ys[row, col]])

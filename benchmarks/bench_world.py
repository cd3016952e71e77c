"""World-model benchmarks: inflation, the proxemic layer and global planning.

Run: ``.venv/bin/python benchmarks/bench_world.py``. Baselines are naive variants measured in
the same run on the same input: a per-cell Python inflation and a brute-force distance, the
proxemic layer evaluated on the full grid per person, and a hand-written ``heapq`` Dijkstra.
"""

from __future__ import annotations

import heapq
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from harness import Case, run_table
from socialnav.core.robot import PR2
from socialnav.planner.global_planner import plan_path, traversable
from socialnav.world.grid import Costmap, GridGeometry
from socialnav.world.inflation import inflate, inflation_cost
from socialnav.world.proxemic_layer import proxemic_costs
from socialnav.world.raster import rasterize

R_INS = PR2.inscribed_radius
R_INF = 0.55


def room(resolution: float) -> tuple[GridGeometry, np.ndarray]:
    """25 × 25 m room: boundary walls, the queue desk and a few pillars and partitions."""
    geo = GridGeometry((round(25 / resolution), round(25 / resolution)), resolution)
    walls = np.array(
        [
            [[0, 0], [25, 0]],
            [[25, 0], [25, 25]],
            [[25, 25], [0, 25]],
            [[0, 25], [0, 0]],
            [[5, 8], [15, 8]],
            [[15, 3], [15, 8]],
            [[3, 15], [9, 21]],
        ],
        dtype=float,
    )
    desk = np.array([[11.7, 20.0], [13.3, 20.0], [13.3, 20.6], [11.7, 20.6]])
    pillars = np.array([[20, 12, 0.3], [6, 4, 0.4], [18, 20, 0.25]], dtype=float)
    return geo, rasterize(geo, walls, [desk], pillars, thickness=0.1)


def hallway(resolution: float) -> tuple[GridGeometry, np.ndarray]:
    """20 × 3 m corridor, walls at y = ±1.5 (grid y from -1.6 to 1.6)."""
    geo = GridGeometry((round(3.2 / resolution), round(20 / resolution)), resolution, (0.0, -1.6))
    walls = np.array([[[0, -1.5], [20, -1.5]], [[0, 1.5], [20, 1.5]]], dtype=float)
    return geo, rasterize(geo, walls, thickness=0.1)


def naive_inflation(occupied: np.ndarray, resolution: float) -> np.ndarray:
    """Per-cell Python loops over cells × obstacle cells (the textbook version)."""
    obstacles = list(zip(*np.nonzero(occupied), strict=True))
    out = np.zeros(occupied.shape, np.uint8)
    for r in range(occupied.shape[0]):
        for c in range(occupied.shape[1]):
            d = min(math.hypot(r - orow, c - ocol) for orow, ocol in obstacles) * resolution
            out[r, c] = int(inflation_cost(d, R_INS, 10.0, R_INF))
    return out


def brute_force_distance_inflation(occupied: np.ndarray, resolution: float) -> np.ndarray:
    """NumPy brute force: every cell against every obstacle cell (chunked), no transform."""
    obs = np.argwhere(occupied).astype(float)
    cells = np.indices(occupied.shape).reshape(2, -1).T.astype(float)
    best = np.empty(len(cells))
    for i in range(0, len(cells), 4096):
        chunk = cells[i : i + 4096]
        d2 = ((chunk[:, None, :] - obs[None, :, :]) ** 2).sum(-1)
        best[i : i + 4096] = np.sqrt(d2.min(axis=1)) * resolution
    return inflation_cost(best.reshape(occupied.shape), R_INS, 10.0, R_INF)


def full_grid_proxemic(geo: GridGeometry, pos: np.ndarray, vel: np.ndarray) -> np.ndarray:
    """Per person over every cell (no bounding window)."""
    xs, ys = geo.cell_centers()
    out = np.zeros(geo.shape, np.uint8)
    for (px, py), (vx, vy) in zip(pos, vel, strict=True):
        th = math.atan2(vy, vx)
        vf = 0.25 * (1 + 5 * math.hypot(vx, vy))
        mx = (xs - px) * math.cos(th) + (ys - py) * math.sin(th)
        my = (ys - py) * math.cos(th) - (xs - px) * math.sin(th)
        a = 77 * np.exp(-(mx**2 / (2 * np.where(mx > 0, vf, 0.25)) + my**2 / 0.5))
        out = np.maximum(out, np.where(a >= 10, np.floor(a), 0).astype(np.uint8))
    return out


def heapq_dijkstra(costmap: Costmap, start: np.ndarray, goal: np.ndarray) -> float:
    """Hand-written 8-connected Dijkstra with the same edge weights (the naive baseline)."""
    costs = costmap.costs.astype(float)
    ok = traversable(costmap.costs)
    rows, cols = costs.shape
    res = costmap.resolution
    s = tuple(costmap.geometry.world_to_cell(start))
    g = tuple(costmap.geometry.world_to_cell(goal))
    dist = {s: 0.0}
    heap = [(0.0, s)]
    while heap:
        d, (r, c) = heapq.heappop(heap)
        if (r, c) == g:
            return d
        if d > dist.get((r, c), math.inf):
            continue
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if (dr or dc) and 0 <= nr < rows and 0 <= nc < cols and ok[nr, nc]:
                    if dr and dc and not (ok[r, nc] and ok[nr, c]):
                        continue
                    w = res * math.hypot(dr, dc) * (50 + 1.5 * (costs[r, c] + costs[nr, nc]))
                    if d + w < dist.get((nr, nc), math.inf):
                        dist[(nr, nc)] = d + w
                        heapq.heappush(heap, (d + w, (nr, nc)))
    return math.inf


def main() -> None:
    cases: list[Case] = []

    geo, occ = room(0.05)
    crop_occ = occ[:60, :60]  # 3 × 3 m corner of the room
    crop_geo = GridGeometry(crop_occ.shape, 0.05)
    np.testing.assert_array_equal(
        naive_inflation(crop_occ, 0.05), inflate(crop_occ, crop_geo, R_INS, R_INF).costs
    )
    cases += [
        Case(
            "inflate 3x3 m @0.05 (60x60)",
            "per-cell Python",
            lambda: naive_inflation(crop_occ, 0.05),
            repeats=1,
            warmup=0,
            baseline="per-cell Python",
        ),
        Case(
            "inflate 3x3 m @0.05 (60x60)",
            "distance_transform_edt",
            lambda: inflate(crop_occ, crop_geo, R_INS, R_INF),
            baseline="per-cell Python",
        ),
        Case(
            "inflate 25x25 m @0.05 (500x500)",
            "brute-force distance",
            lambda: brute_force_distance_inflation(occ, 0.05),
            repeats=1,
            warmup=0,
            baseline="brute-force distance",
            extra={"obstacle cells": str(int(occ.sum()))},
        ),
        Case(
            "inflate 25x25 m @0.05 (500x500)",
            "distance_transform_edt",
            lambda: inflate(occ, geo, R_INS, R_INF),
            baseline="brute-force distance",
            extra={"obstacle cells": str(int(occ.sum()))},
        ),
    ]

    rng = np.random.default_rng(0)
    for k in (1, 5, 20):
        pos = rng.uniform(2, 23, size=(k, 2))
        vel = rng.uniform(-1.2, 1.2, size=(k, 2))
        np.testing.assert_array_equal(
            full_grid_proxemic(geo, pos, vel), proxemic_costs(geo, pos, vel)
        )
        group = f"proxemic 500x500, {k} people"
        cases += [
            Case(
                group,
                "full grid per person",
                lambda p=pos, v=vel: full_grid_proxemic(geo, p, v),
                repeats=3,
                baseline="full grid per person",
            ),
            Case(
                group,
                "windows, vectorized",
                lambda p=pos, v=vel: proxemic_costs(geo, p, v),
                baseline="full grid per person",
            ),
        ]

    room_cm = inflate(occ, geo, R_INS, R_INF)
    geo10, occ10 = room(0.1)
    room_cm10 = inflate(occ10, geo10, R_INS, R_INF)
    r_start, r_goal = np.array([20.0, 3.0]), np.array([4.0, 20.0])
    plan = plan_path(room_cm, r_start, r_goal)
    assert plan.status == "OK", plan.status
    assert math.isclose(heapq_dijkstra(room_cm, r_start, r_goal), plan.cost, rel_tol=1e-9)
    hgeo, hocc = hallway(0.05)
    hall_cm = inflate(hocc, hgeo, R_INS, R_INF)
    h_start, h_goal = np.array([1.0, 0.0]), np.array([19.0, 0.0])
    assert plan_path(hall_cm, h_start, h_goal).status == "OK"
    cases += [
        Case(
            "plan room 25x25 m @0.05 (250k cells)",
            "heapq Dijkstra",
            lambda: heapq_dijkstra(room_cm, r_start, r_goal),
            repeats=1,
            warmup=0,
            baseline="heapq Dijkstra",
            extra={"path pts": str(len(plan.path))},
        ),
        Case(
            "plan room 25x25 m @0.05 (250k cells)",
            "csgraph Dijkstra",
            lambda: plan_path(room_cm, r_start, r_goal),
            baseline="heapq Dijkstra",
            extra={"path pts": str(len(plan.path))},
        ),
        Case(
            "plan room 25x25 m @0.05 (250k cells)",
            "csgraph @0.10 (62.5k)",
            lambda: plan_path(room_cm10, r_start, r_goal),
            baseline="heapq Dijkstra",
        ),
        Case(
            "plan hallway 20x3 m @0.05 (25.6k cells)",
            "heapq Dijkstra",
            lambda: heapq_dijkstra(hall_cm, h_start, h_goal),
            repeats=3,
            baseline="heapq Dijkstra",
        ),
        Case(
            "plan hallway 20x3 m @0.05 (25.6k cells)",
            "csgraph Dijkstra",
            lambda: plan_path(hall_cm, h_start, h_goal),
            baseline="heapq Dijkstra",
        ),
    ]
    run_table(cases, title="world: inflation, proxemic layer, global planner")


if __name__ == "__main__":
    main()

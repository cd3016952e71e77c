"""One local-planner cycle: rollout, all navigation critics (incl. per-cycle BFS grids), selection.

Run: ``.venv/bin/python benchmarks/bench_planner.py [--quick]``.

Setup: a 10 m × 10 m local costmap at 0.05 m (200 × 200 cells) with walls and boxes, inflated
for the PR2; the robot in the middle with a global plan across the window. ``N × T`` = samples ×
poses per rollout (T includes t = 0); the twists are a fixed grid over the PR2's limits and the
granularity is set so the shared time grid has exactly T poses. Sampling itself is timed as the
"sample" stage of the per-stage medians (the dynamic-window sampler produces its own N).

Baseline: a per-sample Python loop (ROS-style: rollout step by step with ``math``, centre cost and
footprint outline per pose, BFS-grid lookups, heading) over the *same* BFS grids (their cost is
excluded from the baseline, i.e. flattering it), measured on ``LOOP_SAMPLES`` samples in this run
and scaled per sample to N.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Case, Row, format_seconds, print_rows, quick_option, time_case, time_interleaved
from socialnav.core.robot import PR2
from socialnav.moo.selection import WeightedSum
from socialnav.planner import kernels
from socialnav.planner import objectives as objective_module
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics import (
    GoalDistanceCritic,
    HeadingCritic,
    OccupancyCritic,
    PathDistanceCritic,
)
from socialnav.planner.critics.occupancy import footprint_outline
from socialnav.planner.local_planner import LocalPlannerParams, traditional_planner
from socialnav.planner.objectives import Objective, evaluate
from socialnav.planner.rollout import RolloutParams, rollout
from socialnav.world.grid import INSCRIBED, LETHAL, UNKNOWN, GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize

LOOP_SAMPLES = 20
ROBOT = PR2
POSE = np.array([5.0, 5.0, 0.2])
VEL = np.array([0.3, 0.0, 0.0])
PATH = np.column_stack([np.linspace(5.0, 9.8, 97), 5.0 + 1.5 * np.sin(np.linspace(0, 2, 97))])


def local_costmap():
    geom = GridGeometry((200, 200), 0.05)
    walls = np.array([[[0.3, 2.0], [9.7, 2.0]], [[0.3, 8.3], [9.7, 8.3]], [[7.0, 2.0], [7.0, 4.3]]])
    boxes = [
        np.array([[3.0, 6.0], [4.0, 6.0], [4.0, 7.0], [3.0, 7.0]]),
        np.array([[6.0, 3.4], [6.6, 3.4], [6.6, 4.0], [6.0, 4.0]]),
    ]
    occ = rasterize(geom, segments=walls, polygons=boxes, thickness=0.1)
    return inflate(occ, geom, ROBOT.inscribed_radius)


COSTMAP = local_costmap()


def twist_grid(n: int) -> np.ndarray:
    """``n`` twists on a vx × vy × wz grid over the robot's limits."""
    k = math.ceil(n ** (1 / 3)) + 1
    vx = np.linspace(ROBOT.min_vel_x, ROBOT.max_vel_x, k)
    vy = np.linspace(-ROBOT.max_vel_y, ROBOT.max_vel_y, k)
    w = np.linspace(-ROBOT.max_vel_theta, ROBOT.max_vel_theta, k)
    g = np.stack(np.meshgrid(vx, vy, w, indexing="ij"), -1).reshape(-1, 3)
    g = g[np.argsort(np.abs(g).sum(1), kind="stable")][::-1]  # keep the fastest (max reach)
    return np.ascontiguousarray(g[:n])


def rollout_params(twists: np.ndarray, poses_per_rollout: int) -> RolloutParams:
    steps = poses_per_rollout - 1
    trans = float(np.hypot(twists[:, 0], twists[:, 1]).max())
    rot = float(np.abs(twists[:, 2]).max())
    sim_time = 1.7
    return RolloutParams(
        sim_time,
        trans * sim_time / steps * 1.0000001,
        max(rot * sim_time / steps * 1.0000001, 1e-3),
    )


def objectives(footprint: bool) -> tuple[Objective, ...]:
    p = LocalPlannerParams()
    return (
        Objective(
            "navigation",
            (
                (PathDistanceCritic(), p.path_distance_bias),
                (GoalDistanceCritic(), p.goal_distance_bias),
                (OccupancyCritic(footprint=footprint), p.occdist_scale),
                (HeadingCritic(), p.heading_scale),
            ),
        ),
    )


def fresh_ctx(reach: float) -> PlanningContext:
    ctx = PlanningContext(POSE, VEL, np.array([*PATH[-1], 0.0]), PATH, COSTMAP, ROBOT)
    ctx.cache.reach = reach
    return ctx


def make_cycle(n: int, t: int, footprint: bool, dtype=np.float64):
    twists = twist_grid(n)
    params = rollout_params(twists, t)
    objs = objectives(footprint)
    select = WeightedSum([1.0])
    reach = float(np.hypot(twists[:, 0], twists[:, 1]).max()) * params.sim_time + 0.1

    def cycle():
        ctx = fresh_ctx(reach)
        trajs = rollout(POSE, VEL, twists, ROBOT, params, dtype=dtype)
        assert trajs.poses.shape == (n, t, 3)
        ev = evaluate(objs, trajs, ctx)
        return select.select(ev.F, ev.legal)

    return cycle, twists, params, reach


def python_loop(twists: np.ndarray, params: RolloutParams, reach: float):
    """ROS-style per-sample scoring in plain Python (BFS grids precomputed, as ROS shares them)."""
    ctx = fresh_ctx(reach)
    objs = objectives(True)
    evaluate(objs, rollout(POSE, VEL, twists[:1], ROBOT, params), ctx)  # fills the BFS grids
    pgrid, ggrid = ctx.cache.path_distance_grid, ctx.cache.goal_distance_grid
    costs = COSTMAP.costs.tolist()  # nested lists: the fastest plain-Python cell lookup
    ox, oy = COSTMAP.geometry.origin
    res = COSTMAP.resolution
    outline = [tuple(p) for p in footprint_outline(ROBOT.polygon, res / 2)]
    steps = round(
        params.sim_time / params.sim_granularity * float(np.hypot(twists[:, 0], twists[:, 1]).max())
    )
    steps = max(steps, 1)
    dt = params.sim_time / steps
    plan = ctx.cache.heading_plan
    dense, tangent = plan.dense, plan.tangent
    dense_l = [tuple(p) for p in dense]

    def cell(x, y):
        return math.floor((y - oy) / res), math.floor((x - ox) / res)

    def run():
        best, best_i = math.inf, -1
        for i, (vx, vy, w) in enumerate(twists.tolist()):
            x, y, th = POSE.tolist()
            occ, legal = 0.0, True
            for _ in range(steps):
                c, s = math.cos(th), math.sin(th)
                x += (vx * c - vy * s) * dt
                y += (vx * s + vy * c) * dt
                th += w * dt
                r, q = cell(x, y)
                cc = costs[r][q]
                if cc >= INSCRIBED:
                    legal = False
                    break
                occ = max(occ, cc)
                c, s = math.cos(th), math.sin(th)
                for bx, by in outline:
                    r, q = cell(x + c * bx - s * by, y + s * bx + c * by)
                    if costs[r][q] in (LETHAL, UNKNOWN):
                        legal = False
                        break
                if not legal:
                    break
            if not legal:
                continue
            r, q = cell(x, y)
            pd, gd = float(pgrid[r, q]), float(ggrid[r, q])
            if not (math.isfinite(pd) and math.isfinite(gd)):
                continue
            j = min(
                range(len(dense_l)),
                key=lambda k: (dense_l[k][0] - x) ** 2 + (dense_l[k][1] - y) ** 2,
            )
            hd = abs((th - tangent[j] + math.pi) % (2 * math.pi) - math.pi)
            cost = 0.6 * pd * res + 0.8 * gd * res + 0.01 * occ * res + 0.2 * hd
            if cost < best:
                best, best_i = cost, i
        return best_i

    return run


def with_kernels(flag: bool, fn):
    """``fn`` run with the compiled kernels on (``True``) or the NumPy reference (``False``)."""

    def run():
        previous = kernels.set_enabled(flag)
        try:
            return fn()
        finally:
            kernels.set_enabled(previous)

    return run


def fresh_grids(fn):
    """``fn`` run without the cross-cycle reuse of prepared grids (every cycle prepares anew,
    as a moving robot's shifting window does, and as the implementation before it did)."""

    def run():
        saved = objective_module._REUSE
        objective_module._REUSE = objective_module.PreparedReuse(size=0)
        try:
            return fn()
        finally:
            objective_module._REUSE = saved

    return run


def compiled_vs_reference(repeats: int) -> None:
    """Full cycle (sampling excluded: fixed twists) on the compiled kernels against the NumPy
    reference, each with fresh grids every cycle and with the prepared grids reused (this scene
    is static: every cycle after the first reuses them), interleaved in one run; wall and
    CPU-time medians. Baseline = NumPy reference with fresh grids (the implementation before)."""
    if not kernels.enabled():
        print("\n(compiled kernels unavailable or SOCIALNAV_KERNELS=reference: skipped)")
        return
    print(f"\nkernel compile/cache load at planner construction: {kernels.compile_seconds:.2f} s")
    header = (
        "| N x T | occupancy | variant | wall (median) | wall (min) | CPU (median) "
        "| speed-up (CPU) |"
    )
    print("\n## Compiled kernels vs the NumPy reference (same run, interleaved)\n")
    print(header)
    print("|" + "|".join("---" for _ in range(7)) + "|")
    for n, t in ((400, 34), (2000, 56)):
        for footprint in (True, False):
            cycle, *_ = make_cycle(n, t, footprint)
            variants = {
                "numpy reference, fresh grids (baseline)": fresh_grids(with_kernels(False, cycle)),
                "numpy reference, grids reused": with_kernels(False, cycle),
                "compiled, fresh grids": fresh_grids(with_kernels(True, cycle)),
                "compiled, grids reused": with_kernels(True, cycle),
            }
            chosen = {fn().index for fn in variants.values()}
            assert len(chosen) == 1, "compiled and reference selections differ"
            timed = time_interleaved(list(variants.values()), repeats, warmup=2)
            base = timed[0][2]
            fp = "footprint" if footprint else "centre only"
            for name, (w, wmin, c) in zip(variants, timed, strict=True):
                ratio = "" if c == base else f"{base / c:.1f}x"
                print(
                    f"| {n}x{t} | {fp} | {name} | {format_seconds(w)} | {format_seconds(wmin)} "
                    f"| {format_seconds(c)} | {ratio} |"
                )


def main(quick: bool = False) -> None:
    repeats = 5 if quick else 15
    kernels.warmup()
    compiled_vs_reference(3 * repeats)
    rows: list[Row] = []
    for n, t in ((400, 34), (2000, 56)):
        group = f"{n}x{t}"
        cases = []
        for footprint in (True, False):
            fp = "footprint" if footprint else "centre only"
            cycle, *_ = make_cycle(n, t, footprint)
            cycle = fresh_grids(with_kernels(False, cycle))
            cases.append(Case(group, f"numpy f64, {fp}", cycle, repeats=repeats, warmup=2))
        cycle32, *_ = make_cycle(n, t, True, np.float32)
        cycle32 = fresh_grids(with_kernels(False, cycle32))
        cases.append(Case(group, "numpy f32, footprint", cycle32, repeats=repeats, warmup=2))
        _, twists, params, reach = make_cycle(n, t, True)
        picked = twists[:: max(1, n // LOOP_SAMPLES)][:LOOP_SAMPLES]
        loop = python_loop(picked, params, reach)
        median, best = time_case(Case(group, "loop", loop, repeats=3, warmup=1))
        scale = n / LOOP_SAMPLES
        base = Row(
            group,
            "python loop (scaled)",
            median * scale,
            best * scale,
            3,
            None,
            {"note": f"{LOOP_SAMPLES} samples, x{scale:g}"},
        )
        rows.append(base)
        for case in cases:
            median, best = time_case(case)
            rows.append(
                Row(group, case.variant, median, best, case.repeats, base.median_s / median, {})
            )
    print_rows(
        rows,
        "Local planner cycle (rollout + 4 critics incl. BFS grids + selection), "
        "10 m x 10 m costmap at 0.05 m; NumPy reference, fresh grids every cycle",
    )

    # Stage breakdown of the real planner (dynamic-window samples, PR2 defaults).
    planner = traditional_planner(ROBOT)
    stages: dict[str, list[float]] = {}
    for _ in range(repeats):
        ctx = PlanningContext(POSE, VEL, np.array([*PATH[-1], 0.0]), PATH, COSTMAP, ROBOT)
        rec = fresh_grids(lambda ctx=ctx: planner.plan(ctx, record=True))().record
        assert rec is not None
        for k, v in rec.timing.items():
            stages.setdefault(k, []).append(v)
    t_poses = rollout(POSE, VEL, rec.twists, ROBOT, LocalPlannerParams()).t.size
    print(
        f"\n## LocalPlanner.plan stage medians (PR2 defaults: N = {rec.num_samples}, "
        f"T = {t_poses}; compiled kernels, fresh grids every cycle)\n"
    )
    for k, v in stages.items():
        print(f"- {k}: {np.median(v) * 1e3:.3f} ms")


if __name__ == "__main__":
    main(quick_option(__doc__))

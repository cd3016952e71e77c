"""Control-loop step in a crowd: ``Navigator.step`` time percentiles and peak memory.

Run: ``.venv/bin/python benchmarks/bench_crowd_step.py [--steps N] [--people N] [--fast S]
[--replan all]``.

Setup (seeded): the 27 m × 27 m room of the paper suite's group/queue scenes (540 × 540 cells
at 0.05 m, the largest static map of the suite), the PR2 driving from (3, 3) to (24, 24) with
its command integrated exactly; ``--people`` people (default 50) walk straight lines at
0.5–1.3 m/s across the room, bouncing off its walls, and one of them walks at ``--fast`` m/s
(default 3; ``--fast 10`` is the tracker glitch of the control-loop issue). People do not react.
Every preset builds its navigator with nobody in view (the objective set follows the scene).

Printed per preset (and per kernel path with ``--kernels both``: the compiled kernels and the
NumPy reference in the same run): step p50 / p95 / p99 / max and the thread's CPU-time p50 / p99
(on a loaded machine CPU time excludes waiting for a core) over ``--steps`` cycles (default
200, the first 5 are warm-up and not counted), and the tracemalloc peak of one warmed-up
``step`` that includes a global replan (the most expensive kind). The control-loop issue's floor is
p95 ≤ 50 ms and peak < 100 MB with 50 people, one at 3 m/s.
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

import numpy as np

from harness import format_seconds
from socialnav.core.robot import PR2
from socialnav.core.scene import Person, SocialContext
from socialnav.planner import kernels
from socialnav.planner.presets import PRESETS, build_navigator
from socialnav.sim.scenario import load_scenario

SEED = 11


def _people(rng: np.random.Generator, k: int, fast: float, size: float):
    pos = rng.uniform(1.0, size - 1.0, (k, 2))
    ang = rng.uniform(-np.pi, np.pi, k)
    speed = rng.uniform(0.5, 1.3, k)
    if k:
        speed[0] = fast
    return pos, np.column_stack([np.cos(ang), np.sin(ang)]) * speed[:, None]


def _advance(pos, vel, dt, size):
    pos = pos + vel * dt
    for axis in range(2):
        out = (pos[:, axis] < 0.5) | (pos[:, axis] > size - 0.5)
        vel[out, axis] *= -1.0
        pos[:, axis] = np.clip(pos[:, axis], 0.5, size - 0.5)
    return pos, vel


def _context(pos, vel):
    return SocialContext(
        tuple(
            Person(i, (float(p[0]), float(p[1])), (float(v[0]), float(v[1])))
            for i, (p, v) in enumerate(zip(pos, vel, strict=True))
        )
    )


def run(
    preset: str,
    steps: int,
    people: int,
    fast: float,
    compiled: bool = True,
    replan: str = "inline",
    search: str = "scipy",
) -> dict[str, float]:
    previous = kernels.set_enabled(compiled) if kernels.enabled() or compiled else False
    try:
        return _run(preset, steps, people, fast, replan, search)
    finally:
        kernels.set_enabled(previous)


def _run(
    preset: str, steps: int, people: int, fast: float, replan: str, search: str
) -> dict[str, float]:
    scenario = load_scenario("group_join")
    costmap = scenario.static_costmap(PR2)
    geo = costmap.geometry
    size = geo.shape[1] * geo.resolution
    rng = np.random.default_rng(SEED)
    pos, vel = _people(rng, people, fast, size)
    goal = np.array([size - 3.0, size - 3.0, 0.0])
    nav = build_navigator(
        preset, PR2, costmap, goal, SocialContext(), global_search=search, replan_mode=replan
    )
    pose, twist = np.array([3.0, 3.0, 0.0]), np.zeros(3)
    times, cpu = [], []
    dt = 0.1
    for k in range(steps):
        social = _context(pos, vel)
        c0, start = time.thread_time(), time.perf_counter()
        result = nav.step(k * dt, pose, twist, social)
        times.append(time.perf_counter() - start)
        cpu.append(time.thread_time() - c0)
        twist = result.cmd
        c, s = np.cos(pose[2]), np.sin(pose[2])
        pose = pose + dt * np.array(
            [c * twist[0] - s * twist[1], s * twist[0] + c * twist[1], twist[2]]
        )
        pos, vel = _advance(pos, vel, dt, size)
    # Peak memory of one warmed-up step that replans (forced by an expired replan period;
    # inline, so the replan's allocations are in the step).
    social = _context(pos, vel)
    nav.close()
    nav.replan_mode = "inline"
    nav._plan_time = -np.inf
    tracemalloc.start()
    nav.step(steps * dt, pose, twist, social)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    t = np.array(times[5:])
    c = np.array(cpu[5:])
    return {
        "cpu_p50": float(np.percentile(c, 50)),
        "cpu_p99": float(np.percentile(c, 99)),
        "p50": float(np.percentile(t, 50)),
        "p95": float(np.percentile(t, 95)),
        "p99": float(np.percentile(t, 99)),
        "max": float(t.max()),
        "peak_mb": peak / 2**20,
    }


# (replan mode, global search) rows: the current inline replan with SciPy's Dijkstra (the
# baseline), the compiled search inline, and rate-separated replanning (deferred: applied
# 2 steps after the request, deterministic) with the compiled search.
CONFIGS = {
    "inline, scipy": ("inline", "scipy"),
    "inline, compiled search": ("inline", "compiled"),
    "deferred, compiled search": ("deferred", "compiled"),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--people", type=int, default=50)
    parser.add_argument("--fast", type=float, default=3.0)
    parser.add_argument("--presets", default=",".join(PRESETS.names()))
    parser.add_argument(
        "--kernels",
        choices=("compiled", "reference", "both"),
        default="compiled",
        help="planner kernels: compiled (numba), the NumPy reference, or both in one run",
    )
    parser.add_argument(
        "--replan",
        default="inline, scipy",
        help="comma-free ';'-separated rows of: " + "; ".join(CONFIGS) + " (or 'all')",
    )
    args = parser.parse_args()
    modes = {"compiled": [True], "reference": [False], "both": [False, True]}[args.kernels]
    configs = list(CONFIGS) if args.replan == "all" else args.replan.split(";")
    print(
        f"\n## Navigator.step, {args.people} people (one at {args.fast} m/s), "
        f"{args.steps} steps, 540 × 540 map\n"
    )
    print(
        "| preset | kernels | replan | p50 | p95 | p99 | max | CPU p50 | CPU p99 | "
        "peak memory (replan step) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in args.presets.split(","):
        for compiled in modes:
            for config in configs:
                replan, search = CONFIGS[config.strip()]
                r = run(name, args.steps, args.people, args.fast, compiled, replan, search)
                print(
                    f"| {name} | {'compiled' if compiled else 'numpy reference'} | {config} "
                    f"| {format_seconds(r['p50'])} | {format_seconds(r['p95'])} | "
                    f"{format_seconds(r['p99'])} | {format_seconds(r['max'])} | "
                    f"{format_seconds(r['cpu_p50'])} | {format_seconds(r['cpu_p99'])} | "
                    f"{r['peak_mb']:.1f} MB |"
                )


if __name__ == "__main__":
    main()

"""Which hallway failures could the robot have passed? A kinodynamic check of each one.

Run: ``.venv/bin/python benchmarks/hallway_feasibility.py --results DIR [--planner paccet]
[--jobs 2]`` on the folder of ``socialnav compare --suite generated --families hallway …``.

A generated hallway marks ``no_personal_space_intrusion`` required when its *joint clearance*
(:func:`~socialnav.sim.generate._passage.joint_clearance`) reaches 1.25 m — a bound generous to
the robot (holonomic, no acceleration limit) — and some command sequence of the robot keeps
1.2 m over the first 4 s (:func:`~socialnav.sim.generate._passage.can_keep_distance`). For
every run of ``--planner`` that failed that
condition, this script asks :func:`~socialnav.sim.generate._passage.personal_space_path`, a
state-lattice search with the robot's own velocity and acceleration limits, for a way to
within 0.3 m of the goal (any heading) that keeps every person's centre 1.2 m from the
robot's. Found: the robot could have passed, so the failure is the planner's. Not found:
proves nothing, but where the generous bound says yes and the lattice finds no way, the
condition may be out of this robot's reach.

Printed: one row per failed run (seed, robot, the run's closest distance, the joint clearance,
the lattice's answer and its path's closest distance, seconds of search), then the counts.
"""

from __future__ import annotations

import argparse
import math
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pandas as pd

from socialnav.sim.generate import generate
from socialnav.sim.generate._passage import personal_space_path
from socialnav.sim.generate.common import robot_model

CONDITION = "no_personal_space_intrusion"


def check(seed: int, robot: str) -> tuple[bool, float, float]:
    """``(found, closest distance (m), search time (s))`` for hallway ``seed`` and ``robot``."""
    start = time.perf_counter()
    found, closest = personal_space_path(generate("hallway", seed), robot_model(robot))
    return found, closest, time.perf_counter() - start


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--results", type=Path, required=True, help="a socialnav compare --out DIR")
    ap.add_argument("--planner", default="paccet")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    runs = pd.read_parquet(args.results / "results")
    runs = runs[
        (runs.family == "hallway")
        & (runs.planner == args.planner)
        & runs.failed_required.fillna("").str.contains(CONDITION)
    ].sort_values(["robot", "seed"])
    if runs.empty:
        print(f"no {args.planner} hallway run in {args.results} failed {CONDITION}")
        return
    with ProcessPoolExecutor(args.jobs) as pool:
        answers = list(pool.map(check, runs.seed.astype(int), runs.robot))
    print(
        "| seed | robot | run's closest (m) | joint clearance (m) | lattice | its closest (m) | s |"
    )
    print("|---" * 7 + "|")
    found_count = 0
    for (_, run), (found, closest, seconds) in zip(runs.iterrows(), answers, strict=True):
        joint = generate("hallway", int(run.seed)).feasibility[run.robot]["joint_clearance"]
        found_count += found
        shown = "—" if math.isnan(closest) else f"{closest:.2f}"
        print(
            f"| {run.seed} | {run.robot} | {run.min_distance_center:.2f} | {joint} | "
            f"{'found' if found else 'none'} | {shown} | {seconds:.1f} |"
        )
    print(
        f"\n{len(runs)} runs failed {CONDITION}: the lattice found a way in {found_count}, "
        f"none in {len(runs) - found_count}"
    )


if __name__ == "__main__":
    main()

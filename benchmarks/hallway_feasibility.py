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
robot's (0.3 m, not the suite's 0.10 m: the lattice holds each command 0.4 s, so it cannot
stop on a 0.10 m target; the question is the passing, not the last centimetres). Found: the
robot could have passed, so the failure is the planner's. Not found:
proves nothing, but where the generous bound says yes and the lattice finds no way, the
condition may be out of this robot's reach.

Printed: one row per failed run (seed, robot, the run's closest distance, the joint clearance,
the lattice's answer and its path's closest distance, seconds of search, the run's other failed
conditions), then the counts. Only the generated suite's hallway runs are read (other suites'
hallway scenarios are not generated from a seed).
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


def positive(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--results", type=Path, required=True, help="a socialnav compare --out DIR")
    ap.add_argument("--planner", default="paccet")
    ap.add_argument("--jobs", type=positive, default=2)
    args = ap.parse_args()
    if not (args.results / "results").is_dir():
        raise SystemExit(
            f"{args.results}: no results dataset in it (give the folder that "
            "socialnav compare --out wrote, not its results/ subfolder)"
        )
    runs = pd.read_parquet(args.results / "results")
    if "suite" not in runs or "failed_required" not in runs:
        raise SystemExit(f"{args.results}: not a generated-suite folder (no failed_required)")
    runs = runs[(runs.suite == "generated") & (runs.family == "hallway")]
    if runs.empty:
        raise SystemExit(f"{args.results}: no generated-suite hallway runs in it")
    if args.planner not in set(runs.planner):
        known = ", ".join(sorted(set(runs.planner)))
        raise SystemExit(f"{args.results}: no {args.planner} runs; its planners: {known}")
    total = int((runs.planner == args.planner).sum())
    runs = runs[
        (runs.planner == args.planner) & runs.failed_required.fillna("").str.contains(CONDITION)
    ].sort_values(["robot", "seed"])
    if runs.empty:
        print(f"none of {total} {args.planner} hallway runs in {args.results} failed {CONDITION}")
        return
    with ProcessPoolExecutor(args.jobs) as pool:
        answers = list(pool.map(check, runs.seed.astype(int), runs.robot))
    print(
        "| seed | robot | run's closest (m) | joint clearance (m) | lattice | its closest (m) "
        "| s | other failed conditions |"
    )
    print("|---" * 8 + "|")
    found_count = 0
    for (_, run), (found, closest, seconds) in zip(runs.iterrows(), answers, strict=True):
        joint = float(generate("hallway", int(run.seed)).feasibility[run.robot]["joint_clearance"])
        found_count += found
        shown = "—" if not math.isfinite(closest) else f"{closest:.2f}"
        others = [c for c in str(run.failed_required).split(",") if c and c != CONDITION]
        print(
            f"| {run.seed} | {run.robot} | {run.min_distance_center:.2f} | {joint:.2f} | "
            f"{'found' if found else 'none'} | {shown} | {seconds:.1f} | "
            f"{', '.join(others) or '—'} |"
        )
    print(
        f"\n{len(runs)} of {total} runs failed {CONDITION}: the lattice found a way in "
        f"{found_count}, none in {len(runs) - found_count}"
    )


if __name__ == "__main__":
    main()

"""Development-split ablation of ``paccet``'s generalization choices (generated suite).

Each variant is ``paccet`` with one choice undone; every variant runs the same development
scenes (seeds below 10,000 only: this is where the configuration is tuned) for both robots and
prints pass rate and median time to goal per family. Usage::

    python benchmarks/tune_generated.py --seeds 0:4 --families queue,group_join --jobs 2

Variants: ``paccet`` (as shipped); ``no_partner`` (interaction partners keep the 1.5 m ID
threshold); ``loose_spot`` (the social goals' own 0.25 m / 0.25 rad arrival tolerance and the
default 0.10 m xy goal tolerance); ``no_arrival`` (rollouts scored at their full-horizon end
point, base_local_planner's rule: the slow final approach); ``no_passing`` (ID without the
walkers' passing distance past the rollout, ``PASSING_HORIZON``).
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import multiprocessing as mp
import statistics
from collections import defaultdict

from harness import development_seeds
from socialnav.planner.local_planner import LocalPlannerParams
from socialnav.planner.presets import PRESETS, recommended_objectives
from socialnav.sim.generate import GENERATORS

BASE = PRESETS.get("paccet")
VARIANTS = {
    "paccet": BASE,
    "no_partner": dataclasses.replace(BASE, objectives=recommended_objectives),
    "loose_spot": dataclasses.replace(BASE, spot_tolerance=None, params=LocalPlannerParams()),
    "no_arrival": dataclasses.replace(
        BASE, params=dataclasses.replace(BASE.params, stop_at_goal=False)
    ),
    "no_passing": dataclasses.replace(
        BASE,
        objectives=functools.partial(recommended_objectives, partner_distance=True),
    ),
}


def run_one(job: tuple[str, str, str, int]) -> tuple[str, str, str, int, bool, float, str]:
    from socialnav.metrics import compute_metrics
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode
    from socialnav.sim.stack import StackController

    variant, family, robot, seed = job
    name = f"tune_{variant}"
    if name not in PRESETS:
        PRESETS.add(name, VARIANTS[variant])
    result = run_episode(generate(family, seed), StackController(name), robot, seed=seed)
    conds = success_conditions(result.record)
    ok = all(c.passed for c in conds if c.required)
    failed = ",".join(c.name for c in conds if c.required and not c.passed)
    t = compute_metrics(result.record, ["time_to_goal"])["time_to_goal"]
    return variant, family, robot, seed, ok, float(t), failed


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", default="0:4")
    ap.add_argument("--families", default="")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    seeds = development_seeds(args.seeds, "tuning")
    families = [f for f in args.families.split(",") if f] or GENERATORS.names()
    jobs = [
        (v, f, r, s)
        for v in args.variants.split(",")
        for f in families
        for r in ("pr2", "pioneer")
        for s in seeds
    ]
    with mp.get_context("fork").Pool(args.jobs) as pool:
        results = pool.map(run_one, jobs, chunksize=1)
    table: dict[tuple[str, str], list] = defaultdict(list)
    for v, f, r, s, ok, t, failed in results:
        table[(f, v)].append((ok, t, f"{r}/s{s}:{failed}" if not ok else ""))
    print(f"development seeds {args.seeds}, both robots; pass, median time to goal of passes (s)")
    print(f"{'family':<18}{'variant':<12}{'pass':>8}{'time':>8}  failures")
    for (f, v), rows in sorted(table.items()):
        passed = [t for ok, t, _ in rows if ok]
        med = statistics.median(passed) if passed else float("nan")
        fails = " ".join(x for _, _, x in rows if x)
        print(f"{f:<18}{v:<12}{len(passed):>4}/{len(rows):<3}{med:>8.1f}  {fails}")


if __name__ == "__main__":
    main()

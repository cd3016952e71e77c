"""Where ``paccet``'s extra time to goal goes, against navground's HL (generated suite).

Time to goal is path length over mean speed, so its ratio to HL's splits into a path ratio
(a detour of the global plan or of the local choices) and a speed ratio (waiting, turning in
place, backing off). For each planner, family and robot this prints, over the development
scenes both it and ``hl`` pass: the median time ratio, the median path-length and mean-speed
ratios, the mean time stopped (speed below 5 cm/s), the mean largest lateral excursion from the
start-goal line, and the mean time to cross the middle of that line (a late crossing means the
time was lost before the midpoint). Development seeds only (< 10,000). Usage::

    python benchmarks/time_breakdown.py --families crowdnav,crowdnav_visible --seeds 0:6

Variants beside the shipped ``paccet``: ``paccet_static_global`` (no personal-space layer in the
global plan, ``social_global_path=False``), to show the share of the global plan's detour, and
``paccet_meeting`` (walkers' personal space where the robot can meet them and replan
hysteresis: the options ``PlannerPreset.meeting_layer`` and ``replan_hysteresis``).
"""

from __future__ import annotations

import argparse
import dataclasses
import multiprocessing as mp
import statistics
from collections import defaultdict

import numpy as np

from harness import development_seeds
from socialnav.planner.presets import PRESETS, RECOMMENDED_HYSTERESIS
from socialnav.sim.generate import GENERATORS

VARIANTS = {
    "paccet_static_global": dataclasses.replace(PRESETS.get("paccet"), social_global_path=False),
    "paccet_meeting": dataclasses.replace(
        PRESETS.get("paccet"), meeting_layer=True, replan_hysteresis=RECOMMENDED_HYSTERESIS
    ),
}
STOPPED = 0.05  # m/s


def run_one(job: tuple[str, str, str, int]) -> tuple[str, str, str, int, bool, dict[str, float]]:
    from socialnav.metrics import compute_metrics
    from socialnav.metrics.success import success_conditions
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode
    from socialnav.sim.stack import StackController

    planner, family, robot, seed = job
    if planner in VARIANTS and planner not in PRESETS:
        PRESETS.add(planner, VARIANTS[planner])
    controller = StackController(planner) if planner in PRESETS else planner
    r = run_episode(generate(family, seed), controller, robot, seed=seed).record
    ok = all(c.passed for c in success_conditions(r) if c.required)
    xy = r.robot_poses[:, :2]
    near = np.flatnonzero(np.hypot(*(xy - r.target[:2]).T) <= r.goal_tolerance)
    n = int(near[0]) + 1 if near.size else len(xy)
    step = np.hypot(*np.diff(xy[:n], axis=0).T)
    line = r.target[:2] - r.start[:2]
    unit = line / max(float(np.hypot(*line)), 1e-9)
    rel = xy[:n] - r.start[:2]
    along = rel @ unit
    lateral = np.abs(rel[:, 0] * unit[1] - rel[:, 1] * unit[0])
    mid = np.flatnonzero(along >= 0.5 * float(np.hypot(*line)))
    facts = {
        "time": float(compute_metrics(r, ["time_to_goal"])["time_to_goal"]),
        "path": float(step.sum()),
        "stopped": float((step / r.dt < STOPPED).sum() * r.dt),
        "lateral": float(lateral.max()),
        "midpoint": float(r.times[mid[0]]) if mid.size else float("nan"),
    }
    facts["speed"] = facts["path"] / max(facts["time"], 1e-9)
    return planner, family, robot, seed, ok, facts


def _median(values: list[float]) -> float:
    return statistics.median(values) if values else float("nan")


def _mean(values: list[float]) -> float:
    return float(np.mean(values)) if values else float("nan")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", default="0:6")
    ap.add_argument("--families", default="crowdnav,crowdnav_visible,mixed")
    ap.add_argument("--planners", default="paccet,paccet_static_global")
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args()
    seeds = development_seeds(args.seeds, "this breakdown")
    families = [f for f in args.families.split(",") if f] or GENERATORS.names()
    planners = ["hl", *(p for p in args.planners.split(",") if p and p != "hl")]
    robots = ("pioneer", "pr2")
    jobs = [(p, f, r, s) for p in planners for f in families for r in robots for s in seeds]
    with mp.get_context("fork").Pool(args.jobs) as pool:
        results = pool.map(run_one, jobs, chunksize=1)
    runs: dict[tuple[str, str, str], dict[int, tuple[bool, dict[str, float]]]] = defaultdict(dict)
    for p, f, r, s, ok, facts in results:
        runs[(p, f, r)][s] = (ok, facts)
    print(f"development seeds {args.seeds}; ratios are planner / hl over the scenes both pass")
    head = f"{'family':<17}{'robot':<8}{'planner':<22}{'pass':>6}{'both':>5}"
    print(head + f"{'time':>7}{'path':>7}{'speed':>7}{'stop s':>7}{'lat m':>7}{'mid s':>7}")
    for f in families:
        for robot in ("pioneer", "pr2"):
            base = runs[("hl", f, robot)]
            for p in planners:
                mine = runs[(p, f, robot)]
                both = [s for s in seeds if mine[s][0] and base[s][0]]
                passes = sum(ok for ok, _ in mine.values())
                ratios = {
                    key: _median([mine[s][1][key] / base[s][1][key] for s in both])
                    for key in ("time", "path", "speed")
                }
                means = {
                    key: _mean([mine[s][1][key] for s in both])
                    for key in ("stopped", "lateral", "midpoint")
                }
                print(
                    f"{f:<17}{robot:<8}{p:<22}{passes:>4}/{len(seeds):<2}{len(both):>4}"
                    f"{ratios['time']:>7.2f}{ratios['path']:>7.2f}{ratios['speed']:>7.2f}"
                    f"{means['stopped']:>7.1f}{means['lateral']:>7.2f}{means['midpoint']:>7.1f}"
                )


if __name__ == "__main__":
    main()

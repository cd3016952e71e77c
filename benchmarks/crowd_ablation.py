"""The crowd suite's ``paccet`` with parts of the control loop switched off by option.

Run: ``.venv/bin/python benchmarks/crowd_ablation.py --data FILE [--data FILE …]
[--seeds 10000:10050] [--robots pr2,pioneer] [--variants default,loop_off] [--jobs N]``.

Each variant is ``paccet`` built with :class:`~socialnav.planner.recovery.RecoveryParams` and
interpersonal-critic overrides (``StackController(recovery=…)``), run on the crowd suite's
episodes (the same seeds select the same tasks as ``socialnav compare --suite crowds``):

- ``default``: ``paccet`` as registered;
- ``loop_off``: the control-loop issue's behaviours that have an option switched off — no
  evasion (``evasion_ttc=0``) and no waiting for a blocking person
  (``person_blocking_distance=0``, ``person_blocking_lookahead=0``: recoveries run instead).
  STUCK as a non-latching status, escape from overlap and the objective set following the
  scene have no switch and stay on.

Printed per recording × robot × variant: episodes, success %, episodes with an active /
passive / any contact (%), time within 1.2 m (s, mean), path length ratio and time to goal (s,
means over successful episodes) and the planner step p95 (ms, pooled over steps; timings on a
loaded machine are inflated).
"""

from __future__ import annotations

import argparse
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from socialnav.experiments.crowd import CROWD_METRICS, cached_recording, parse_seeds

VARIANTS: dict[str, dict[str, Any]] = {
    "default": {},
    "loop_off": {
        "recovery": {
            "evasion_ttc": 0.0,
            "person_blocking_distance": 0.0,
            "person_blocking_lookahead": 0.0,
        }
    },
}


def run_one(data: str, robot: str, seed: int, variant: str) -> dict[str, Any]:
    """One episode's metrics and step times (ms)."""
    from socialnav.crowds.episodes import generate_episode
    from socialnav.metrics import compute_metrics
    from socialnav.sim.controller import make_controller
    from socialnav.sim.replay import CrowdTask, run_crowd_episode

    recording = cached_recording(data)
    episode = generate_episode(recording, seed)
    task = CrowdTask(episode.t0, episode.start, episode.goal, episode.time_limit)
    controller = make_controller("paccet", **VARIANTS[variant])
    result = run_crowd_episode(recording, task, controller, robot, seed=seed)
    row: dict[str, Any] = {"data": data, "robot": robot, "seed": seed, "variant": variant}
    row.update(compute_metrics(result.record, CROWD_METRICS))
    row["ms"] = np.asarray(result.step_seconds) * 1e3
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", action="append", required=True)
    ap.add_argument("--seeds", default="10000:10050")
    ap.add_argument("--robots", default="pr2,pioneer")
    ap.add_argument("--variants", default="default,loop_off")
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args()
    variants = args.variants.split(",")
    unknown = sorted(set(variants) - set(VARIANTS))
    if unknown:
        ap.error(f"unknown variant(s) {unknown}; known: {', '.join(VARIANTS)}")
    jobs = [
        (d, r, s, v)
        for v in variants
        for d in args.data
        for r in args.robots.split(",")
        for s in parse_seeds(args.seeds)
    ]
    with ProcessPoolExecutor(max_workers=max(args.jobs, 1)) as pool:
        rows = list(pool.map(run_one, *zip(*jobs, strict=True)))
    header = (
        "| recording | robot | variant | n | success % | active % | passive % | contact % "
        "| t<1.2 s | path ratio | time s | ms p95 |"
    )
    print(header)
    print("|---" * 12 + "|")
    for d in args.data:
        for r in args.robots.split(","):
            for v in variants:
                sel = [x for x in rows if x["data"] == d and x["robot"] == r and x["variant"] == v]
                ok = [x for x in sel if x["success"] >= 1.0]
                active = np.mean([x["collisions_active"] > 0 for x in sel]) * 100
                passive = np.mean([x["collisions_passive"] > 0 for x in sel]) * 100
                contact = (
                    np.mean([x["collisions_active"] + x["collisions_passive"] > 0 for x in sel])
                    * 100
                )
                ratio = np.mean([x["path_length_ratio"] for x in ok]) if ok else np.nan
                ttg = np.mean([x["time_to_goal"] for x in ok]) if ok else np.nan
                p95 = np.percentile(np.concatenate([x["ms"] for x in sel]), 95)
                name = d.rsplit("/", 1)[-1].removesuffix(".txt").removesuffix("_obsmat")
                print(
                    f"| {name} | {r} | {v} | {len(sel)} | "
                    f"{100 * len(ok) / len(sel):.0f} | {active:.0f} | {passive:.0f} | "
                    f"{contact:.0f} | {np.mean([x['time_within_1.2'] for x in sel]):.2f} | "
                    f"{ratio:.2f} | {ttg:.1f} | {p95:.1f} |"
                )


if __name__ == "__main__":
    main()

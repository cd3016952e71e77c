"""Control-step time in the paper suite and the crowd suite: replanning inline (as before)
against rate-separated replanning (deferred: applied 2 steps after the request, reproducible).

Run: ``.venv/bin/python benchmarks/bench_suite_step.py [--quick] [--preset paccet]``.

Paper suite: every built-in scenario once (seed 0; ``--quick``: four of them), PR2, scripted
people. Crowd suite: the recordings under ``../shared/data/crowds`` (ETH hotel, UCY zara01),
development seeds 0–2 (``--quick``: 0), replayed people. Per step: wall time (what
``run_episode`` records) and the stepping thread's CPU time (``time.thread_time``, which on a
loaded machine excludes waiting for a core; a deferred replan's join wait is wall only).
Rows: ``inline, scipy`` (the implementation before: replan in the step, SciPy's Dijkstra),
``inline, compiled search``, ``deferred, compiled search`` (the worker thread runs the replan
without the GIL in its search). Percentiles over all steps of all episodes of a suite.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from harness import format_seconds, machine_note
from socialnav.planner import kernels
from socialnav.sim.runner import run_episode
from socialnav.sim.scenario import builtin_scenarios
from socialnav.sim.stack import StackController

CONFIGS = {
    "inline, scipy (before)": ("inline", "scipy"),
    "inline, compiled search": ("inline", "compiled"),
    "deferred, compiled search": ("deferred", "compiled"),
}
CROWDS = Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "crowds"


class TimedController(StackController):
    """The stack with the thread CPU time of every step recorded."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.cpu: list[float] = []

    def step(self, time_s, pose, velocity, social):
        c0 = time.thread_time()
        try:
            return super().step(time_s, pose, velocity, social)
        finally:
            self.cpu.append(time.thread_time() - c0)


def paper(preset: str, replan: str, search: str, quick: bool) -> tuple[list[float], list[float]]:
    names = builtin_scenarios()
    if quick:
        names = [
            n
            for n in names
            if n in ("group_join", "hallway_passing", "queue_line", "gallery_present")
        ]
    wall: list[float] = []
    cpu: list[float] = []
    for name in names:
        ctrl = TimedController(preset, global_search=search, replan_mode=replan)
        result = run_episode(name, ctrl, "pr2", seed=0)
        wall += result.step_seconds
        cpu += ctrl.cpu
        ctrl.navigator.close()
    return wall, cpu


def crowd(preset: str, replan: str, search: str, quick: bool) -> tuple[list[float], list[float]]:
    from socialnav.crowds.episodes import generate_episode
    from socialnav.experiments.crowd import cached_recording
    from socialnav.sim.replay import CrowdTask, run_crowd_episode

    wall: list[float] = []
    cpu: list[float] = []
    files = sorted(CROWDS.glob("*_obsmat.txt"))
    for path in files:
        recording = cached_recording(str(path))
        for seed in range(1 if quick else 3):
            episode = generate_episode(recording, seed)
            task = CrowdTask(episode.t0, episode.start, episode.goal, episode.time_limit)
            ctrl = TimedController(preset, global_search=search, replan_mode=replan)
            result = run_crowd_episode(recording, task, ctrl, "pr2", seed=seed)
            wall += result.step_seconds
            cpu += ctrl.cpu
            ctrl.navigator.close()
    return wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--preset", default="paccet")
    args = parser.parse_args()
    kernels.warmup()
    suites = {"paper": paper}
    if CROWDS.is_dir():
        suites["crowd"] = crowd
    else:
        print(f"(no recordings under {CROWDS}: crowd suite skipped)")
    print(
        f"\n## Control step, {args.preset}, PR2: wall and thread-CPU percentiles over every step "
        f"({machine_note()})\n"
    )
    print(
        "| suite | replan | steps | wall p50 | wall p95 | wall p99 | CPU p50 | CPU p99 | CPU max |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for suite, fn in suites.items():
        for name, (replan, search) in CONFIGS.items():
            wall, cpu = fn(args.preset, replan, search, args.quick)
            w, c = np.asarray(wall), np.asarray(cpu)
            cells = [np.percentile(w, q) for q in (50, 95, 99)]
            cells += [np.percentile(c, 50), np.percentile(c, 99), c.max()]
            row = " | ".join(format_seconds(float(v)) for v in cells)
            print(f"| {suite} | {name} | {w.size} | {row} |", flush=True)


if __name__ == "__main__":
    main()

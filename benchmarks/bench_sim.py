"""Simulation overhead: one full 60 s episode (601 samples) with a trivial controller.

Rows:
- ``bare navground``: the same world stepped 601 times, no controller, no recording — the floor;
- ``run_episode``: the full runner (Python behaviour → controller → clamp, ground-truth social
  context, exact footprint collision checks, EpisodeRecord) with a stand-still controller, so
  every episode lasts the full 60 s; per-step cost = median / 601;
- ``reactive humans``: the same with navground ``HL`` people;
- ``ORCA robot``: the robot driven by navground's ORCA (ends when its target is reached).

Run: ``.venv/bin/python benchmarks/bench_sim.py``.
"""

from __future__ import annotations

import numpy as np

from harness import Case, run_table
from socialnav.core.robot import PR2
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.sim.engine import ControllerBehavior, build_world
from socialnav.sim.runner import run_episode
from socialnav.sim.scenario import load_scenario

STEPS = 601


class StandStill:
    def reset(self, scenario, robot) -> None:
        pass

    def step(self, time, pose, velocity, social) -> PlannerResult:
        return PlannerResult(np.zeros(3), PlannerStatus.OK)


def bare(name: str) -> None:
    simw = build_world(load_scenario(name), PR2, ControllerBehavior())
    for _ in range(STEPS):
        simw.world.update(0.1)


def main() -> None:
    cases = []
    for name in ("hallway_oncoming", "group_join", "queue_rotated"):
        scn = load_scenario(name)
        extra = {
            "people": str(len(scn.people)),
            "walls": str(len(scn.walls_array()) + 4 * len(scn.map.rectangles)),
        }
        cases += [
            Case(name, "bare navground", lambda n=name: bare(n), repeats=5, extra=extra),
            Case(
                name,
                "run_episode",
                lambda s=scn: run_episode(s, StandStill(), "pr2"),
                repeats=5,
                baseline="bare navground",
                extra=extra,
            ),
            Case(
                name,
                "reactive humans",
                lambda s=scn: run_episode(s, StandStill(), "pr2", humans="reactive"),
                repeats=3,
                baseline="bare navground",
                extra=extra,
            ),
        ]
    scn = load_scenario("hallway_stationary")
    cases.append(
        Case(
            "hallway_stationary",
            "ORCA robot",
            lambda: run_episode(scn, "orca"),
            repeats=3,
            extra={"people": "1", "walls": "2"},
        )
    )
    rows = run_table(cases, title="60 s episode (601 samples at 0.1 s), PR2")
    print()
    for r in rows:
        if r.variant == "run_episode":
            print(f"{r.group}: {r.median_s / STEPS * 1e3:.3f} ms per step (run_episode)")


if __name__ == "__main__":
    main()

"""Gymnasium environment overhead: one 60 s episode (600 steps) against ``run_episode``.

Rows per scenario (a stand-still policy/controller, so every episode lasts the full 60 s):
- ``run_episode``: the runner with a stand-still controller — the baseline;
- ``env.step``: ``SocialNavEnv`` reset + 600 steps (observation, reward, collision checks) and,
  at the end, the metrics of ``socialnav compare`` (``info["metrics"]``);
- ``env.step, no metrics``: the same with ``metrics_on_end=False``;
- ``env.step + costmap``: with the 64 × 64 costmap crop in the observation.

Run: ``.venv/bin/python benchmarks/bench_gym.py``.
"""

from __future__ import annotations

import numpy as np

from bench_sim import StandStill
from harness import Case, run_table
from socialnav.integrations.gym import SocialNavEnv
from socialnav.sim.runner import run_episode
from socialnav.sim.scenario import load_scenario


def episode(env: SocialNavEnv) -> None:
    env.reset(seed=0)
    action = np.zeros(3, dtype=np.float32)
    while True:
        *_, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            return


def main() -> None:
    cases = []
    for name in ("hallway_oncoming", "group_join", "queue_rotated"):
        scn = load_scenario(name)
        extra = {"people": str(len(scn.people))}
        variants = {
            "env.step": SocialNavEnv(scenes=lambda rng, s=scn: s),
            "env.step, no metrics": SocialNavEnv(scenes=lambda rng, s=scn: s, metrics_on_end=False),
            "env.step + costmap": SocialNavEnv(scenes=lambda rng, s=scn: s, costmap_cells=64),
        }
        cases.append(
            Case(
                name,
                "run_episode",
                lambda s=scn: run_episode(s, StandStill(), "pr2"),
                repeats=3,
                extra=extra,
            )
        )
        for variant, env in variants.items():
            cases.append(
                Case(
                    name,
                    variant,
                    lambda e=env: episode(e),
                    repeats=3,
                    baseline="run_episode",
                    extra=extra,
                )
            )
    run_table(cases, "One 60 s episode (600 steps of 0.1 s), PR2, scripted people")


if __name__ == "__main__":
    main()

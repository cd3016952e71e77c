"""Evaluate policies inside the socialnav Gymnasium environment, with socialnav compare's metrics.

Our planners (as privileged policies: they plan on the map and the people's true state, as in
``socialnav compare``) beside a random policy; a learned policy plugs in the same way — any
callable ``observation -> action`` with a ``reset()``. No training happens here.

    python examples/gym_evaluate.py   # 2 hallway episodes: random, traditional, paccet
    python examples/gym_evaluate.py --env socialnav/SocialNav-v0 --episodes 5 \
        --policies random,traditional,paccet,hl

Prints one row per policy: episodes, success rate (``socialnav compare``'s success conditions),
collisions per episode, mean time to goal (s) over successes, mean minimum distance to a person
(m), mean personal-space compliance and the mean return. Every policy meets the same scenes (the
same seeds). Episodes go on after a collision, as in ``socialnav compare``
(``--terminate-on-collision`` ends them there, CrowdNav's rule and the env's default).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np

import socialnav.integrations.gym as sg

COLUMNS = ("success", "collisions", "time_to_goal", "min_distance_center", "psc_1.2")


def make_policy(name: str, env: gym.Env, seed: int) -> Any:
    if name == "random":
        return sg.RandomPolicy(env, seed=seed)
    return sg.PlannerPolicy(env, name)


def evaluate(
    policy: Callable[[Any], np.ndarray],
    env: gym.Env,
    seeds: Sequence[int],
    label: str,
    scenario: str | None = None,
) -> list[dict[str, float]]:
    """One row per episode: the episode's metrics and its return."""
    rows = []
    for seed in seeds:
        options: dict[str, Any] = {"planner": label}
        if scenario:
            options["scenario"] = scenario
        obs, _ = env.reset(seed=seed, options=options)
        policy.reset()  # type: ignore[attr-defined]
        total = 0.0
        while True:
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            total += float(reward)
            if terminated or truncated:
                break
        rows.append({**info["metrics"], "success": float(info["is_success"]), "return": total})
    return rows


def summarize(label: str, rows: list[dict[str, float]]) -> dict[str, Any]:
    ok = [r for r in rows if r["success"] > 0]
    out: dict[str, Any] = {"policy": label, "episodes": len(rows)}
    out["success"] = float(np.mean([r["success"] for r in rows]))
    out["collisions"] = float(np.mean([r["collisions"] for r in rows]))
    out["time_to_goal"] = float(np.mean([r["time_to_goal"] for r in ok])) if ok else math.nan
    out["min_distance_center"] = float(np.nanmean([r["min_distance_center"] for r in rows]))
    out["psc_1.2"] = float(np.nanmean([r["psc_1.2"] for r in rows]))
    out["return"] = float(np.mean([r["return"] for r in rows]))
    return out


def table(summaries: list[dict[str, Any]]) -> str:
    keys = ["policy", "episodes", *COLUMNS, "return"]
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    for s in summaries:
        cells = [f"{s[k]:.2f}" if isinstance(s[k], float) else str(s[k]) for k in keys]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> str:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="socialnav/SocialNavHallway-v0")
    parser.add_argument("--policies", default="random,traditional,paccet")
    parser.add_argument("--episodes", type=int, default=2)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--robot", default="pr2")
    parser.add_argument("--scenario", default=None, help="one scenario of the env's pool")
    parser.add_argument("--terminate-on-collision", action="store_true")
    args = parser.parse_args(argv)
    env = gym.make(args.env, robot=args.robot, terminate_on_collision=args.terminate_on_collision)
    seeds = range(args.first_seed, args.first_seed + args.episodes)
    summaries = []
    for name in args.policies.split(","):
        policy = make_policy(name, env, seed=args.first_seed)
        rows = evaluate(policy, env, seeds, name, args.scenario)
        summaries.append(summarize(name, rows))
    text = table(summaries)
    print(text)
    return text


if __name__ == "__main__":
    main()

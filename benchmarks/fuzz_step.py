"""Adversarial fuzzing of ``Navigator.step``: well-typed calls that a control loop can produce.

Run: ``.venv/bin/python benchmarks/fuzz_step.py [--calls 100000] [--seed 0]``.

Every planner preset × both robots (PR2, Pioneer) is driven in sessions of ``--session``
calls (default 200; a fresh navigator each session, built with nobody in view or with the
first people) on the paper suite's maps (``--maps``; default the 22 m hallway and the 27 m
room). Each call starts from the loop's true state (the pose integrated from the previous
command) and, with some probability each, perturbs it (seeded):

- time: repeated, backwards, far in the future (1e12 s), NaN, inf;
- pose: anywhere on the map, off the map, 1e6 / 1e9 m, NaN, inf, any yaw (1e6 rad);
- velocity: zero, at the limits, huge (1e3 / 1e9), NaN, inf;
- people: 0–60, on the robot, on the goal, far away (1e6 m), walking 0–3 m/s, glitching at
  10–1000 m/s, duplicate ids (the ``SocialContext`` constructor rejects those by name, so
  they are counted and the call is made with the ids renumbered).

Checked per call (``valid`` = finite time, finite pose inside the map, finite velocity — the
contract in ``Navigator.step``'s docstring): exceptions out of ``step``; non-finite commands;
commands beyond the limits (the velocity box, and the acceleration window around a finite
measured velocity; a zero command for a non-finite one); ``INVALID_INPUT`` on valid input;
the step time. Printed: one row per preset and a total; the target is zeros in the first four
columns.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from socialnav.core.errors import InvalidInputError
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.limits import within_limits
from socialnav.planner.local_planner import PlannerStatus
from socialnav.planner.presets import PRESETS, build_navigator
from socialnav.sim.scenario import load_scenario

DT = 0.1
# The paper suite's maps: the 22 m × 5 m hallway and the 27 m × 27 m room (``--maps``).
MAPS = ("hallway_stationary", "group_join")


@dataclass
class Tally:
    calls: int = 0
    exceptions: int = 0
    non_finite: int = 0
    beyond_limits: int = 0
    invalid_on_valid: int = 0
    rejected_contexts: int = 0
    times: list[float] = field(default_factory=list)
    statuses: Counter = field(default_factory=Counter)
    examples: list[str] = field(default_factory=list)

    def add(self, other: Tally) -> None:
        for name in (
            "calls",
            "exceptions",
            "non_finite",
            "beyond_limits",
            "invalid_on_valid",
            "rejected_contexts",
        ):
            setattr(self, name, getattr(self, name) + getattr(other, name))
        self.times += other.times
        self.statuses.update(other.statuses)
        self.examples += other.examples[: max(0, 10 - len(self.examples))]


def _people(rng: np.random.Generator, bounds, pose, goal) -> tuple[list[Person], bool]:
    x0, y0, x1, y1 = bounds
    k = int(rng.choice([0, 1, 2, 5, 10, 30, 60], p=[0.2, 0.2, 0.15, 0.15, 0.1, 0.1, 0.1]))
    people, duplicate = [], False
    dup = rng.random() < 0.05  # one duplicated id in 5 % of the contexts
    for i in range(k):
        u = rng.random()
        if u < 0.1:
            xy = np.asarray(pose[:2], dtype=float) + rng.normal(0.0, 0.2, 2)  # on the robot
        elif u < 0.2:
            xy = goal[:2] + rng.normal(0.0, 0.2, 2)  # on the goal
        elif u < 0.25:
            xy = rng.choice([-1.0, 1.0], 2) * 1e6  # far away
        else:
            xy = rng.uniform([x0, y0], [x1, y1])
        if not np.all(np.isfinite(xy)):
            xy = np.zeros(2)
        v = rng.random()
        if v < 0.4:
            vel = np.zeros(2)
        elif v < 0.9:
            vel = rng.normal(0.0, 1.2, 2)
        else:
            vel = rng.normal(0.0, 1.0, 2) * rng.choice([10.0, 100.0, 1000.0])
        pid = i
        if i > 0 and dup:
            pid, duplicate = 0, True
            dup = False
        people.append(Person(pid, (float(xy[0]), float(xy[1])), (float(vel[0]), float(vel[1]))))
    return people, duplicate


def _context(people: list[Person], tally: Tally) -> SocialContext:
    try:
        return SocialContext(tuple(people))
    except InvalidInputError:
        tally.rejected_contexts += 1  # duplicate ids: rejected by name before any step
        return SocialContext(
            tuple(Person(i, p.position, p.velocity, p.yaw, p.radius) for i, p in enumerate(people))
        )


def _perturb(rng, t, pose, vel, robot: RobotModel, bounds):
    x0, y0, x1, y1 = bounds
    t, pose, vel = float(t), pose.copy(), vel.copy()
    r = rng.random()
    if r < 0.05:
        t = t - DT  # repeats the previous timestamp
    elif r < 0.08:
        t = t - rng.uniform(1.0, 100.0)  # backwards
    elif r < 0.1:
        t = 1e12
    elif r < 0.11:
        t = float(rng.choice([np.nan, np.inf, -np.inf]))
    r = rng.random()
    if r < 0.08:
        pose = np.array([*rng.uniform([x0, y0], [x1, y1]), rng.uniform(-np.pi, np.pi)])
    elif r < 0.11:
        pose[:2] = rng.choice([-1.0, 1.0], 2) * rng.choice([1e6, 1e9])
    elif r < 0.13:
        pose[:2] = [x1 + rng.uniform(0.0, 5.0), y0 - rng.uniform(0.0, 5.0)]
    elif r < 0.14:
        pose[rng.integers(0, 3)] = rng.choice([np.nan, np.inf])
    elif r < 0.16:
        pose[2] = rng.choice([1e6, -1e6, 1e3])
    r = rng.random()
    if r < 0.05:
        vel = np.zeros(3)
    elif r < 0.1:
        vel = np.array([robot.max_vel_x, robot.max_vel_y, robot.max_vel_theta]) * rng.choice(
            [-1.0, 1.0], 3
        )
    elif r < 0.15:
        vel = rng.normal(0.0, 1.0, 3) * rng.choice([1e3, 1e9])
    elif r < 0.16:
        vel[rng.integers(0, 3)] = rng.choice([np.nan, np.inf, -np.inf])
    return t, pose, vel


def fuzz_session(
    preset: str, robot: RobotModel, costmap, rng: np.random.Generator, calls: int
) -> Tally:
    tally = Tally()
    geo = costmap.geometry
    bounds = (
        geo.origin[0],
        geo.origin[1],
        geo.origin[0] + geo.shape[1] * geo.resolution,
        geo.origin[1] + geo.shape[0] * geo.resolution,
    )
    x0, y0, x1, y1 = bounds
    goal = np.array([*rng.uniform([x0, y0], [x1, y1]), rng.uniform(-np.pi, np.pi)])
    pose = np.array([*rng.uniform([x0, y0], [x1, y1]), rng.uniform(-np.pi, np.pi)])
    vel = np.zeros(3)
    people, _ = _people(rng, bounds, pose, goal)
    first = SocialContext() if rng.random() < 0.5 else _context(people, Tally())
    nav = build_navigator(preset, robot, costmap, goal, first)
    for k in range(calls):
        t, p, v = _perturb(rng, k * DT, pose, vel, robot, bounds)
        if rng.random() < 0.3:
            people, _ = _people(rng, bounds, pose, goal)
        social = _context(people, tally)
        start = time.perf_counter()
        try:
            res = nav.step(t, p, v, social)
        except Exception as exc:  # counted: step must never raise
            tally.exceptions += 1
            tally.examples.append(f"{preset}/{robot.name}: raised {type(exc).__name__}: {exc}")
            continue
        finally:
            tally.times.append(time.perf_counter() - start)
            tally.calls += 1
        tally.statuses[res.status.value] += 1
        cmd = np.asarray(res.cmd, dtype=float)
        valid = (
            np.isfinite(t)
            and np.all(np.isfinite(p))
            and np.all(np.isfinite(v))
            and x0 <= p[0] <= x1
            and y0 <= p[1] <= y1
        )
        if cmd.shape != (3,) or not np.all(np.isfinite(cmd)):
            tally.non_finite += 1
            tally.examples.append(f"{preset}/{robot.name}: non-finite {cmd} ({res.status})")
            continue
        ok = within_limits(cmd, v, robot, DT) if np.all(np.isfinite(v)) else not np.any(cmd)
        if not ok:
            tally.beyond_limits += 1
            tally.examples.append(f"{preset}/{robot.name}: {cmd} beyond limits at v={v}")
        if valid and res.status == PlannerStatus.INVALID_INPUT:
            tally.invalid_on_valid += 1
            tally.examples.append(f"{preset}/{robot.name}: INVALID_INPUT on valid: {res.message}")
        # The loop's true state moves on with the command (from the true pose, if it was valid).
        if valid:
            c, s = np.cos(p[2]), np.sin(p[2])
            pose = p + DT * np.array([c * cmd[0] - s * cmd[1], s * cmd[0] + c * cmd[1], cmd[2]])
            vel = cmd
    return tally


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=100_000)
    parser.add_argument("--session", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--progress", type=int, default=0, help="interim table every N calls")
    parser.add_argument("--maps", default=",".join(MAPS), help="scenarios whose maps are used")
    args = parser.parse_args()
    names = tuple(args.maps.split(","))
    maps = {
        name: {r.name: load_scenario(name).static_costmap(r) for r in (PR2, PIONEER)}
        for name in names
    }
    presets = PRESETS.names()
    per_preset = {p: Tally() for p in presets}
    rng = np.random.default_rng(args.seed)
    done, session = 0, 0
    started = time.perf_counter()
    while done < args.calls:
        preset = presets[session % len(presets)]
        robot = (PR2, PIONEER)[(session // len(presets)) % 2]
        costmap = maps[names[(session // (2 * len(presets))) % len(names)]]
        n = min(args.session, args.calls - done)
        per_preset[preset].add(fuzz_session(preset, robot, costmap[robot.name], rng, n))
        done += n
        session += 1
        if args.progress and done % args.progress < n and done < args.calls:
            report(per_preset, done, args.seed, time.perf_counter() - started)  # interim
    report(per_preset, done, args.seed, time.perf_counter() - started)


def report(per_preset: dict[str, Tally], done: int, seed: int, wall: float) -> None:
    total = Tally()
    for t in per_preset.values():
        total.add(t)
    print(f"\n## Navigator.step fuzzing: {done} calls, seed {seed}, {wall:.0f} s wall\n")
    print(
        "| preset | calls | exceptions | non-finite cmd | beyond limits | INVALID_INPUT on valid "
        "| contexts rejected (dup. ids) | p50 | p99.9 | max |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name, t in [*per_preset.items(), ("**total**", total)]:
        if not t.calls:
            continue
        ms = np.array(t.times) * 1e3
        print(
            f"| {name} | {t.calls} | {t.exceptions} | {t.non_finite} | {t.beyond_limits} | "
            f"{t.invalid_on_valid} | {t.rejected_contexts} | {np.percentile(ms, 50):.2f} ms | "
            f"{np.percentile(ms, 99.9):.1f} ms | {ms.max():.1f} ms |"
        )
    print("\nstatuses: " + ", ".join(f"{k} {v}" for k, v in sorted(total.statuses.items())))
    for line in total.examples:
        print(f"- {line}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()

"""The contact guard's cost per control cycle (``socialnav.planner.contact_guard``).

Run: ``.venv/bin/python benchmarks/bench_contact_guard.py [--quick]``.

Setup: each robot at full speed turning at full rate in a 3 m corridor of a 12 m × 12 m static
map (the guard's wall check runs on every candidate's stop, as in the navigator), 20 people
in a 10 m × 10 m area around it (seeded). Rows per robot: the acceleration limits alone
(``enforce_limits``, what every command went through before; the baseline), the guard with
nobody within reach (the common case), with someone touching the robot's back (the command
and its stop are checked and kept), and with someone touching its front (no reachable command
avoids closing on them: the whole search over the acceleration window, 7 values per axis, 343
commands for the PR2, 49 for the Pioneer). ``stays`` says whether the guard kept the command.
The guard runs after the limits: a cycle costs the two rows' sum.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Case, machine_note, quick_option, run_table
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.contact_guard import guard_contact
from socialnav.planner.limits import enforce_limits
from socialnav.world.grid import LETHAL, Costmap, GridGeometry

DT = 0.1
#: the static map the navigator hands the guard: 12 m × 12 m at 0.05 m, the robot at its
#: centre, walls 1.5 m to either side (a corridor along x)
GEOMETRY = GridGeometry((240, 240), 0.05, (-6.0, -6.0))


def corridor() -> Costmap:
    costs = np.zeros(GEOMETRY.shape, np.uint8)
    costs[:90, :] = LETHAL  # y < -1.5 m
    costs[150:, :] = LETHAL  # y >= 1.5 m
    return Costmap(costs, GEOMETRY)


def crowd(robot: RobotModel, near: tuple[float, float] | None) -> SocialContext:
    """20 people at least 2 m from the robot (seeded), plus one at ``near`` (body frame = world:
    the robot stands at the origin facing +x)."""
    rng = np.random.default_rng(5)
    people = []
    if near is not None:
        people.append(Person(0, near, (0.0, 0.0)))
    while len(people) < 20:
        p = rng.uniform(-5.0, 5.0, 2)
        if np.hypot(*p) > 2.0 + robot.circumscribed_radius:
            people.append(Person(len(people), (float(p[0]), float(p[1])), (0.5, 0.0)))
    return SocialContext(tuple(people))


def main() -> None:
    quick = quick_option(__doc__)
    repeats = 50 if quick else 300
    cases = []
    cm = corridor()
    for robot in (PIONEER, PR2):
        v = np.array([robot.max_vel_x, 0.0, -robot.max_vel_theta])
        cmd = enforce_limits(v, v, robot, DT)
        front = float(robot.polygon[:, 0].max())
        scenes = {
            "guard: nobody within reach": crowd(robot, None),
            "guard: someone touching behind": crowd(robot, (-front - 0.3 - 0.02, 0.0)),
            "guard: someone touching in front": crowd(robot, (front + 0.3 + 0.02, 0.0)),
        }
        group = robot.name
        cases.append(
            Case(
                group,
                "enforce_limits alone",
                lambda r=robot, c=cmd, v=v: enforce_limits(c, v, r, DT),
                repeats,
            )
        )
        for name, social in scenes.items():
            out, _ = guard_contact(cmd, np.zeros(3), v, robot, social, DT, costmap=cm)
            cases.append(
                Case(
                    group,
                    name,
                    lambda r=robot, c=cmd, v=v, s=social: guard_contact(
                        c, np.zeros(3), v, r, s, DT, costmap=cm
                    ),
                    repeats,
                    baseline="enforce_limits alone",
                    extra={"stays": "yes" if out is cmd else "no"},
                )
            )
    run_table(cases, f"Contact guard, one call per control cycle ({machine_note()})")


if __name__ == "__main__":
    main()

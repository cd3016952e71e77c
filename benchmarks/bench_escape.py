"""The occupancy critic's escape from overlap: one ``score`` call with the robot already touching.

Run: ``.venv/bin/python benchmarks/bench_escape.py [--quick]``.

Setup: a 5 m × 5 m local costmap at 0.05 m (100 × 100 cells), a corridor's two walls and a
partition, 20 people marked as the navigator marks them, one of them overlapping the robot's
footprint, so every rollout takes the escape rule. ``N × T`` = samples × poses (a twist grid
over each robot's limits, the planners' rollout settings). Rows: the whole ``score`` (the
per-cell rule, then the wall floor on the trajectories it keeps), and, as the baseline measured
in the same run, the per-cell rule alone (``_never_closer``, the escape before the wall floor).
A fresh context per call: the per-cycle distance transforms are in the timing.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Case, machine_note, quick_option, run_table
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics import OccupancyCritic
from socialnav.planner.critics.occupancy import _never_closer, _start_in_collision
from socialnav.planner.rollout import RolloutParams, rollout
from socialnav.world.costmap import add_obstacle_discs
from socialnav.world.grid import Costmap, GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize

GEOMETRY = GridGeometry((100, 100), 0.05)
WALLS = np.array([[[0.0, 0.9], [5.0, 0.9]], [[0.0, 4.1], [5.0, 4.1]], [[3.5, 2.0], [3.5, 3.0]]])
POSE = np.array([2.5, 2.5, 0.3])


def scene(robot: RobotModel) -> tuple[Costmap, SocialContext]:
    """The costmap with the people marked, and the people (seeded)."""
    rng = np.random.default_rng(3)
    people = [Person(0, (POSE[0] + robot.inscribed_radius + 0.2, POSE[1]))]  # touching
    while len(people) < 20:
        p = rng.uniform([0.3, 1.3], [4.7, 3.7])
        if np.hypot(*(p - POSE[:2])) > 0.9:
            people.append(Person(len(people), (float(p[0]), float(p[1]))))
    social = SocialContext(tuple(people))
    grown = social.radii() + GEOMETRY.resolution * np.sqrt(2.0) / 2.0
    cm = inflate(rasterize(GEOMETRY, segments=WALLS), GEOMETRY, robot.inscribed_radius)
    discs = np.column_stack([social.positions(), grown])
    return add_obstacle_discs(cm, discs, robot.inscribed_radius), social


def context(cm: Costmap, robot: RobotModel, social: SocialContext) -> PlanningContext:
    return PlanningContext(
        pose=POSE.copy(),
        velocity=np.zeros(3),
        goal=np.array([4.5, 2.5, 0.0]),
        global_path=np.array([POSE[:2], [4.5, 2.5]]),
        costmap=cm,
        robot=robot,
        social=social,
    )


def main() -> None:
    quick = quick_option(__doc__)
    cases = []
    for robot, (nv, ny, nw) in ((PIONEER, (6, 1, 11)), (PR2, (6, 5, 11)), (PR2, (20, 5, 20))):
        cm, social = scene(robot)
        v, vy, w = np.meshgrid(
            np.linspace(robot.min_vel_x, robot.max_vel_x, nv),
            np.linspace(-robot.max_vel_y, robot.max_vel_y, ny),
            np.linspace(-robot.max_vel_theta, robot.max_vel_theta, nw),
        )
        twists = np.column_stack([v.ravel(), vy.ravel(), w.ravel()])
        trajs = rollout(POSE, np.zeros(3), twists, robot, RolloutParams())
        assert _start_in_collision(context(cm, robot, social), POSE, True)
        group = f"{robot.name} {trajs.poses.shape[0]}×{trajs.poses.shape[1]}"
        legal = int(
            (~OccupancyCritic().score(trajs, context(cm, robot, social)).illegal["collision"]).sum()
        )
        repeats = 3 if quick else 9
        cases += [
            Case(
                group,
                "per-cell rule alone",
                lambda cm=cm, r=robot, s=social, t=trajs: _never_closer(
                    context(cm, r, s), t.poses, True
                ),
                repeats,
            ),
            Case(
                group,
                "score: per-cell rule + wall floor",
                lambda cm=cm, r=robot, s=social, t=trajs: OccupancyCritic().score(
                    t, context(cm, r, s)
                ),
                repeats,
                baseline="per-cell rule alone",
                extra={"legal": str(legal)},
            ),
        ]
    run_table(cases, f"Escape from overlap, one score call ({machine_note()})")


if __name__ == "__main__":
    main()

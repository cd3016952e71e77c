"""Social critics and social-goal geometry: time per planning cycle.

Run: ``.venv/bin/python benchmarks/bench_social.py``. Critic rows score ``N`` trajectories of
``T = 68`` steps (sim_time 1.7 s at 0.025 s) against 6 people, one group and one artwork; the
baseline is a plain per-candidate Python loop computing the interpersonal cost (max over time).
"""

from __future__ import annotations

import numpy as np

from harness import Case, run_table
from socialnav.core.robot import PR2
from socialnav.core.scene import Artwork, Group, Person, SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics import (
    ActivitySpaceCritic,
    GroupCritic,
    InterpersonalCritic,
    SocialGoalCritic,
)
from socialnav.social.goals import (
    SocialGoal,
    activity_space_waypoint,
    o_formation_join_pose,
    presenter_pose,
    queue_tail_pose,
)
from socialnav.social.resolve import resolve_social_goal
from socialnav.world.grid import Costmap, GridGeometry

SOCIAL = SocialContext(
    (
        Person(0, (1.0, 0.5), (0.2, 0.0)),
        Person(1, (-0.5, 1.0), (0.0, -0.3)),
        Person(2, (4.0, 4.9)),
        Person(3, (3.1, 4.0)),
        Person(4, (4.9, 4.0)),
        Person(5, (0.0, -1.0), yaw=-np.pi / 2),
    ),
    groups=(Group((2, 3, 4)),),
    artworks=(Artwork((0.0, -2.5), 1.2, np.pi / 2, (5,)),),
)


def make_inputs(n: int, steps: int = 68, seed: int = 0) -> tuple[Trajectories, PlanningContext]:
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.7, steps)
    xy = rng.uniform(-3, 5, (n, 1, 2)) + np.cumsum(rng.normal(0, 0.02, (n, steps, 2)), axis=1)
    poses = np.concatenate([xy, rng.uniform(-np.pi, np.pi, (n, steps, 1))], axis=-1)
    ctx = PlanningContext(
        pose=np.zeros(3),
        velocity=np.zeros(3),
        goal=np.zeros(3),
        global_path=np.zeros((0, 2)),
        costmap=Costmap(np.zeros((4, 4), np.uint8), GridGeometry((4, 4), 1.0)),
        robot=PR2,
        social=SOCIAL,
        social_goal=SocialGoal(np.array([4.0, 3.2, -np.pi / 2]), "o_formation"),
    )
    return Trajectories(np.zeros((n, 3)), poses, t), ctx


def loop_interpersonal(trajs: Trajectories, ctx: PlanningContext) -> np.ndarray:
    """Per-candidate Python loop (the baseline a direct port would write)."""
    people = ctx.people_at(trajs.t)
    out = np.zeros(len(trajs))
    for i in range(len(trajs)):
        best = 0.0
        for k in range(trajs.t.shape[0]):
            for p in people[k]:
                d = float(np.hypot(*(trajs.poses[i, k, :2] - p)))
                if d <= 1.5:
                    best = max(best, float(np.exp(1.0 / max(d, 0.1))))
        out[i] = best
    return out


def main() -> None:
    cases: list[Case] = []
    for n in (400, 2000):
        trajs, ctx = make_inputs(n)
        group = f"critics N={n}"
        extra = {"N": str(n), "T": "68", "K": "6"}
        if n == 400:
            cases.append(
                Case(
                    group,
                    "loop interpersonal",
                    lambda tr=trajs, c=ctx: loop_interpersonal(tr, c),
                    repeats=3,
                    extra=extra,
                )
            )
        base = "loop interpersonal" if n == 400 else None
        critics = {
            "interpersonal last": InterpersonalCritic(),
            "interpersonal max_over_time": InterpersonalCritic(evaluation="max_over_time"),
            "group max_over_time": GroupCritic(evaluation="max_over_time", illegal_inside=True),
            "social_goal": SocialGoalCritic(heading_weight=1.0),
            "activity_space": ActivitySpaceCritic(illegal_inside=True),
        }
        for name, critic in critics.items():
            cases.append(
                Case(
                    group,
                    name,
                    lambda cr=critic, tr=trajs, c=ctx: cr.score(tr, c),
                    baseline=base,
                    extra=extra,
                )
            )
    a = np.radians([90, 180, 270])
    members = np.column_stack([12.5 + 0.9 * np.cos(a), 12.5 + 0.9 * np.sin(a)])
    queue = [(12.5, 19.4), (12.5, 18.6), (12.5, 17.8)]
    geo = "social goals (one call)"
    cases += [
        Case(
            geo,
            "o_formation join",
            lambda: o_formation_join_pose(members, "join", (20, 12.5)),
            repeats=50,
        ),
        Case(geo, "queue tail", lambda: queue_tail_pose(queue, (12.5, 20.3)), repeats=50),
        Case(
            geo,
            "presenter",
            lambda: presenter_pose(
                (13, 25), 1.2, -np.pi / 2, (13, 23.5), np.pi / 2, robot_position=(5, 17)
            ),
            repeats=50,
        ),
        Case(
            geo,
            "activity waypoint",
            lambda: activity_space_waypoint(
                (13, 25), 1.2, -np.pi / 2, (13, 22.5), (7, 23.8), (19, 23.8)
            ),
            repeats=50,
        ),
        Case(
            geo,
            "resolve (group + art)",
            lambda: resolve_social_goal(SOCIAL, (4.0, 4.0, 0.0), (0.0, 0.0, 0.0)),
            repeats=50,
        ),
    ]
    run_table(cases, "social critics and social goals")


if __name__ == "__main__":
    main()

"""What ``InterpersonalCritic(passage_distance=True)`` costs per planning cycle.

Run: ``.venv/bin/python benchmarks/bench_passage.py``. A 2.52 m corridor (0.05 m cells) with
``K`` people standing near the plan (pairs side by side, as in the generated hallway) and one
walker; ``paccet``'s ID critic (max over time, partners, passing distance, polygon approach
rule) scores ``N = 600`` trajectories of ``T = 68`` steps, without the option (the baseline of
each group) and with it; the last row of each group is :func:`passage_clearances` alone.
"""

from __future__ import annotations

import numpy as np

from harness import Case, run_table
from socialnav.core.robot import PIONEER
from socialnav.core.scene import Person, SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.interpersonal import InterpersonalCritic, passage_clearances
from socialnav.world.costmap import add_obstacle_discs
from socialnav.world.grid import GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize

HALF, RES, N, T = 1.26, 0.05, 600, 68


def corridor(standing: int) -> PlanningContext:
    """The corridor context with ``standing`` people near the plan and one walker."""
    geometry = GridGeometry((80, 320), RES, (0.0, -2.0))
    walls = np.array([[[0.0, -HALF], [16.0, -HALF]], [[0.0, HALF], [16.0, HALF]]])
    costmap = inflate(rasterize(geometry, segments=walls), geometry, PIONEER.inscribed_radius)
    people = [Person(i, (5.0 + 0.6 * (i // 2), -0.19 + 0.69 * (i % 2))) for i in range(standing)]
    people.append(Person(99, (7.0, 0.8), velocity=(-1.0, 0.0)))
    social = SocialContext(tuple(people))
    grown = social.radii() + RES * np.sqrt(2.0) / 2.0
    costmap = add_obstacle_discs(
        costmap, np.column_stack([social.positions(), grown]), PIONEER.inscribed_radius
    )
    path = np.column_stack([np.linspace(4.0, 13.0, 60), np.full(60, -0.9)])
    return PlanningContext(
        pose=np.array([4.0, -0.9, 0.0]),
        velocity=np.array([0.3, 0.0, 0.0]),
        goal=np.array([13.0, -0.9, 0.0]),
        global_path=path,
        costmap=costmap,
        robot=PIONEER,
        social=social,
    )


def trajectories(seed: int = 0) -> Trajectories:
    """``N`` unicycle rollouts of 1.7 s from the corridor's start pose."""
    rng = np.random.default_rng(seed)
    v = rng.uniform(0.0, 0.5, N)
    w = rng.uniform(-0.6, 0.6, N)
    t = np.linspace(0.0, 1.7, T)
    yaw = w[:, None] * t[None]  # (N, T); poses[:, 0] is the start pose
    dt = t[1] - t[0]
    start = np.zeros((N, 1))
    x = 4.0 + np.hstack([start, np.cumsum(v[:, None] * np.cos(yaw[:, :-1]) * dt, axis=1)])
    y = -0.9 + np.hstack([start, np.cumsum(v[:, None] * np.sin(yaw[:, :-1]) * dt, axis=1)])
    poses = np.stack([x, y, yaw], axis=-1)
    return Trajectories(np.column_stack([v, np.zeros(N), w]), poses, t)


def main() -> None:
    trajs = trajectories()
    options = dict(
        evaluation="max_over_time",
        partner_distance=True,
        hold_horizon=2.5,
        approach_footprint="polygon",
    )
    plain = InterpersonalCritic(**options)  # type: ignore[arg-type]
    passage = InterpersonalCritic(**options, passage_distance=True)  # type: ignore[arg-type]
    cases = []
    for standing in (1, 3, 6):
        ctx = corridor(standing)
        group = f"{standing} standing + 1 walker"
        base = "ID without passage"
        # a fresh context per call: the critic's per-cycle cache must not carry over
        cases += [
            Case(group, base, lambda c=ctx: plain.score(trajectories_for(c, trajs), c), 15),
            Case(
                group,
                "ID with passage",
                lambda c=ctx: passage.score(trajectories_for(c, trajs), c),
                15,
                baseline=base,
            ),
            Case(group, "passage_clearances alone", lambda c=ctx: passage_clearances(c, 1.5), 50),
        ]
    run_table(cases, f"passage distance: ID critic on N = {N} trajectories of T = {T} steps")


def trajectories_for(ctx: PlanningContext, trajs: Trajectories) -> Trajectories:
    """A copy of ``trajs`` (a new batch, so the per-cycle distance cache is rebuilt) after
    clearing ``ctx``'s cache, as a new planning cycle would."""
    ctx.cache.people_distances = None
    return Trajectories(trajs.twists, trajs.poses.copy(), trajs.t)


if __name__ == "__main__":
    main()

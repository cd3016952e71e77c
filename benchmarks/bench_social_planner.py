"""Social planning cycle: PaCcET vs weighted-sum selection, and PaCcET's share of the cycle.

Run: ``.venv/bin/python benchmarks/bench_social_planner.py [--quick]``.

Setup: a 10 m × 10 m local costmap at 0.05 m (200 × 200 cells) with walls, a partition, a box
and a pillar, inflated for the PR2, with people added as obstacle discs (as the Navigator's
obstacle layer does). The holonomic PR2 at (4.8, 5.8) moving at 0.3 m/s, on its approach from
(1.0, 4.5); the global plan (``plan_path``) runs from the robot to the target. People (seeded):
with 5 or more people, 3 stand in an O-formation ~2.2 m ahead that the robot joins (social goal
``o_formation_join_pose``; objectives navigation + ID + GD + SGD, all active); the others stand
or walk along the path (0.3–1.0 m/s) 0.6–2.5 m beside it (up to 4 m with more than 20),
from 3 m behind to 4 m ahead (the first one stands 1–1.5 m ahead). With 1 person there is no
group and no social goal (navigation + ID: the paper's hallway, m = 2).

Planners are the real presets through ``LocalPlanner.plan(ctx, record=True)`` (a fresh context
every cycle, so per-cycle BFS grids are rebuilt as in the control loop):

- ``weighted sum`` = preset ``weighted_social`` (recommended objectives, paper weights) — the
  baseline for ``PaCcET recommended`` (``paccet``: same objectives, L1 target, default options);
- ``weighted sum, paper obj.`` = the paper's objectives (ID per nearest person ≤ 3, end-point
  rule, people static) with a weighted sum — the baseline for ``PaCcET paper (parity)``
  (``paccet_paper``: reference weights and bisections). The two objective sets differ in cost,
  so each PaCcET row is compared with the weighted sum over the *same* objectives.

Cycle time = the record's ``timing["total"]``; selection time = ``timing["select"]`` of the same
cycle; share = median over cycles of select / total. Cycles are interleaved across the four
planners of a row group; ``cycle (min)`` is printed too because medians drift on a loaded machine.
"""

from __future__ import annotations

import statistics
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from bench_planner import fresh_grids
from harness import format_seconds, quick_option, time_interleaved
from socialnav.core.robot import PR2
from socialnav.core.scene import Group, Person, SocialContext
from socialnav.moo.selection import WeightedSum
from socialnav.planner import kernels
from socialnav.planner.context import PlanningContext
from socialnav.planner.global_planner import plan_path
from socialnav.planner.local_planner import LocalPlanner, LocalPlannerParams
from socialnav.planner.presets import (
    PRESETS,
    build_local_planner,
    has_social_goal,
    paper_objectives,
)
from socialnav.planner.record import EvaluationRecord
from socialnav.planner.rollout import rollout
from socialnav.social.goals import o_formation_join_pose
from socialnav.world.costmap import add_obstacle_discs
from socialnav.world.grid import INSCRIBED, Costmap, GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize

SEED = 7
ROBOT = PR2
START = np.array([1.0, 4.5])  # where the robot's approach began (people line this path)
POSE = np.array([4.8, 5.8, 0.35])  # ~2.2 m before the join spot: every social term is active
VEL = np.array([0.3, 0.0, 0.0])
GIVEN_GOAL = np.array([9.0, 7.2, 0.0])  # 1 person: no social goal; START–goal passes POSE
GROUP_CENTER = np.array([7.6, 6.6])
GROUP_RADIUS = 0.7
GROUP_BEARINGS = np.radians([20.0, 110.0, 250.0])  # widest gap (110°→250°) faces the robot
PEOPLE_COUNTS = (1, 5, 10, 20, 50)
# (vx, vy, vth) samples → N at VEL (in-place rotations below min_in_place_vel_theta are dropped).
SAMPLINGS = ((9, 5, 9), (13, 9, 17))


WALLS = np.array([[[0.3, 0.6], [9.7, 0.6]], [[0.3, 9.4], [9.7, 9.4]], [[6.5, 0.6], [6.5, 3.0]]])
BOXES = [np.array([[3.0, 6.8], [3.8, 6.8], [3.8, 7.6], [3.0, 7.6]])]
PILLAR = np.array([[5.0, 3.6, 0.2]])


def static_costmap() -> Costmap:
    geom = GridGeometry((200, 200), 0.05)
    occ = rasterize(geom, segments=WALLS, polygons=BOXES, discs=PILLAR, thickness=0.1)
    return inflate(occ, geom, ROBOT.inscribed_radius)


@dataclass
class Scene:
    social: SocialContext
    social_goal: object | None
    goal: np.ndarray
    path: np.ndarray
    costmap: Costmap  # local costmap with people as obstacles


def group_members() -> np.ndarray:
    return GROUP_CENTER + GROUP_RADIUS * np.column_stack(
        [np.cos(GROUP_BEARINGS), np.sin(GROUP_BEARINGS)]
    )


def place_people(
    count: int, path: np.ndarray, static: Costmap, taken: list[np.ndarray], rng: np.random.Generator
) -> list[Person]:
    """``count`` people 0.6–2.5 m beside ``path (P, 2)`` from 3 m behind to 4 m ahead of the
    robot, on free cells, ≥ 0.7 m apart; half of them walking along the path. The first one
    stands 1–1.5 m ahead, 0.6–0.9 m beside the path, so the ID objective is active."""
    seg = np.diff(path, axis=0)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*seg.T))])
    s_robot = s[np.argmin(np.hypot(*(path - POSE[:2]).T))]
    usable = np.flatnonzero((s > s_robot - 3.0) & (s < min(s_robot + 4.0, s[-1] - 0.8)))
    # Crowds beyond 20 need a wider band (up to 4 m beside the path) and 0.6 m spacing.
    band, spacing = (2.5, 0.7) if count <= 20 else (4.0, 0.6)
    people: list[Person] = []
    for _ in range(20000):
        if len(people) == count:
            break
        first = not people  # the person the robot is passing: 1–1.5 m ahead, close to the path
        ahead = (s > s_robot + 1.0) & (s < s_robot + 1.5)
        i = int(rng.choice(np.flatnonzero(ahead) if first else usable))
        tangent = seg[min(i, seg.shape[0] - 1)]
        normal = np.array([-tangent[1], tangent[0]]) / np.hypot(*tangent)
        offset = rng.uniform(0.6, 0.9) if first else rng.uniform(0.6, band)
        p = path[i] + rng.choice([-1.0, 1.0]) * offset * normal
        # Half walk along the path (either way); a walker starts far enough away that it cannot
        # reach the robot's spot within the 1.7 s horizon, so the scene stays passable.
        speed = float(rng.uniform(0.3, 1.0)) if rng.random() < 0.5 and not first else 0.0
        heading = float(np.arctan2(tangent[1], tangent[0]) + np.pi * rng.integers(2))
        if int(static.cost_at(p)) != 0 or np.hypot(*(p - GROUP_CENTER)) < 1.6:
            continue
        if np.hypot(*(p - POSE[:2])) < 1.0 + 1.7 * speed:
            continue
        if taken and min(np.hypot(*(p - q)) for q in taken) < spacing:
            continue
        taken.append(p)
        vel = (speed * np.cos(heading), speed * np.sin(heading))
        people.append(Person(100 + len(people), (float(p[0]), float(p[1])), vel, heading))
    if len(people) < count:
        raise RuntimeError(f"placed only {len(people)} of {count} people")
    return people


def build_scene(n_people: int, static: Costmap) -> Scene:
    rng = np.random.default_rng(SEED + n_people)
    free = static.costs < INSCRIBED
    if n_people >= 3:
        members = group_members()
        yaws = np.arctan2(*(GROUP_CENTER - members).T[::-1])  # facing the group centre
        group = [
            Person(k, (float(x), float(y)), yaw=float(a))
            for k, ((x, y), a) in enumerate(zip(members, yaws, strict=True))
        ]
        sg = o_formation_join_pose(
            members,
            robot_position=POSE[:2],
            free_fn=lambda pts: free[tuple(static.geometry.world_to_cell(pts).T)],
        )
        goal = np.asarray(sg.pose, dtype=float)
        groups: tuple[Group, ...] = (Group((0, 1, 2)),)
        taken = list(members)
    else:
        group, sg, goal, groups, taken = [], None, GIVEN_GOAL, (), []
    approach = plan_path(static, START, goal[:2])
    plan = plan_path(static, POSE[:2], goal[:2])  # the pruned plan, from the robot onwards
    if plan.path is None or approach.path is None:
        raise RuntimeError(f"global plan failed: {plan.status}, {approach.status}")
    others = place_people(n_people - len(group), approach.path, static, taken, rng)
    social = SocialContext(tuple(group + others), groups)
    discs = np.column_stack([social.positions(), social.radii()])
    local = add_obstacle_discs(static, discs, ROBOT.inscribed_radius)
    return Scene(social, sg, goal, plan.path, local)


def make_context(scene: Scene, predict: bool) -> PlanningContext:
    return PlanningContext(
        POSE,
        VEL,
        scene.goal,
        scene.path,
        scene.costmap,
        ROBOT,
        social=scene.social,
        social_goal=scene.social_goal,
        predict_people=predict,
    )


def planners(
    scene: Scene, params: LocalPlannerParams
) -> list[tuple[str, str | None, LocalPlanner, bool]]:
    """(variant, baseline variant, planner, predict_people) rows of one group."""
    social = scene.social
    ws = "weighted sum"
    ws_paper = "weighted sum, paper obj."
    pairs = paper_objectives(social, has_social_goal(social), params)
    paper_ws = LocalPlanner(
        ROBOT, [o for o, _ in pairs], WeightedSum([w for _, w in pairs]), params
    )
    return [
        (
            ws,
            None,
            build_local_planner("weighted_social", ROBOT, social, params),
            PRESETS.get("weighted_social").predict_people,
        ),
        (
            "PaCcET recommended",
            ws,
            build_local_planner("paccet", ROBOT, social, params),
            PRESETS.get("paccet").predict_people,
        ),
        (ws_paper, None, paper_ws, PRESETS.get("paccet_paper").predict_people),
        (
            "PaCcET paper (parity)",
            ws_paper,
            build_local_planner("paccet_paper", ROBOT, social, params),
            PRESETS.get("paccet_paper").predict_people,
        ),
    ]


@dataclass
class Measured:
    total: list[float] = field(default_factory=list)
    stages: dict[str, list[float]] = field(default_factory=dict)
    shares: list[float] = field(default_factory=list)
    record: EvaluationRecord | None = None

    def add(self, rec: EvaluationRecord) -> None:
        self.total.append(rec.timing["total"])
        self.shares.append(rec.timing.get("select", 0.0) / rec.timing["total"])
        for k, v in rec.timing.items():
            self.stages.setdefault(k, []).append(v)
        self.record = rec

    def other(self) -> list[float]:
        """Per-cycle time outside the timed stages (validation, F assembly, bookkeeping)."""
        parts = [v for k, v in self.stages.items() if k != "total"]
        return [t - sum(p[i] for p in parts) for i, t in enumerate(self.total)]


def measure_group(
    rows: list[tuple[LocalPlanner, Callable[[], PlanningContext]]], repeats: int, warmup: int
) -> list[Measured]:
    """Cycles interleaved across the planners of one group, so drift and load hit all alike."""
    out = [Measured() for _ in rows]
    for r in range(warmup + repeats):
        for (planner, ctx_fn), res in zip(rows, out, strict=True):
            rec = planner.plan(ctx_fn(), record=True).record
            assert rec is not None
            if r >= warmup:
                res.add(rec)
    return out


def med(values: list[float]) -> float:
    return statistics.median(values)


def print_table(header: list[str], body: list[list[str]]) -> None:
    widths = [max([len(h)] + [len(b[i]) for b in body]) for i, h in enumerate(header)]
    print("| " + " | ".join(h.ljust(w) for h, w in zip(header, widths, strict=True)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for b in body:
        print("| " + " | ".join(c.ljust(w) for c, w in zip(b, widths, strict=True)) + " |")


def stage_order(name: str) -> tuple[int, str]:
    rank = {"sample": 0, "rollout": 1, "prepare": 2, "score": 3, "select": 4, "total": 6}
    return rank.get(name.split(":")[0], 5), name


def print_breakdown(title: str, measured: dict[str, Measured]) -> None:
    """Stage medians (ms) per variant, with each stage's share of the median cycle."""
    names = sorted({k for res in measured.values() for k in res.stages}, key=stage_order)
    rows = []
    for stage in [*names[:-1], "other (untimed)", names[-1]]:
        row = [stage]
        for res in measured.values():
            total = med(res.total)
            if stage == "other (untimed)":  # per-cycle residual: medians do not add up
                t = med(res.other())
            elif stage in res.stages:
                t = med(res.stages[stage])
            else:
                row.append("")
                continue
            row.append(f"{t * 1e3:.3f} ({100 * t / total:.0f} %)")
        rows.append(row)
    print(f"\n## {title} (ms; share of the median cycle)\n")
    print_table(["stage", *measured], rows)


def peak_memory(fn: Callable[[], object]) -> int:
    """tracemalloc peak (bytes) over one call of ``fn`` (warmed up by the caller)."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def compiled_vs_reference(scenes: dict[int, Scene], repeats: int) -> None:
    """``paccet`` cycles at N ≈ 2000 on the compiled kernels and on the NumPy reference,
    interleaved in one run (each on its own planner, so PaCcET's archive evolves alike), with
    fresh grids every cycle (a moving robot) and, compiled, with the prepared grids reused (this
    scene is static); the chosen candidates must agree. Peak memory: tracemalloc over one
    warmed-up cycle."""
    if not kernels.enabled():
        print("\n(compiled kernels unavailable or SOCIALNAV_KERNELS=reference: skipped)")
        return
    params = LocalPlannerParams(*SAMPLINGS[-1])
    predict = PRESETS.get("paccet").predict_people
    print(
        "\n## PaCcET cycle, compiled kernels vs the NumPy reference (same run, interleaved; "
        f"kernel compile/cache load {kernels.compile_seconds:.2f} s, at construction)\n"
    )
    header = [
        "people",
        "N",
        "variant",
        "cycle wall (median)",
        "cycle wall (min)",
        "cycle CPU (median)",
        "speed-up (CPU)",
        "peak memory",
    ]
    body: list[list[str]] = []
    for n_people in sorted(scenes):
        scene = scenes[n_people]
        runs = {}
        for name, flag, fresh in (
            ("numpy reference, fresh grids (baseline)", False, True),
            ("compiled, fresh grids", True, True),
            ("compiled, grids reused", True, False),
        ):
            planner = build_local_planner("paccet", ROBOT, scene.social, params)

            def cycle(planner=planner, flag=flag, scene=scene):
                previous = kernels.set_enabled(flag)
                try:
                    return planner.plan(make_context(scene, predict), record=True)
                finally:
                    kernels.set_enabled(previous)

            runs[name] = fresh_grids(cycle) if fresh else cycle
        chosen = set()
        for run in runs.values():
            record = run().record
            assert record is not None
            chosen.add(record.chosen)
        assert len(chosen) == 1, "compiled and reference choices differ"
        timed = time_interleaved(list(runs.values()), repeats, warmup=1)
        base = timed[0][2]
        for (name, run), (w, wmin, c) in zip(runs.items(), timed, strict=True):
            peak = peak_memory(run)
            body.append(
                [
                    str(n_people),
                    str(record.num_samples),
                    name,
                    format_seconds(w),
                    format_seconds(wmin),
                    format_seconds(c),
                    "" if c == base else f"{base / c:.1f}x",
                    f"{peak / 2**20:.1f} MB",
                ]
            )
    print_table(header, body)


def navground_rows(scenes: dict[int, Scene], repeats: int) -> None:
    """navground's HL, ORCA and SocialForce computing the robot's command in the same scenes
    (walls, box edges and pillar as obstacles, the people as neighbours, the same goal): CPU
    time per ``compute_cmd`` = one agent step."""
    try:
        from navground import core

        from socialnav.sim.baselines import make_behavior
    except ImportError:
        print("\n(navground not installed: no navground rows)")
        return
    print("\n## navground behaviours in the same scenes (one agent step = one compute_cmd)\n")
    header = ["people", "behaviour", "step CPU (median)", "step wall (median)"]
    body: list[list[str]] = []
    edges = [*WALLS, *(np.stack([b, np.roll(b, -1, axis=0)], axis=1) for b in BOXES)]
    segments = [
        core.LineSegment(tuple(map(float, a)), tuple(map(float, b)))
        for group in edges
        for a, b in np.asarray(group).reshape(-1, 2, 2)
    ]
    for n_people in sorted(scenes):
        scene = scenes[n_people]
        for name in ("HL", "ORCA", "SocialForce"):
            behavior = make_behavior(name, ROBOT)
            state = behavior.environment_state
            state.line_obstacles = segments
            state.static_obstacles = [core.Disc((x, y), r) for x, y, r in PILLAR.tolist()]
            state.neighbors = [
                core.Neighbor(p.position, p.radius, p.velocity, p.id) for p in scene.social.people
            ]
            behavior.pose = core.Pose2((float(POSE[0]), float(POSE[1])), float(POSE[2]))
            behavior.twist = core.Twist2((float(VEL[0]), 0.0), 0.0, frame=core.Frame.relative)
            behavior.target = core.Target(
                position=(float(scene.goal[0]), float(scene.goal[1])), position_tolerance=0.1
            )

            def step(behavior=behavior):
                return behavior.compute_cmd(0.1, core.Frame.relative)

            ((w, _, c),) = time_interleaved([step], 10 * repeats, warmup=5)
            body.append([str(n_people), name, format_seconds(c), format_seconds(w)])
    print_table(header, body)


def main(quick: bool = False) -> None:
    repeats, warmup = (5, 1) if quick else (25, 3)
    static = static_costmap()
    scenes = {k: build_scene(k, static) for k in PEOPLE_COUNTS}
    header = [
        "people",
        "N",
        "variant",
        "m",
        "legal",
        "|ND|",
        "cycle (median)",
        "cycle (min)",
        "vs WS (same obj.)",
        "select (median)",
        "select share",
    ]
    body: list[list[str]] = []
    # Stage breakdowns: the brief's case (5 people, N ≈ 400) and the slowest (20, N ≈ 2000).
    wanted = {(5, SAMPLINGS[0]): {}, (20, SAMPLINGS[-1]): {}, (50, SAMPLINGS[-1]): {}}
    breakdowns: dict[tuple[int, tuple[int, int, int]], dict[str, Measured]] = wanted
    poses_per_rollout = {}
    sample_counts = {}
    for n_people in PEOPLE_COUNTS:
        scene = scenes[n_people]
        for samples in SAMPLINGS:
            params = LocalPlannerParams(*samples)
            group = planners(scene, params)
            measured = measure_group(
                [
                    (planner, lambda s=scene, p=predict: make_context(s, p))
                    for _, _, planner, predict in group
                ],
                repeats,
                warmup,
            )
            results = {variant: res for (variant, *_), res in zip(group, measured, strict=True)}
            for (variant, base, *_), res in zip(group, measured, strict=True):
                rec = res.record
                assert rec is not None
                if rec.status != "OK":
                    print(f"warning: {n_people} people, {variant}: status {rec.status}")
                ratio = "" if base is None else f"{med(res.total) / med(results[base].total):.2f}x"
                nd = rec.selection.get("nondominated")
                body.append(
                    [
                        str(n_people),
                        str(rec.num_samples),
                        variant,
                        str(len(rec.objective_names)),
                        f"{rec.num_legal}/{rec.num_samples}",
                        "" if nd is None else str(int(np.count_nonzero(nd))),
                        format_seconds(med(res.total)),
                        format_seconds(min(res.total)),
                        ratio,
                        format_seconds(med(res.stages.get("select", [0.0]))),
                        f"{100 * med(res.shares):.1f} %",
                    ]
                )
            if (n_people, samples) in breakdowns:
                breakdowns[(n_people, samples)] = results
            rec = measured[0].record
            assert rec is not None
            sample_counts[samples] = rec.num_samples
            poses_per_rollout[samples] = rollout(POSE, VEL, rec.twists, ROBOT, params).t.size
    sizes = ", ".join(f"N = {sample_counts[k]} ({k[0]}x{k[1]}x{k[2]})" for k in SAMPLINGS)
    steps = {t - 1 for t in poses_per_rollout.values()}
    print(
        f"\n## Social planning cycle: PR2 at {VEL[0]} m/s, 10 m x 10 m costmap at 0.05 m, "
        f"{sizes}, T = {'/'.join(map(str, sorted(steps)))} rollout steps (sim_time 1.7 s); "
        f"median of {repeats} cycles per row\n"
    )
    print(
        "`vs WS` = cycle time / the weighted-sum cycle over the same objectives "
        "(above 1 = slower); |ND| = PaCcET archive size (non-dominated legal candidates)\n"
    )
    print_table(header, body)
    for (n_people, samples), measured in breakdowns.items():
        print_breakdown(f"Stage medians, {n_people} people, N = {sample_counts[samples]}", measured)
    compiled_vs_reference(scenes, repeats)
    navground_rows(scenes, repeats)


if __name__ == "__main__":
    main(quick_option(__doc__))

"""Benchmark of the metric library on synthetic episode records.

Run: ``python benchmarks/bench_metrics.py``. Rows: the full registry on records of growing size
(baseline: the smallest record), and two kernels against a per-sample Python loop measured in
the same run (the loop is the baseline).
"""

from __future__ import annotations

import numpy as np

from harness import Case, run_table
from socialnav.core.episode import EpisodeRecord
from socialnav.core.robot import PR2
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.metrics import compute_metrics
from socialnav.metrics.scenario import cut_in_depth, queue_bands
from socialnav.metrics.series import convex_overlap_depth, footprint_world


def synthetic_record(steps: int, people: int, seed: int = 0) -> EpisodeRecord:
    """A wandering robot among ``people`` (a queue, a group and an art viewer among them)."""
    rng = np.random.default_rng(seed)
    dt = 0.1
    t = np.arange(steps) * dt
    xy = np.column_stack([0.05 * t, np.sin(0.1 * t)]) + rng.normal(0, 0.01, (steps, 2))
    yaw = np.unwrap(np.arctan2(np.gradient(xy[:, 1]), np.gradient(xy[:, 0])))
    base = rng.uniform(-5, 5, (people, 2))
    pos = base[None] + rng.normal(0, 0.02, (steps, people, 2)).cumsum(axis=0)
    vel = np.gradient(pos, dt, axis=0)
    ids = tuple(range(people))
    persons = tuple(Person(i, tuple(pos[0, i]), tuple(vel[0, i])) for i in ids)
    k = min(people, 3)
    context = SocialContext(
        persons,
        groups=(Group(ids[:k]),),
        queues=(Queue(ids[:k], service_point=(0.0, 9.0)),),
        artworks=(Artwork((0.0, 9.0), 1.2, -np.pi / 2, ids[:1]),),
    )
    return EpisodeRecord(
        dt=dt,
        times=t,
        robot_poses=np.column_stack([xy, yaw]),
        robot_twists=np.zeros((steps, 3)),
        robot_footprint=PR2.polygon,
        robot_radius=PR2.circumscribed_radius,
        people_ids=np.arange(people),
        people_positions=pos,
        people_velocities=vel,
        people_radii=np.full(people, 0.25),
        start=np.array([*xy[0], 0.0]),
        goal=np.array([*xy[-1], 0.0]),
        target=np.array([*xy[-1], 0.0]),
        goal_tolerance=0.2,
        time_limit=60.0,
        family="hallway",
        scenario="bench",
        context=context,
        meta={"robot": "pr2"},
    )


def proxemics_loop(record: EpisodeRecord) -> tuple[float, int, float]:
    """Per-sample Python loop: min distance, personal-space entries, personal-zone share."""
    best, entries, inside_count, was_inside = np.inf, 0, 0, False
    for t in range(record.num_steps):
        d = min(
            float(np.hypot(*(record.people_positions[t, k] - record.robot_xy[t])))
            for k in range(record.people_ids.shape[0])
        )
        best = min(best, d)
        inside = d < 1.2
        entries += int(inside and not was_inside)
        inside_count += int(inside)
        was_inside = inside
    return best, entries, inside_count / record.num_steps


def proxemics_vectorized(record: EpisodeRecord) -> dict[str, float]:
    names = ["min_distance_center", "proxemic_intrusions", "psc_1.2"]
    return compute_metrics(record, names)


def cut_in_loop(record: EpisodeRecord) -> float:
    bands = queue_bands(record)
    fp = footprint_world(record)
    return max(
        float(convex_overlap_depth(fp[t], band)) for t in range(record.num_steps) for band in bands
    )


def main() -> None:
    cases = []
    sizes = [(600, 1), (600, 10), (6000, 10), (6000, 50)]
    records = {size: synthetic_record(*size) for size in sizes}
    for size, rec in records.items():
        cases.append(
            Case(
                "compute_metrics (all)",
                f"T={size[0]} K={size[1]}",
                lambda rec=rec: compute_metrics(rec),
                repeats=5,
                baseline="T=600 K=1",
                extra={"samples": str(size[0])},
            )
        )
    big = records[(6000, 10)]
    cases += [
        Case(
            "proxemics T=6000 K=10",
            "python loop",
            lambda: proxemics_loop(big),
            repeats=3,
            baseline="python loop",
        ),
        Case(
            "proxemics T=6000 K=10",
            "vectorized",
            lambda: proxemics_vectorized(big),
            baseline="python loop",
        ),
        Case(
            "queue cut-in T=6000",
            "python loop",
            lambda: cut_in_loop(big),
            repeats=3,
            baseline="python loop",
        ),
        Case(
            "queue cut-in T=6000",
            "vectorized",
            lambda: cut_in_depth(big).max(),
            baseline="python loop",
        ),
    ]
    run_table(cases, title="metrics")


if __name__ == "__main__":
    main()

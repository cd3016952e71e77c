"""Suite throughput per backend: episodes per second on one spec, and the overhead against local.

The spec: the randomized suite over the five hallway scenarios × ``traditional``, ``paccet``,
``hl``, ``orca`` × both robots (40 episodes per seed), seeds 0–4 — 200 episodes; ``--episodes N``
takes the first N in (seed, run id) order, so every row runs the same episodes. Rows:

- ``local`` with 1 and 2 workers (joblib/loky process pool, the default backend);
- ``dask`` with a local 2-worker cluster (``distributed.LocalCluster``, one thread per worker);
- ``ray`` with a local 2-CPU cluster (``ray.init(num_cpus=2)``).

Each row is one timed run of the whole suite into a fresh folder (cluster start and stop, every
episode's files and the results dataset included); the rows of every backend are checked to be
the same as local's, timing columns aside. ``overhead`` is the wall time against ``local`` with
the same number of workers (1.00 = none). One run per row: a 200-episode suite takes minutes.

Run: ``.venv/bin/python benchmarks/bench_backends.py [--episodes 200] [--backends local,dask,ray]``.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

from socialnav.experiments.results import TIMING_COLUMNS
from socialnav.experiments.suite import EpisodeSpec, run_suite, suite_specs
from socialnav.sim.scenario import builtin_scenarios

PLANNERS = ("traditional", "paccet", "hl", "orca")
ROBOTS = ("pr2", "pioneer")


def spec(episodes: int) -> list[EpisodeSpec]:
    scenarios = [s for s in builtin_scenarios() if s.startswith("hallway")]
    per_seed = len(scenarios) * len(PLANNERS) * len(ROBOTS)
    seeds = math.ceil(episodes / per_seed)
    specs = suite_specs("randomized", scenarios, PLANNERS, ROBOTS, seeds)
    return sorted(specs, key=lambda s: (s.seed, s.run_id))[:episodes]


def comparable(rows: list[dict]) -> list[dict]:
    def same(v: object) -> object:
        return "nan" if isinstance(v, float) and math.isnan(v) else v

    return [{k: same(v) for k, v in r.items() if k not in TIMING_COLUMNS} for r in rows]


def differences(a: list[dict], b: list[dict]) -> list[str]:
    """``run_id: column`` for every cell that differs (timing columns excluded)."""
    if len(a) != len(b):
        return [f"{len(a)} rows against {len(b)}"]
    out = []
    for x, y in zip(a, b, strict=True):
        for key in sorted(set(x) | set(y)):
            if x.get(key) != y.get(key):
                out.append(f"{x.get('run_id')}: {key} {x.get(key)!r} vs {y.get(key)!r}")
    return out


def timed(specs: list[EpisodeSpec], backend: str, workers: int) -> tuple[float, list[dict]]:
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        rows = run_suite(specs, Path(folder), n_jobs=workers, suite="bench", backend=backend)
        return time.perf_counter() - start, rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--backends", default="local,dask,ray")
    args = parser.parse_args()
    specs = spec(args.episodes)
    runs = [("local", 1), ("local", 2)]
    runs += [(b, 2) for b in args.backends.split(",") if b != "local"]
    results: dict[tuple[str, int], float] = {}
    reference: list[dict] | None = None
    for backend, workers in runs:
        seconds, rows = timed(specs, backend, workers)
        results[(backend, workers)] = seconds
        errors = sum(1 for r in rows if r.get("error"))
        if reference is None:
            reference = comparable(rows)
        diff = differences(reference, comparable(rows))
        same = "yes" if not diff else f"NO ({'; '.join(diff[:5])})"
        print(
            f"  ran {backend} × {workers}: {seconds:.1f} s, {errors} errors, same rows: {same}",
            flush=True,
        )
    print()
    print(
        f"{len(specs)} episodes (randomized hallways; {', '.join(PLANNERS)}; {', '.join(ROBOTS)})"
    )
    header = f"{'backend':<8} {'workers':>7} {'wall (s)':>9} {'episodes/s':>11} {'overhead':>9}"
    print(header)
    print("-" * len(header))
    for (backend, workers), seconds in results.items():
        base = results[("local", workers)]
        print(
            f"{backend:<8} {workers:>7} {seconds:>9.1f} {len(specs) / seconds:>11.2f} "
            f"{seconds / base:>9.2f}"
        )
    print(
        "overhead = wall time / local's with the same workers. One run per row on a shared "
        "machine: read differences under ~10 % as noise."
    )


if __name__ == "__main__":
    main()

"""Suites of episodes: which runs make up a comparison, and running them in parallel.

``run_spec`` is a pure, picklable function of an :class:`EpisodeSpec`; seeds are fixed in the spec,
so results never depend on the number of workers or on the backend (``local``, ``dask``, ``ray``,
see :mod:`socialnav.experiments.backends`). A failed episode becomes a row with its error, never
the end of the suite. ``run_suite`` stores each finished episode at once in the results dataset
(:mod:`socialnav.experiments.results`) and resumes: episodes already stored without error are
skipped, so a killed suite loses only the episodes in flight.
"""

from __future__ import annotations

import itertools
import time
import traceback
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from socialnav.core.success import not_required_text
from socialnav.experiments.crowd import CrowdSpec

TABLE1_SCENARIO = "hallway_passing"
TABLE1_SEEDS = (0, 1, 2, 3, 4)
#: ``EpisodeSpec.scenario`` of a generated scene: ``"generated:<family>"``, the seed picks it
GENERATED_PREFIX = "generated:"


@dataclass(frozen=True)
class EpisodeSpec:
    """One run: scenario × planner × robot × seed × human model."""

    scenario: str
    planner: str
    robot: str
    seed: int = 0
    humans: str = "scripted"
    randomize: bool = False
    context: str = "given"

    @property
    def run_id(self) -> str:
        name = self.scenario.replace(GENERATED_PREFIX, "gen_")
        name = Path(name).stem if not self.scenario.startswith(GENERATED_PREFIX) else name
        suffix = "_rand" if self.randomize else ""
        # the given context keeps its historical ids, so earlier results still resume
        ctx = "" if self.context == "given" else f"__{self.context}"
        return f"{name}__{self.planner}__{self.robot}__{self.humans}{suffix}{ctx}__s{self.seed}"


def suite_specs(
    suite: str,
    scenarios: Sequence[str],
    planners: Sequence[str],
    robots: Sequence[str],
    seeds: int | range | None = None,
    contexts: Sequence[str] = ("given",),
) -> list[EpisodeSpec]:
    """The episodes of a named suite, once per social ``contexts`` entry (``given`` and/or
    ``detected``, see :func:`socialnav.sim.runner.run_episode`).

    - ``paper``: every scenario once (seed 0) and ``hallway_passing`` with seeds 0–4 (Table 1).
    - ``reactive``: the same runs with people driven by navground ``HL`` who react to the robot.
    - ``randomized``: seeded jitter of positions, speeds and group sizes; ``seeds`` (20) each.

    ``seeds``: a count N (seeds ``0 … N-1``) or a ``range`` (``--seeds A:B``).
    """
    specs: list[EpisodeSpec] = []
    chosen = range(seeds) if isinstance(seeds, int) else seeds
    for scenario in scenarios:
        if suite == "randomized":
            run_seeds: Iterable[int] = chosen or range(20)
        elif Path(scenario).stem == TABLE1_SCENARIO:
            run_seeds = TABLE1_SEEDS if chosen is None else chosen
        else:
            run_seeds = chosen or range(1)
        for planner in planners:
            for robot in robots:
                for seed, context in itertools.product(run_seeds, contexts):
                    specs.append(
                        EpisodeSpec(
                            scenario=scenario,
                            planner=planner,
                            robot=robot,
                            seed=seed,
                            humans="reactive" if suite == "reactive" else "scripted",
                            randomize=suite == "randomized",
                            context=context,
                        )
                    )
    return specs


# --- the generated suite ----------------------------------------------------------------------


def generated_specs(
    families: Sequence[str],
    planners: Sequence[str],
    robots: Sequence[str],
    seeds: Iterable[int],
    contexts: Sequence[str] = ("given",),
) -> list[EpisodeSpec]:
    """Every family × planner × robot × seed of the generated suite (``socialnav.sim.generate``;
    seeds below 10,000 are the development split, 10,000 and up the reporting split), once per
    social ``contexts`` entry (``given`` and/or ``detected``)."""
    seeds = list(seeds)
    return [
        EpisodeSpec(scenario=f"{GENERATED_PREFIX}{f}", planner=p, robot=r, seed=s, context=c)
        for f in families
        for p in planners
        for r in robots
        for s in seeds
        for c in contexts
    ]


def run_spec(
    spec: EpisodeSpec | CrowdSpec, out_dir: Path | None = None, figure: bool = False
) -> dict[str, Any]:
    """Run one episode; return its result row (metrics, success conditions, timing, error).

    Column names are those of the results dataset (:mod:`socialnav.experiments.results`);
    ``error`` is None when the episode ran. A :class:`CrowdSpec` runs as a crowd episode
    (:func:`socialnav.experiments.crowd.run_crowd_spec`).
    """
    if isinstance(spec, CrowdSpec):
        from socialnav.experiments.crowd import run_crowd_spec

        return run_crowd_spec(spec, out_dir, figure)
    from socialnav.experiments.results import condition_column, metric_column

    row: dict[str, Any] = {**asdict(spec), "run_id": spec.run_id, "error": None}
    started = time.perf_counter()
    try:
        from socialnav.experiments.planners import run_planner_episode
        from socialnav.metrics import measure_episode

        result = run_planner_episode(spec)
        record = result.record
        measured = measure_episode(record)
        row.update({metric_column(k): float(v) for k, v in measured.metrics.items()})
        # overall success is the metric ``success``: stored once
        conditions = {k: v for k, v in measured.passed().items() if k != "success"}
        row.update({condition_column(k): bool(v) for k, v in conditions.items()})
        judged = measured.conditions
        row["failed_required"] = ",".join(c.name for c in judged if c.required and not c.passed)
        row["not_required"] = not_required_text(judged)
        row["family"] = record.family
        row["steps"] = record.num_steps
        row["planner_ms_median"] = float(record.meta.get("planner_ms_median", np.nan))
        row["estimator_ms_median"] = float(record.meta.get("estimator_ms_median", np.nan))
        if out_dir is not None:
            from socialnav.experiments.storage import save_episode

            folder = save_episode(record, out_dir / "runs" / spec.run_id)
            if figure:
                from socialnav.viz.topdown import plot_episode, save_figure

                save_figure(plot_episode(record), folder / "topdown.png")
    except Exception as exc:  # an episode failure is data, not the end of the suite
        row["error"] = f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=4)}"
    row["wall_time_s"] = time.perf_counter() - started
    return row


def run_suite(
    specs: Sequence[EpisodeSpec | CrowdSpec],
    out_dir: Path,
    n_jobs: int = -1,
    figures: bool = False,
    resume: bool = True,
    progress: Callable[[int, int], None] | None = None,
    *,
    suite: str = "paper",
    backend: str = "local",
    address: str | None = None,
    notify: Callable[[str], None] | None = None,
) -> list[dict[str, Any]]:
    """Run ``specs`` on ``backend`` into ``out_dir``; returns the rows of ``specs``, old and new.

    Rows are stored under ``out_dir/results`` partitioned by ``suite``, planner and robot, each
    the moment its episode finishes. ``resume=False`` runs every spec again (the new rows replace
    the stored ones). ``notify`` receives one line per damaged file found and recovered from.
    """
    from socialnav.experiments.backends import map_unordered
    from socialnav.experiments.results import ResultStore

    out_dir.mkdir(parents=True, exist_ok=True)
    store = ResultStore(out_dir, notify)
    store.compact()  # fragments a killed run left become part of the dataset
    stored = {r["run_id"]: r for r in store.load() if r["suite"] == suite}
    done = {k for k, r in stored.items() if r.get("error") is None} if resume else set()
    todo = [s for s in specs if s.run_id not in done]
    total = len(todo)
    if progress:
        progress(0, total)
    new: dict[str, dict[str, Any]] = {}
    results = map_unordered(
        run_spec, todo, backend=backend, n_jobs=n_jobs, address=address, args=(out_dir, figures)
    )
    for finished, row in enumerate(results, start=1):
        row["suite"] = suite
        store.append(row)  # durable now: a kill from here on does not lose this episode
        new[row["run_id"]] = row
        if progress:
            progress(finished, total)
    store.compact()
    rows = [new.get(s.run_id) or stored[s.run_id] for s in specs]
    unique = {r["run_id"]: r for r in rows}
    return [unique[k] for k in sorted(unique)]

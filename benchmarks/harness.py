"""Tiny benchmark runner: median wall time over repeats, printed as a table with ratios.

Every benchmark script builds a list of :class:`Case` rows. Rows that share a ``group`` are
compared against the row of that group whose ``variant`` equals the group's ``baseline`` — measured
in the same run, on the same machine, so ratios stay meaningful when absolute times drift.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field


@dataclass
class Case:
    """One timed row: ``fn`` is called ``repeats`` times after ``warmup`` untimed calls."""

    group: str
    variant: str
    fn: Callable[[], object]
    repeats: int = 7
    warmup: int = 1
    baseline: str | None = None
    extra: dict[str, str] = field(default_factory=dict)


@dataclass
class Row:
    group: str
    variant: str
    median_s: float
    min_s: float
    repeats: int
    ratio: float | None
    extra: dict[str, str]


def time_case(case: Case) -> tuple[float, float]:
    """Median and minimum seconds of ``case.fn`` over ``case.repeats`` calls."""
    for _ in range(case.warmup):
        case.fn()
    samples = []
    for _ in range(case.repeats):
        start = time.perf_counter()
        case.fn()
        samples.append(time.perf_counter() - start)
    return statistics.median(samples), min(samples)


def format_seconds(seconds: float) -> str:
    if seconds < 1e-3:
        return f"{seconds * 1e6:.1f} µs"
    if seconds < 1.0:
        return f"{seconds * 1e3:.2f} ms"
    return f"{seconds:.2f} s"


def run_table(cases: Sequence[Case], title: str = "") -> list[Row]:
    """Time every case and print one table.

    ``ratio`` = baseline median / this median, so a value above 1 means faster than the baseline.
    """
    medians: dict[tuple[str, str], float] = {}
    rows: list[Row] = []
    for case in cases:
        median, best = time_case(case)
        medians[(case.group, case.variant)] = median
        rows.append(Row(case.group, case.variant, median, best, case.repeats, None, case.extra))
    for row, case in zip(rows, cases, strict=True):
        if case.baseline is not None and (case.group, case.baseline) in medians:
            row.ratio = medians[(case.group, case.baseline)] / row.median_s
    print_rows(rows, title)
    return rows


def print_rows(rows: Sequence[Row], title: str = "") -> None:
    extra_keys = sorted({k for r in rows for k in r.extra})
    header = ["group", "variant", *extra_keys, "median", "min", "n", "speed-up vs baseline"]
    body = [
        [
            r.group,
            r.variant,
            *[r.extra.get(k, "") for k in extra_keys],
            format_seconds(r.median_s),
            format_seconds(r.min_s),
            str(r.repeats),
            "" if r.ratio is None else f"{r.ratio:.1f}x" if r.ratio >= 0.1 else f"{r.ratio:.2g}x",
        ]
        for r in rows
    ]
    widths = [max([len(h)] + [len(b[i]) for b in body]) for i, h in enumerate(header)]
    if title:
        print(f"\n## {title}\n")
    print("| " + " | ".join(h.ljust(w) for h, w in zip(header, widths, strict=True)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for b in body:
        print("| " + " | ".join(c.ljust(w) for c, w in zip(b, widths, strict=True)) + " |")


def time_interleaved(
    fns: Sequence[Callable[[], object]], repeats: int, warmup: int = 1
) -> list[tuple[float, float, float]]:
    """(wall median, wall min, CPU-time median) seconds per function, calls interleaved round
    by round so that load changes hit every function alike. On a loaded machine the thread's
    CPU time (``time.thread_time``) excludes the time spent waiting for a core."""
    for _ in range(warmup):
        for fn in fns:
            fn()
    wall: list[list[float]] = [[] for _ in fns]
    cpu: list[list[float]] = [[] for _ in fns]
    for _ in range(repeats):
        for i, fn in enumerate(fns):
            c0, w0 = time.thread_time(), time.perf_counter()
            fn()
            wall[i].append(time.perf_counter() - w0)
            cpu[i].append(time.thread_time() - c0)
    return [
        (statistics.median(w), min(w), statistics.median(c)) for w, c in zip(wall, cpu, strict=True)
    ]


def development_seeds(text: str, why: str) -> range:
    """The seeds ``A:B`` (or ``N`` for ``0:N``) of ``text``; exits naming ``why`` when any is a
    reporting seed (tuning and diagnosis stay on the development split)."""
    from socialnav.experiments.crowd import parse_seeds
    from socialnav.sim.generate import REPORTING_SEED

    seeds = parse_seeds(text)
    if seeds.stop > REPORTING_SEED:
        raise SystemExit(f"{why} runs on development seeds only (< {REPORTING_SEED})")
    return seeds


def machine_note() -> str:
    """``"<cores> cores, load average <1 min>"``: the conditions a table was measured in (the
    load average is sampled when the table starts; timings drift with it)."""
    import os

    cores = os.cpu_count() or 0
    try:
        load = f"{os.getloadavg()[0]:.1f}"
    except OSError:  # not available on this platform
        load = "unknown"
    return f"{cores} cores, load average {load}"


def quick_option(doc: str | None) -> bool:
    """Parse ``[--quick]`` (fewer repeats) with ``--help`` printing the script's docstring."""
    parser = argparse.ArgumentParser(
        description=doc, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--quick", action="store_true", help="fewer repeats (a rough table)")
    return bool(parser.parse_args().quick)

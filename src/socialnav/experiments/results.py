"""Suite results as a Parquet dataset that a kill cannot damage and SQL can read.

Layout (Hive partitioning, what DuckDB, pandas, Polars and ``pyarrow.dataset`` read as one table)::

    RESULTS_DIR/results/suite=<suite>/planner=<planner>/robot=<robot>/part-0.parquet
    RESULTS_DIR/results/suite=<suite>/planner=<planner>/robot=<robot>/ep-<run_id>.parquet

Every finished episode is written at once as its own one-row ``ep-*.parquet`` fragment (temporary
file, ``fsync``, ``os.replace``), so a run killed at any moment loses only the episodes in flight.
:meth:`ResultStore.compact` merges a partition's fragments into ``part-0.parquet`` the same atomic
way; a kill between the merge and the removal of the fragments leaves a row in both, which every
read here deduplicates (and the next compaction removes). A file that cannot be read (cut short by
a kill before this layout, or damaged on disk) is reported, moved to ``results/_damaged/`` and its
episodes run again: never an ``ArrowInvalid`` traceback.

Columns: the episode's spec (``scenario``, ``seed``, ``humans``, ``randomize``, …) with ``suite``,
``planner`` and ``robot`` in the path only; ``family`` and ``steps``; one ``float64`` column per
registered metric (``psc_1.2`` is column ``psc_1_2``: names need no quoting in SQL) whose field
metadata holds its ``unit``, ``direction`` (``min``: lower is better) and ``description`` (also
in the file's key-value metadata ``socialnav_columns``, a JSON object by column); one
boolean ``ok_<condition>`` per success condition of the family (overall success is the metric
``success``, stored once); ``error`` (null when the episode ran) and the timing columns
``wall_time_s``, ``planner_ms_median`` and ``estimator_ms_median``, which are the only ones that
differ between two runs of the same spec. Crowd rows (``--suite crowds``) hold the recording
``data`` (the path given), its ``data_sha256`` (which file that was: the first 16 hex digits
of its SHA-256), ``switch_distance`` and ``context`` in place of the scenario spec, the
episode's ``t0``, ``flow``,
``people_near`` and ``people_total``, and the timings ``planner_ms_p95`` and
``planner_ms_steps`` (every cycle, so a report pools percentiles over steps).
"""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
from collections import defaultdict
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

DATASET_DIR = "results"
DAMAGED_DIR = "_damaged"
PART_FILE = "part-0.parquet"
FRAGMENT_PREFIX = "ep-"
PARTITION_KEYS = ("suite", "planner", "robot")
CONDITION_PREFIX = "ok_"
TIMING_COLUMNS = ("wall_time_s", "planner_ms_median", "estimator_ms_median")
#: the crowd suite's further timing columns (``socialnav.experiments.crowd``)
CROWD_TIMING_COLUMNS = ("planner_ms_p95", "planner_ms_steps")
_TIMING_META = {
    "wall_time_s": ("s", "min", "Wall-clock time of the whole episode on its worker."),
    "planner_ms_median": ("ms", "min", "Median time of one planning cycle (our planners only)."),
    "estimator_ms_median": ("ms", "min", "Median time of one context estimate (detected only)."),
    "planner_ms_p95": ("ms", "min", "95th percentile of the planning cycle (crowd suite)."),
}
LEGACY_FILE = "results.parquet"
COLUMNS_KEY = "socialnav_columns"


def metric_column(name: str) -> str:
    """The column of metric ``name``: dots become underscores (``psc_1.2`` → ``psc_1_2``)."""
    return name.replace(".", "_")


def condition_column(name: str) -> str:
    """The column of success condition ``name`` (``reached_goal`` → ``ok_reached_goal``)."""
    return CONDITION_PREFIX + name.replace(".", "_")


def _metric_fields() -> dict[str, pa.Field]:
    from socialnav.metrics import METRICS

    fields = {}
    for name in METRICS.names():
        m = METRICS.get(name)
        description = m.doc.split("\n\n", 1)[0].replace("\n", " ")
        meta = {"unit": m.unit, "direction": m.direction, "description": description}
        meta["metric"] = name
        meta["reference"] = m.reference
        column = metric_column(name)
        fields[column] = pa.field(column, pa.float64(), metadata=meta)
    return fields


def _field(name: str, values: list[Any], metrics: dict[str, pa.Field]) -> pa.Field:
    if name in metrics:
        return metrics[name]
    if name in _TIMING_META:
        unit, direction, text = _TIMING_META[name]
        meta = {"unit": unit, "direction": direction, "description": text, "timing": "true"}
        return pa.field(name, pa.float64(), metadata=meta)
    if name == "planner_ms_steps":  # a list per episode; typed, so empty lists unify
        meta = {"unit": "ms", "description": "every planning cycle's time", "timing": "true"}
        return pa.field(name, pa.list_(pa.float64()), metadata=meta)
    if name == "error":
        return pa.field(name, pa.string(), metadata={"description": "null when the episode ran"})
    if name.startswith(CONDITION_PREFIX):
        meta = {"unit": "1", "direction": "max", "description": "success condition passed"}
        return pa.field(name, pa.bool_(), metadata=meta)
    kind = pa.array(values).type
    return pa.field(name, pa.string() if pa.types.is_null(kind) else kind)


def rows_to_table(rows: Sequence[dict[str, Any]]) -> pa.Table:
    """A table of result rows (without the partition columns) with the typed, documented schema."""
    metrics = _metric_fields()
    keys = {k for r in rows for k in r if k not in PARTITION_KEYS and k != "run_id"}
    first = [k for k in ("scenario", "seed", "humans", "randomize", "family", "steps") if k in keys]
    ordered = [
        *first,
        *sorted(k for k in keys if k not in first and k not in metrics and k != "error"),
        *[k for k in metrics if k in keys],
        *(["error"] if "error" in keys else []),
    ]
    columns = {k: [r.get(k) for r in rows] for k in ordered}
    fields = [_field(k, columns[k], metrics) for k in ordered]
    # the same documentation once more at file level: SQL engines show key-value metadata
    # (DuckDB's parquet_kv_metadata) but not Arrow field metadata
    documented = {
        f.name: {k.decode(): v.decode() for k, v in f.metadata.items()}
        for f in fields
        if f.metadata
    }
    schema = pa.schema(fields, metadata={COLUMNS_KEY: json.dumps(documented)})
    return pa.Table.from_pydict(columns, schema=schema)


def _write_atomic(table: pa.Table, path: Path) -> None:
    """Write ``table`` to ``path`` so that a reader sees the old file or the whole new one."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    pq.write_table(table, tmp)
    with open(tmp, "rb") as handle:
        os.fsync(handle.fileno())
    os.replace(tmp, path)


def _run_id(row: dict[str, Any]) -> str:
    """The run id of a stored row, rebuilt from its spec columns (a crowd row has ``data``)."""
    from socialnav.experiments.crowd import CrowdSpec
    from socialnav.experiments.suite import EpisodeSpec

    kind: type[EpisodeSpec] | type[CrowdSpec] = CrowdSpec if "data" in row else EpisodeSpec
    names = {f.name for f in dataclasses.fields(kind)}
    # a column added later reads as null in older rows: the field's default then applies
    return kind(**{k: v for k, v in row.items() if k in names and v is not None}).run_id


class ResultStore:
    """The results dataset of one results folder (see the module docstring for the layout).

    ``notify`` receives one line per problem found (a damaged file and what was done about it).
    """

    def __init__(self, out_dir: Path, notify: Callable[[str], None] | None = None) -> None:
        self.out_dir = Path(out_dir)
        self.root = self.out_dir / DATASET_DIR
        self.notify = notify or (lambda message: None)

    def _partition(self, row: dict[str, Any]) -> Path:
        return self.root.joinpath(*[f"{k}={row[k]}" for k in PARTITION_KEYS])

    def append(self, row: dict[str, Any]) -> Path:
        """Write one finished episode durably as its own fragment; returns the fragment path."""
        folder = self._partition(row)
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{FRAGMENT_PREFIX}{row.get('run_id') or _run_id(row)}.parquet"
        _write_atomic(rows_to_table([row]), path)
        return path

    def _files(self) -> list[Path]:
        if not self.root.exists():
            return []
        return sorted(
            p
            for p in self.root.rglob("*.parquet")
            if DAMAGED_DIR not in p.relative_to(self.root).parts
        )

    def _read(self, path: Path) -> list[dict[str, Any]] | None:
        """The rows of one file with partition values and ``run_id``, or None when damaged."""
        try:
            rows = pq.read_table(path).to_pylist()
        except (pa.ArrowException, OSError) as exc:
            target = self.root / DAMAGED_DIR / path.relative_to(self.root)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.move(path, target)
            self.notify(
                f"damaged results file {path} ({type(exc).__name__}: {exc}); moved to {target}; "
                "its episodes will run again"
            )
            return None
        parts = dict(p.split("=", 1) for p in path.relative_to(self.root).parent.parts)
        for row in rows:
            row.update({k: parts[k] for k in PARTITION_KEYS})
            row["run_id"] = _run_id(row)
        return rows

    def _clean_temporaries(self) -> None:
        if self.root.exists():
            for tmp in self.root.rglob(".*.tmp"):
                tmp.unlink(missing_ok=True)  # a write a kill interrupted: never visible as data

    def load(self) -> list[dict[str, Any]]:
        """Every row, one per (suite, run id) — a fragment wins over the compacted part."""
        self._clean_temporaries()
        legacy = self.out_dir / LEGACY_FILE
        if legacy.exists():
            self.notify(f"{legacy} is the old single-file format and is not read; see {self.root}")
        rows: dict[tuple[str, str], dict[str, Any]] = {}
        for path in sorted(self._files(), key=lambda p: p.name != PART_FILE):
            for row in self._read(path) or []:
                rows[(row["suite"], row["run_id"])] = row
        return sorted(rows.values(), key=lambda r: (r["suite"], r["run_id"]))

    def compact(self) -> None:
        """Merge each partition's fragments into its ``part-0.parquet`` (atomically)."""
        self._clean_temporaries()
        by_folder: dict[Path, list[Path]] = defaultdict(list)
        for path in self._files():
            by_folder[path.parent].append(path)
        for folder, files in by_folder.items():
            fragments = [p for p in files if p.name.startswith(FRAGMENT_PREFIX)]
            if not fragments:
                continue
            merged: dict[str, dict[str, Any]] = {}
            for path in sorted(files, key=lambda p: p.name != PART_FILE):
                for row in self._read(path) or []:
                    merged[row["run_id"]] = row
            ordered = [merged[k] for k in sorted(merged)]
            _write_atomic(rows_to_table(ordered), folder / PART_FILE)
            for path in fragments:
                path.unlink(missing_ok=True)

    def schema(self) -> pa.Schema:
        """The unified schema of every readable file (partition columns not included)."""
        return pa.unify_schemas([pq.read_schema(p) for p in self._files()])


def load_results(
    out_dir: Path, suite: str | None = None, notify: Callable[[str], None] | None = None
) -> list[dict[str, Any]]:
    """The rows stored under ``out_dir`` (of one ``suite`` if given), sorted by run id."""
    rows = ResultStore(out_dir, notify).load()
    return [r for r in rows if suite is None or r["suite"] == suite]


def suites_in(rows: Iterable[dict[str, Any]]) -> list[str]:
    """The suites present in ``rows``, sorted."""
    return sorted({r["suite"] for r in rows})

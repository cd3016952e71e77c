"""The results dataset: partitioned, documented, queryable, the same on every backend, and safe
against a kill at any moment."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.dataset as ds
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from socialnav.cli import app
from socialnav.experiments.results import (
    DAMAGED_DIR,
    PART_FILE,
    TIMING_COLUMNS,
    ResultStore,
    load_results,
)
from socialnav.experiments.suite import run_suite, suite_specs
from socialnav.metrics import METRICS

# navground's HL and ORCA drive the robot: a few hundredths of a second per episode
SPECS = suite_specs("randomized", ["hallway_passing"], ["hl", "orca"], ["pr2"], 3)


def comparable(rows: list[dict]) -> list[dict]:
    """Rows without their timing columns, NaN made comparable."""
    return [
        {
            k: ("nan" if isinstance(v, float) and math.isnan(v) else v)
            for k, v in r.items()
            if k not in TIMING_COLUMNS
        }
        for r in rows
    ]


@pytest.fixture(scope="module")
def local(tmp_path_factory) -> tuple[Path, list[dict]]:
    out = tmp_path_factory.mktemp("local")
    rows = run_suite(SPECS, out, n_jobs=2, suite="randomized")
    return out, rows


# --- layout, schema, metadata ---------------------------------------------------------------------


def test_dataset_is_partitioned_by_suite_planner_and_robot(local) -> None:
    out, rows = local
    files = sorted(p.relative_to(out).as_posix() for p in (out / "results").rglob("*.parquet"))
    assert files == [
        f"results/suite=randomized/planner={p}/robot=pr2/{PART_FILE}" for p in ("hl", "orca")
    ]
    table = ds.dataset(out / "results", partitioning="hive").to_table()
    assert table.num_rows == len(SPECS) == len(rows)
    assert sorted(set(table["planner"].to_pylist())) == ["hl", "orca"]


def test_columns_are_sql_names_and_metrics_carry_unit_direction_description(local) -> None:
    out, _ = local
    schema = ResultStore(out).schema()
    assert all(name.isidentifier() and name.islower() for name in schema.names)
    assert "psc_1_2" in schema.names and "psc_1.2" not in schema.names
    for name in METRICS.names():
        field = schema.field(name.replace(".", "_"))
        meta = {k.decode(): v.decode() for k, v in field.metadata.items()}
        metric = METRICS.get(name)
        assert meta["unit"] == metric.unit and meta["direction"] == metric.direction
        assert meta["description"] and meta["description"] in metric.doc.replace("\n", " ")
    for name in TIMING_COLUMNS:
        assert schema.field(name).metadata[b"timing"] == b"true"


def test_no_quantity_is_stored_twice_and_error_is_null(local) -> None:
    out, _ = local
    table = pq.read_table(next((out / "results").rglob(PART_FILE)))
    # success is the metric; the run id, suite, planner and robot are in the spec and the path
    for twice in ("ok_success", "run_id", "suite", "planner", "robot"):
        assert twice not in table.column_names
    assert table["error"].null_count == table.num_rows


def test_duckdb_reads_the_dataset_as_one_table(local) -> None:
    duckdb = pytest.importorskip("duckdb")
    out, rows = local
    glob = (out / "results" / "**" / "*.parquet").as_posix()
    got = duckdb.sql(
        f"SELECT planner, count(*) AS n, avg(min_distance_center) AS d "
        f"FROM read_parquet('{glob}', hive_partitioning = true, union_by_name = true) "
        f"WHERE error IS NULL GROUP BY planner ORDER BY planner"
    ).fetchall()
    for planner, n, d in got:
        mine = [r["min_distance_center"] for r in rows if r["planner"] == planner]
        assert n == len(mine) and d == pytest.approx(sum(mine) / len(mine))


# --- backends -------------------------------------------------------------------------------------


def test_dask_cluster_gives_the_same_rows(local, tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    _, rows = local
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        got = run_suite(
            SPECS, tmp_path, suite="randomized", backend="dask", address=cluster.scheduler_address
        )
    assert comparable(got) == comparable(rows)
    assert comparable(load_results(tmp_path)) == comparable(load_results(local[0]))


def test_the_crowd_suite_gives_the_same_rows_on_dask(tmp_path: Path) -> None:
    """Crowd runs go through the same backends and dataset (the reference controller: fast)."""
    pytest.importorskip("distributed")
    from shared import crowd_data
    from socialnav.experiments.crowd import crowd_specs
    from socialnav.experiments.results import CROWD_TIMING_COLUMNS

    hotel = str(crowd_data("eth_hotel_obsmat.txt"))
    specs = crowd_specs([hotel], ["straight_line"], ["pr2"], range(10000, 10002))
    local = run_suite(specs, tmp_path / "local", n_jobs=1, suite="crowds")
    dask = run_suite(specs, tmp_path / "dask", n_jobs=2, suite="crowds", backend="dask")

    def strip(rows: list[dict]) -> list[dict]:
        return comparable(
            [{k: v for k, v in r.items() if k not in CROWD_TIMING_COLUMNS} for r in rows]
        )

    assert [r["run_id"] for r in local] == sorted(s.run_id for s in specs)
    assert all(r["error"] is None and r["suite"] == "crowds" for r in local)
    assert strip(dask) == strip(local)
    assert strip(load_results(tmp_path / "local")) == strip(local)


def test_ray_cluster_gives_the_same_rows(local, tmp_path: Path) -> None:
    pytest.importorskip("ray")
    _, rows = local
    got = run_suite(SPECS, tmp_path, n_jobs=2, suite="randomized", backend="ray")
    assert comparable(got) == comparable(rows)


def test_cli_rejects_an_unknown_backend_and_an_address_without_a_cluster(tmp_path: Path) -> None:
    result = CliRunner().invoke(app, ["compare", "--backend", "spark", "--out", str(tmp_path)])
    assert result.exit_code != 0 and "'spark'" in result.stderr
    result = CliRunner().invoke(app, ["compare", "--address", "auto", "--out", str(tmp_path)])
    assert result.exit_code != 0 and "--backend dask|ray" in result.stderr


# --- resume, damage, kill -------------------------------------------------------------------------


def test_a_damaged_results_file_is_reported_and_its_runs_run_again(local, tmp_path: Path) -> None:
    _, rows = local
    run_suite(SPECS, tmp_path, suite="randomized")
    part = tmp_path / "results" / "suite=randomized" / "planner=orca" / "robot=pr2" / PART_FILE
    part.write_bytes(part.read_bytes()[:200])  # cut short, as by a kill mid-write
    notes: list[str] = []
    again = run_suite(SPECS, tmp_path, suite="randomized", notify=notes.append)
    assert len(notes) == 1 and "damaged" in notes[0] and str(part) in notes[0]
    assert (tmp_path / "results" / DAMAGED_DIR).exists()
    assert comparable(again) == comparable(rows)
    assert len(load_results(tmp_path)) == len(SPECS)


def test_report_rebuilds_from_stored_results(local) -> None:
    out, rows = local
    (out / "report.md").unlink(missing_ok=True)
    result = CliRunner().invoke(app, ["report", str(out)])
    assert result.exit_code == 0, result.output
    assert f"{len(rows)} runs (0 errors)" in result.stdout
    text = (out / "report.md").read_text()
    assert "suite `randomized`" in text and "hl" in text
    result = CliRunner().invoke(app, ["report", str(out), "--suite", "paper"])
    assert result.exit_code != 0 and "randomized" in result.stderr


def _fragments(out: Path) -> list[Path]:
    return sorted((out / "results").rglob("ep-*.parquet")) if (out / "results").exists() else []


def test_a_killed_run_loses_only_episodes_in_flight_and_resumes(tmp_path: Path) -> None:
    script = Path(sys.executable).with_name("socialnav")
    args = [
        str(script),
        "compare",
        "--suite",
        "randomized",
        "--scenarios",
        "hallway_passing",
        "--planners",
        "hl",
        "--robots",
        "pr2",
        "--seeds",
        "40",
        "--jobs",
        "1",
        "--out",
        str(tmp_path),
    ]
    proc = subprocess.Popen(
        args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True
    )
    try:
        deadline = time.monotonic() + 120
        while len(_fragments(tmp_path)) < 3 and time.monotonic() < deadline:
            assert proc.poll() is None, "the suite ended before it could be killed"
            time.sleep(0.02)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)  # the CLI and its worker processes
        proc.wait()
    notes: list[str] = []
    survived = load_results(tmp_path, notify=notes.append)
    assert notes == []  # nothing half-written is visible
    assert 3 <= len(survived) < 40
    stamps = {r["run_id"]: r["wall_time_s"] for r in survived}
    rows = run_suite(
        suite_specs("randomized", ["hallway_passing"], ["hl"], ["pr2"], 40),
        tmp_path,
        suite="randomized",
    )
    stored = load_results(tmp_path)
    assert len(rows) == len(stored) == 40
    assert len({r["run_id"] for r in stored}) == 40
    assert all(r["error"] is None for r in stored)
    # what finished before the kill was kept, not run again
    assert {r["run_id"]: r["wall_time_s"] for r in stored if r["run_id"] in stamps} == stamps
    assert _fragments(tmp_path) == []


def test_sql_engines_see_the_column_documentation_too(local) -> None:
    duckdb = pytest.importorskip("duckdb")
    out, _ = local
    path = next((out / "results").rglob(PART_FILE)).as_posix()
    ((value,),) = duckdb.sql(
        f"SELECT value FROM parquet_kv_metadata('{path}') WHERE key = 'socialnav_columns'"
    ).fetchall()
    documented = json.loads(value.decode() if isinstance(value, bytes) else value)
    assert documented["psc_1_2"]["unit"] == "1" and documented["psc_1_2"]["direction"] == "max"
    assert documented["time_to_goal"]["unit"] == "s"

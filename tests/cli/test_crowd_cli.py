"""The crowd suite end to end through the CLI (a small slice: one reporting seed), and
``socialnav run --crowd``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from shared import crowd_data, md_tables
from socialnav.cli import app
from socialnav.core.errors import ConfigurationError
from socialnav.experiments.crowd import crowd_specs, parse_seeds


def invoke(*args: str):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_parse_seeds() -> None:
    assert parse_seeds("3") == range(0, 3)
    assert parse_seeds("10000:10050") == range(10000, 10050)
    for bad in ("a", "5:5", "7:3", "-1:2"):
        with pytest.raises(ConfigurationError, match="seeds"):
            parse_seeds(bad)


def test_every_crowd_suite_runs_the_straight_line_reference() -> None:
    specs = crowd_specs(["a.txt", "b.txt"], ["paccet", "orca"], ["pr2"], range(2))
    assert [s.planner for s in specs[::4]] == ["paccet", "straight_line", "orca"]
    assert len({s.run_id for s in specs}) == len(specs) == 12


def test_compare_crowds_slice(tmp_path: Path) -> None:
    hotel = crowd_data("eth_hotel_obsmat.txt")
    out = tmp_path / "report"
    result = invoke(
        "compare",
        "--suite",
        "crowds",
        "--data",
        hotel,
        "--seeds",
        "10000:10001",
        "--planners",
        "paccet",
        "--robots",
        "pr2",
        "--jobs",
        "1",
        "--out",
        out,
    )
    assert result.exit_code == 0, result.output
    assert "2 runs (0 errors)" in result.output
    text = (out / "report.md").read_text()
    assert "## Recording eth_hotel" in text
    table = next(t for t in md_tables(text) if t[0][0] == "planner")
    assert [row[0] for row in table[1:]] == ["paccet", "straight_line"]
    assert all(len(row) == len(table[0]) for row in table)
    assert "`paccet` on pr2: met" in text
    assert (out / "figures" / "crowd_eth_hotel.png").stat().st_size > 10_000


def test_compare_crowds_needs_data_and_names_bad_files(tmp_path: Path) -> None:
    result = invoke("compare", "--suite", "crowds", "--out", tmp_path)
    assert result.exit_code == 2 and "--data" in result.output
    bad = tmp_path / "bad_obsmat.txt"
    bad.write_text("1 1 0 0 0 0 0 0\n2 1 0 0 zz 0 0 0\n")
    result = invoke("compare", "--suite", "crowds", "--data", bad, "--out", tmp_path / "r")
    assert result.exit_code == 2
    assert "bad_obsmat.txt: line 2: column 5 (y)" in " ".join(result.output.split())


def test_run_crowd_writes_every_file(tmp_path: Path) -> None:
    zara = crowd_data("ucy_zara01_obsmat.txt")
    out = tmp_path / "run"
    result = invoke(
        "run",
        "--crowd",
        zara,
        "--t0",
        "33.2",
        "--start",
        "-1.90",
        "6.41",
        "--goal",
        "-4.25",
        "16.78",
        "--planner",
        "straight_line",
        "--out",
        out,
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    assert summary["people"] > 5
    metrics = json.loads((out / "metrics.json").read_text())
    assert {"collisions_active", "time_within_1.2", "success_conditions"} <= metrics.keys()
    assert (out / "trajectory.parquet").is_file() and (out / "topdown.png").is_file()
    result = invoke("run", "--crowd", zara, "--out", out)
    assert result.exit_code == 2 and "--start" in result.output

"""``socialnav compare`` end to end on a tiny suite: report, figures, results table, resume."""

from __future__ import annotations

import base64
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from shared import TABLE1_KEYS, html_tables, md_tables
from socialnav.cli import app
from socialnav.experiments.results import load_results
from socialnav.experiments.suite import EpisodeSpec, run_suite, suite_specs

ARGS = [
    "compare",
    "--scenarios",
    "hallway_passing",
    "--planners",
    "traditional,paccet",
    "--robots",
    "pr2",
    "--seeds",
    "1",
    "--jobs",
    "1",
]
RUN_IDS = [
    "hallway_passing__paccet__pr2__scripted__s0",
    "hallway_passing__traditional__pr2__scripted__s0",
]


@pytest.fixture(scope="module")
def report_dir(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("report")
    result = CliRunner().invoke(app, [*ARGS, "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "2 runs (0 errors)" in result.stdout
    return out


def results(out: Path) -> list[dict]:
    return load_results(out)


def same(a: object, b: object) -> bool:
    """Equality with NaN equal to NaN (result cells are floats, bools, ints and strings)."""
    if isinstance(a, float) and isinstance(b, float) and np.isnan(a) and np.isnan(b):
        return True
    return a == b


def table1(out: Path) -> list[list[str]]:
    text = (out / "report.md").read_text()
    section = text.split("## Table 1 reproduction", 1)[1].split("\n## ", 1)[0]
    return md_tables(section)[0]


# --- the results dataset --------------------------------------------------------------------------


def test_results_has_one_row_per_run_with_metrics_and_conditions(report_dir: Path) -> None:
    rows = results(report_dir)
    assert [r["run_id"] for r in rows] == RUN_IDS
    assert [r["error"] for r in rows] == [None, None]
    for row in rows:
        assert row["scenario"] == "hallway_passing" and row["robot"] == "pr2"
        assert row["seed"] == 0 and row["family"] == "hallway" and row["suite"] == "paper"
        for key in TABLE1_KEYS:
            assert key in row
        assert {"ok_reached_goal", "ok_no_collision", "success", "psc_1_2"} <= set(row)
        assert "ok_success" not in row  # stored once, as the metric ``success``
        assert all(isinstance(row[k], bool) for k in row if k.startswith("ok_"))
        assert row["ok_reached_goal"] and row["ok_no_collision"]
        assert np.isfinite(row["total_distance"]) and row["steps"] > 10
        assert (report_dir / "runs" / row["run_id"] / "trajectory.parquet").exists()
    by_planner = {r["planner"]: r for r in rows}
    assert by_planner["paccet"]["success"] == 1.0 and by_planner["traditional"]["success"] == 0


# --- the report -----------------------------------------------------------------------------------


def test_report_has_table1_with_the_papers_values_and_ours(report_dir: Path) -> None:
    for name in ("report.md", "report.html"):
        assert "Table 1 reproduction" in (report_dir / name).read_text()
    rows = {r[0]: r[1:] for r in table1(report_dir)}
    assert rows["planner"] == ["runs", "D_t (m)", "t (s)", "D_l (m)", "N (sum of 5)", "D_d (m)"]
    assert rows["traditional (paper)"] == ["5", "5.04", "13.20", "0.90", "5", "n/a"]
    assert rows["IRL (paper)"] == ["5", "5.21", "15.94", "1.01", "0", "1.80"]
    assert rows["PaCcET (paper)"] == ["5", "5.34", "14.36", "1.39", "0", "1.50"]
    for row in results(report_dir):
        ours = rows[row["planner"]]
        assert ours[0] == "1"
        for cell, key in zip(ours[1:], TABLE1_KEYS, strict=True):
            value = row[key]
            expected = str(int(value)) if key == "proxemic_intrusions" else f"{value:.2f}"
            assert cell == expected, key


def test_report_markdown_and_html_show_the_same_tables(report_dir: Path) -> None:
    md = md_tables((report_dir / "report.md").read_text())
    page = html_tables((report_dir / "report.html").read_text())
    assert len(md) == len(page) >= 4
    strip = [[[c.replace("**", "").replace("`", "") for c in r] for r in t] for t in md]
    assert strip == page


def test_figures_referenced_by_the_report_exist(report_dir: Path) -> None:
    md = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", (report_dir / "report.md").read_text())
    assert "figures/hallway_passing__pr2.png" in md
    assert "figures/tradeoff.png" in md
    for ref in md:
        path = report_dir / ref
        assert path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", ref
    assert "## Errors" not in (report_dir / "report.md").read_text()


def test_report_html_is_one_self_contained_file(report_dir: Path) -> None:
    page = (report_dir / "report.html").read_text()
    sources = re.findall(r"<img src='([^']+)'", page)
    md = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", (report_dir / "report.md").read_text())
    assert len(sources) == len(md) >= 2
    for source, ref in zip(sources, md, strict=True):
        assert source.startswith("data:image/png;base64,")
        assert base64.b64decode(source.split(",", 1)[1]) == (report_dir / ref).read_bytes()
    assert not re.search(r"(src|href)='(?!data:)", page)  # nothing else to fetch


# --- resume and workers ---------------------------------------------------------------------------


def test_rerun_resumes_without_running_again(report_dir: Path) -> None:
    before = results(report_dir)
    runs = sorted((report_dir / "runs").rglob("*"))
    stamps = {p: p.stat().st_mtime_ns for p in runs}
    result = CliRunner().invoke(app, [*ARGS, "--out", str(report_dir)])
    assert result.exit_code == 0, result.output
    after = results(report_dir)
    # the same rows, wall times included: nothing ran again
    assert [sorted(r) for r in after] == [sorted(r) for r in before]
    for a, b in zip(after, before, strict=True):
        assert all(same(a[k], b[k]) for k in a), a["run_id"]
    assert sorted((report_dir / "runs").rglob("*")) == runs
    assert {p: p.stat().st_mtime_ns for p in runs} == stamps
    assert "2 runs (0 errors)" in result.stdout


def test_results_do_not_depend_on_the_number_of_workers(report_dir: Path, tmp_path: Path) -> None:
    specs = suite_specs("paper", ["hallway_passing"], ["traditional", "paccet"], ["pr2"], 1)
    assert specs == [
        EpisodeSpec("hallway_passing", "traditional", "pr2", 0),
        EpisodeSpec("hallway_passing", "paccet", "pr2", 0),
    ]
    parallel = run_suite(specs, tmp_path, n_jobs=2)
    serial = results(report_dir)
    assert [r["run_id"] for r in parallel] == RUN_IDS
    for a, b in zip(parallel, serial, strict=True):
        for key in a:
            if key not in ("wall_time_s", "planner_ms_median"):
                assert same(a[key], b[key]), key

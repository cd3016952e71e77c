"""The project's front door: the README's two commands and CI stay in step."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def quick_start_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    section = text.split("## Quick start", 1)[1]
    block = re.search(r"```bash\n(.*?)```", section, re.S)
    assert block, "the quick start needs a bash code block"
    return [line for line in block.group(1).splitlines() if line.strip()]


def test_quick_start_is_two_commands_main_job_then_tests() -> None:
    commands = quick_start_commands()
    assert len(commands) == 2
    assert "socialnav compare" in commands[0]
    assert "pytest" in commands[1]


def test_ci_runs_the_readme_test_command() -> None:
    ci = (ROOT / ".ci" / "run").read_text()
    assert quick_start_commands()[1] in ci


def test_no_machine_specific_paths_in_sources() -> None:
    pattern = re.compile(r"/(work|root|home/[a-z]+)/")
    offenders = [
        str(path.relative_to(ROOT))
        for folder in ("src", "tests", "benchmarks")
        for path in (ROOT / folder).rglob("*")
        if path.suffix in {".py", ".yaml", ".md", ".toml"} and pattern.search(path.read_text())
    ]
    assert offenders == []


def test_no_merge_conflict_markers_in_tracked_text() -> None:
    # a marker line is exactly 7 of <, = or > (then a space and a name for < and >);
    # reStructuredText tables use longer runs of =, so they never match
    marker = re.compile(r"^(<{7} |={7}$|>{7} )", re.M)
    offenders = [
        str(path.relative_to(ROOT))
        for path in [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "CONTRIBUTING.md"]
        + [
            p
            for folder in ("src", "tests", "benchmarks", "docs", "examples", ".ci")
            if (ROOT / folder).is_dir()
            for p in (ROOT / folder).rglob("*")
            if p.is_file() and p.suffix in {".py", ".yaml", ".md", ".toml", ""}
        ]
        if path.is_file() and marker.search(path.read_text(errors="replace"))
    ]
    assert offenders == []


def test_readme_python_example_runs_and_plans_a_move() -> None:
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks, "the README shows how to use the planner in a control loop"
    namespace: dict[str, object] = {}
    exec(compile(blocks[0], "README.md", "exec"), namespace)
    result = namespace["result"]
    assert str(result.status.value) == "OK"
    assert result.cmd[0] > 0  # the robot starts moving toward the goal


def test_readme_duckdb_query_runs_on_stored_results(tmp_path, monkeypatch) -> None:
    pytest.importorskip("duckdb")
    from socialnav.experiments.suite import run_suite, suite_specs

    text = (ROOT / "README.md").read_text()
    (block,) = [b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "duckdb" in b]
    specs = suite_specs("paper", ["hallway_passing"], ["hl", "orca"], ["pr2"], 1)
    run_suite(specs, tmp_path / "report", n_jobs=1, suite="paper")
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {}
    exec(compile(block.replace("print(", "result = ("), "README.md", "exec"), namespace)
    rows = namespace["result"].fetchall()  # type: ignore[attr-defined]
    assert sorted(r[0] for r in rows) == ["hl", "orca"]
    assert all(r[1] == "pr2" and r[2] == 1 and r[3] in (0.0, 1.0) for r in rows)
    # the mean time is over arrivals: a planner that arrived has a number, not NaN
    assert all(r[4] is not None and r[4] == r[4] for r in rows if r[3] == 1.0)


def test_readme_context_estimator_example_finds_the_pair() -> None:
    text = (ROOT / "README.md").read_text()
    (block,) = [
        b for b in re.findall(r"```python\n(.*?)```", text, re.S) if "ContextEstimator" in b
    ]
    namespace: dict[str, object] = {}
    exec(compile(block.replace("print(", "groups = ("), "README.md", "exec"), namespace)
    groups = namespace["groups"]
    assert [g.member_ids for g in groups] == [(1, 2)]  # type: ignore[attr-defined]

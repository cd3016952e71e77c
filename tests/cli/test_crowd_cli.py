"""The crowd suite end to end through the CLI (a small slice: one reporting seed) on the
results dataset every suite uses, and ``socialnav run --crowd``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow.compute as pc
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from shared import crowd_data, md_tables
from socialnav.cli import app
from socialnav.core.errors import ConfigurationError
from socialnav.experiments.crowd import (
    crowd_specs,
    parse_seeds,
    recording_fingerprint,
    unique_recordings,
)
from socialnav.experiments.results import ResultStore, load_results
from socialnav.experiments.storage import load_episode


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
    args = (
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
    result = invoke(*args)
    assert result.exit_code == 0, result.output
    assert "2 runs (0 errors)" in result.output
    text = (out / "report.md").read_text()
    assert "## Recording eth_hotel" in text
    table = next(t for t in md_tables(text) if t[0][0] == "planner")
    assert [row[0] for row in table[1:]] == ["paccet", "straight_line"]
    assert all(len(row) == len(table[0]) for row in table)
    assert "`paccet` on pr2: met" in text
    assert (out / "figures" / "crowd_eth_hotel.png").stat().st_size > 10_000
    # the same results dataset as every suite: partitioned, SQL-friendly names, null errors
    rows = load_results(out, suite="crowds")
    assert [(r["planner"], r["robot"]) for r in rows] == [
        ("paccet", "pr2"),
        ("straight_line", "pr2"),
    ]
    parts = sorted(p.relative_to(out).parts[:4] for p in (out / "results").rglob("*.parquet"))
    assert parts[0] == ("results", "suite=crowds", "planner=paccet", "robot=pr2")
    names = ResultStore(out).schema().names
    assert all(n.isidentifier() for n in names)
    assert {"time_within_1_2", "ok_reached_goal", "success"} <= set(names)
    assert "ok_success" not in names and all(r["error"] is None for r in rows)
    # the per-run trajectory is the long table: people absent at a step have no row there
    run = out / "runs" / rows[0]["run_id"]
    steps = pq.read_table(run / "trajectory.parquet")
    record = load_episode(run)
    people = steps.filter(pc.equal(steps["agent"], "person"))
    assert people.num_rows == int(record.people_present.sum()) > 0
    assert not record.people_present.all()  # people enter and leave the recording
    # resuming runs nothing again; `socialnav report` rebuilds the same tables from the dataset
    again = invoke(*args)
    assert again.exit_code == 0 and "2 runs (0 errors)" in again.output
    assert len(load_results(out, suite="crowds")) == 2
    (out / "report.md").unlink()
    rebuilt = invoke("report", out)
    assert rebuilt.exit_code == 0, rebuilt.output
    assert md_tables((out / "report.md").read_text()) == md_tables(text)
    assert "data:image/png;base64," in (out / "report.html").read_text()


def test_compare_crowds_needs_data_and_names_bad_files(tmp_path: Path) -> None:
    result = invoke("compare", "--suite", "crowds", "--out", tmp_path)
    assert result.exit_code == 2 and "--data" in result.output
    bad = tmp_path / "bad_obsmat.txt"
    bad.write_text("1 1 0 0 0 0 0 0\n2 1 0 0 zz 0 0 0\n")
    result = invoke("compare", "--suite", "crowds", "--data", bad, "--out", tmp_path / "r")
    assert result.exit_code == 2
    assert "bad_obsmat.txt: line 2: column 5 (y)" in " ".join(result.output.split())


ZARA_TASK = ("--t0", "33.2", "--start", "-1.9", "6.41", "--goal", "-4.25", "16.78")


def run_zara(*args: str | Path):
    return invoke("run", "--crowd", crowd_data("ucy_zara01_obsmat.txt"), *args)


def test_run_crowd_writes_every_file(tmp_path: Path) -> None:
    out = tmp_path / "run"
    result = run_zara(*ZARA_TASK, "--planner", "straight_line", "--out", out)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)  # the progress lines are on stderr
    assert summary["people"] > 5
    metrics = json.loads((out / "metrics.json").read_text())
    assert {"collisions_active", "time_within_1.2", "success_conditions"} <= metrics.keys()
    assert (out / "trajectory.parquet").is_file() and (out / "topdown.png").is_file()
    result = run_zara("--out", out)
    assert result.exit_code == 2 and "--start" in result.output


def test_run_crowd_writes_what_a_scenario_run_writes(tmp_path: Path) -> None:
    # a rollout planner on a 2 m task (a few seconds of recording): the same files as
    # `socialnav run <scenario>`, diagnostics and the decision figure included
    out = tmp_path / "run"
    task = "--t0 33.2 --start -1.9 6.41 --goal -1.9 8.41 --planner paccet --format csv"
    result = run_zara(*task.split(), "--out", out)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert {p.name for p in out.iterdir()} == {
        "trajectory.csv",
        "episode.json",
        "metrics.json",
        "topdown.png",
        "diagnostics.parquet",
        "decision.png",
    }
    diagnostics = pq.read_table(out / "diagnostics.parquet").to_pydict()
    assert 0 < len(diagnostics["step"]) <= summary["steps"]
    assert max(diagnostics["n_candidates"]) > 1
    assert (out / "decision.png").read_bytes()[:4] == b"\x89PNG"
    assert load_episode(out).num_steps == summary["steps"]
    assert result.stderr.splitlines()[-1] == "done"  # progress on stderr, as a scenario run
    assert "drawing topdown.png and decision.png …" in result.stderr.splitlines()


CROWD_FLAGS = ("--t0", "--start", "--goal", "--switch-distance")
SCENARIO_FLAGS = ("--humans",)


@pytest.mark.parametrize(
    ("args", "option"),
    [
        (["--start", "-4", "--goal", "1", "2"], "--start"),
        (["--start", "1", "--goal", "-4", "2"], "--start"),
        (["--start", "1", "2", "--goal", "-4"], "--goal"),
        (["--goal", "1", "2", "--start", "-4"], "--start"),
        (["--start", "1", "2", "3", "--goal", "1", "2"], "--start"),
        (["--start", "1", "2", "--goal", "1", "2", "-3"], "--goal"),
        (["--start", "a", "b", "--goal", "1", "2"], "--start"),
    ],
)
def test_run_crowd_start_and_goal_need_two_numbers(
    tmp_path: Path, args: list[str], option: str
) -> None:
    out = tmp_path / "run"
    result = run_zara("--out", out, *args)  # --out before: nothing for a short option to swallow
    assert result.exit_code == 2, result.output
    message = " ".join(result.output.replace("│", " ").split())
    assert f"Invalid value for '{option}': needs two numbers X Y" in message, message
    assert "Traceback" not in result.output
    assert not out.exists()


@pytest.mark.parametrize(
    ("crowd", "args", "message"),
    [
        (False, ["--start", "1", "2"], "--start only applies with --crowd"),
        (False, ["--goal", "-1", "2"], "--goal only applies with --crowd"),
        (False, ["--t0", "3"], "--t0 only applies with --crowd"),
        (False, ["--switch-distance", "1.5"], "--switch-distance only applies with --crowd"),
        (True, ["hallway_passing"], "a scenario or --crowd FILE, not both"),
        (True, ["--seed", "3"], "--seed with --crowd only applies to --context detected"),
        (True, ["--humans", "reactive"], "--humans only applies to a scenario"),
        (True, ["--context", "seen"], "unknown context 'seen'"),
    ],
)
def test_each_mode_refuses_the_other_modes_options(
    tmp_path: Path, crowd: bool, args: list[str], message: str
) -> None:
    out = tmp_path / "run"
    if crowd:
        result = run_zara(*args, *ZARA_TASK, "--out", out)
    else:
        result = invoke("run", "hallway_passing", *args, "--out", out)
    assert result.exit_code == 2, result.output
    assert message in " ".join(result.stderr.split())
    assert not out.exists()  # refused before running


def test_run_help_says_which_options_apply_to_which_mode() -> None:
    lines = invoke("run", "--help").stdout.splitlines()
    for flags, mark in ((CROWD_FLAGS, "--crowd only:"), (SCENARIO_FLAGS, "Scenario only:")):
        for flag in flags:
            row = next(ln for ln in lines if ln.lstrip("│ ").startswith(f"{flag} "))
            assert mark in row.split(flag, 1)[1], row


def test_run_crowd_with_the_context_detected_is_seeded_and_says_so(tmp_path: Path) -> None:
    # `run --crowd` refused --context: a recorded crowd could be run detected only through
    # `compare`. The perception noise is the run's one random choice: --seed picks it.
    task = "--t0 33.2 --start -1.9 6.41 --goal -1.9 8.41 --planner paccet --robot pioneer"
    runs = {}
    for name, seed in (("a", "3"), ("b", "3"), ("c", "4")):
        out = tmp_path / name
        result = run_zara(*task.split(), "--context", "detected", "--seed", seed, "--out", out)
        assert result.exit_code == 0, result.output
        assert json.loads(result.stdout)["context"] == "detected"
        record = load_episode(out)
        assert record.meta["context"] == "detected" and record.meta["seed"] == int(seed)
        assert record.meta["estimator_ms_median"] > 0
        runs[name] = record
    assert np.array_equal(runs["a"].robot_poses, runs["b"].robot_poses)  # same seed, same run
    shown = run_zara(*task.split(), "--context", "detected", "--seed", "5", "--out", tmp_path / "d")
    assert json.loads(shown.stdout)["seed"] == 5 and "context detected (seed 5)" in shown.stderr
    given = run_zara(*task.split(), "--out", tmp_path / "g")
    assert given.exit_code == 0 and json.loads(given.stdout)["context"] == "given"
    assert "seed" not in load_episode(tmp_path / "g").meta  # a given task draws nothing
    assert "seed" not in json.loads(given.stdout)


@pytest.mark.parametrize(
    "args",
    [
        ["run", "queue_line", "--seed", "4294967296"],
        ["run", "--crowd", "ZARA", *ZARA_TASK, "--context", "detected", "--seed", "99999999999"],
        ["detect", "queue_line", "--seed", "4294967296"],
        [
            "compare",
            "--suite",
            "generated",
            "--families",
            "queue",
            "--seeds",
            "4294967295:4294967297",
        ],
    ],
)
def test_a_seed_beyond_32_bits_is_refused_cleanly(tmp_path: Path, args: list[str]) -> None:
    # newcomer trial: navground's world seed is 32-bit; 2**32 raised a TypeError traceback
    args = [str(crowd_data("ucy_zara01_obsmat.txt")) if a == "ZARA" else a for a in args]
    result = invoke(*args, "--out", tmp_path / "o")
    assert result.exit_code == 2, result.output
    assert "4294967295" in " ".join(result.output.split())
    assert not (tmp_path / "o").exists()


def test_the_cli_seed_limit_is_the_simulator_s() -> None:
    from socialnav import cli
    from socialnav.sim.engine import MAX_SEED
    from socialnav.sim.runner import run_episode

    assert cli.MAX_SEED == MAX_SEED
    with pytest.raises(ConfigurationError, match="seed"):
        run_episode("queue_line", "go_to_goal", "pr2", seed=MAX_SEED + 1)


# --- newcomer trial: runs are keyed on the recording's name, so two files with one name ----


def straight_line_crowds(data: list[Path], out: Path, *more: str):
    args = ["compare", "--suite", "crowds", "--seeds", "0:1", "--planners", "straight_line"]
    for d in data:
        args += ["--data", str(d)]
    return invoke(*args, "--robots", "pioneer", "--jobs", "1", "--out", out, *more)


def two_recordings_named_walk(tmp_path: Path) -> tuple[Path, Path]:
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first, second = tmp_path / "a" / "walk.txt", tmp_path / "b" / "walk.txt"
    first.write_bytes(crowd_data("eth_hotel_obsmat.txt").read_bytes())
    second.write_bytes(crowd_data("ucy_zara01_obsmat.txt").read_bytes())
    return first, second


def test_bug_two_recordings_with_one_name_overwrote_each_others_runs(tmp_path: Path) -> None:
    first, second = two_recordings_named_walk(tmp_path)
    # in one call: refused, naming both files (it ran both and kept one file's rows)
    result = straight_line_crowds([first, second], tmp_path / "one")
    assert result.exit_code == 2
    message = " ".join(result.output.split())
    assert "same name 'walk'" in message and str(first) in message
    # across calls: the folder holds the first file's runs; resuming skipped the second file
    out = tmp_path / "two"
    assert straight_line_crowds([first], out).exit_code == 0
    result = straight_line_crowds([second], out)
    assert result.exit_code == 2, result.output
    assert "already holds runs of another recording named 'walk'" in " ".join(result.output.split())
    rows = load_results(out, suite="crowds")
    assert {r["data_sha256"] for r in rows} == {recording_fingerprint(str(first))}
    # the same file again, by another path: resumed, nothing refused
    (tmp_path / "c").mkdir()
    again = tmp_path / "c" / "walk.txt"
    again.write_bytes(first.read_bytes())
    result = straight_line_crowds([again, again], out)
    assert result.exit_code == 0 and "1 runs (0 errors)" in result.output, result.output


def test_runs_whose_people_switch_to_hl_are_labelled_and_reported_apart(tmp_path: Path) -> None:
    hotel = crowd_data("eth_hotel_obsmat.txt")
    out = tmp_path / "r"
    assert straight_line_crowds([hotel], out).exit_code == 0
    result = straight_line_crowds([hotel], out, "--switch-distance", "1.5")
    assert result.exit_code == 0, result.output
    rows = load_results(out, suite="crowds")
    assert sorted(r["humans"] for r in rows) == ["replayed", "replayed+HL@1.5m"]
    assert invoke("report", out).exit_code == 0
    text = (out / "report.md").read_text()
    assert "## Recording eth_hotel\n" in text
    assert "## Recording eth_hotel, people switching to HL within 1.5 m" in text
    # one row of one episode in each section: the two behaviours are never pooled
    tables = [t for t in md_tables(text) if t[0][0] == "planner"]
    assert [[row[2] for row in t[1:]] for t in tables] == [["1"], ["1"]]
    assert "1 episode (" in text and "seed 0;" in text  # singular, one seed
    # the commands that made these rows, one per switch distance
    base = f"socialnav compare --suite crowds --data {hotel} --seeds 0:1 --planners straight_line"
    assert f"`{base} --robots pioneer`, and `{base} --robots pioneer --switch-distance 1.5`" in text


@pytest.mark.parametrize(
    ("suite", "option"),
    [
        ("paper", ["--data", "x.txt"]),
        ("generated", ["--switch-distance", "1.5"]),
        ("crowds", ["--families", "hallway"]),
        ("crowds", ["--scenarios", "group_join"]),
        ("generated", ["--scenarios", "group_join"]),
    ],
)
def test_compare_refuses_an_option_its_suite_would_ignore(
    tmp_path: Path, suite: str, option: list[str]
) -> None:
    result = invoke("compare", "--suite", suite, *option, "--out", tmp_path / "r")
    assert result.exit_code == 2
    assert f"{option[0]} applies only with" in " ".join(result.output.split())
    assert not (tmp_path / "r").exists()


def test_compare_crowds_runs_each_context_and_reports_them_apart(tmp_path: Path) -> None:
    out = tmp_path / "r"
    result = straight_line_crowds([crowd_data("eth_hotel_obsmat.txt")], out, "--context", "both")
    assert result.exit_code == 0, result.output
    rows = load_results(out, suite="crowds")
    assert sorted(r["context"] for r in rows) == ["detected", "given"]
    assert len({r["run_id"] for r in rows}) == 2
    text = (out / "report.md").read_text()
    assert "## Recording eth_hotel\n" in text and "## Recording eth_hotel, context detected" in text


def test_run_crowd_warns_of_a_task_unlike_the_suites(tmp_path: Path) -> None:
    # newcomer trial: a start on a person, or a t0 near the recording's end, ran without a word
    on_someone = ("--t0", "33.2", "--start", "0.229", "12.906", "--goal", "-4.25", "16.78")
    result = run_zara(*on_someone, "--planner", "straight_line", "--out", tmp_path / "a")
    assert result.exit_code == 0, result.output
    assert "warning: person 16 is 0.00 m from --start at --t0 33.2 s" in result.stderr
    assert len(json.loads(result.stdout)["warnings"]) == 1
    late = ("--t0", "355", "--start", "-1.9", "6.41", "--goal", "-4.25", "16.78")
    result = run_zara(*late, "--planner", "straight_line", "--out", tmp_path / "b")
    assert result.exit_code == 0, result.output
    assert "the recording ends" in result.stderr and "nobody is in the scene" in result.stderr
    result = run_zara(*ZARA_TASK, "--planner", "straight_line", "--out", tmp_path / "c")
    assert json.loads(result.stdout)["warnings"] == [] and "warning" not in result.stderr


def test_compare_crowds_fails_once_on_a_recording_without_episodes(tmp_path: Path) -> None:
    # before: one error row per planner and seed, each after 400 draws
    path = tmp_path / "sparse.txt"
    spots = [(0, 0), (40, 0), (0, 40), (40, 40), (20, 20), (20, 0)]
    path.write_text(
        "".join(f"{f} {i} {x} {y}\n" for f in (0, 10) for i, (x, y) in enumerate(spots))
    )
    out = tmp_path / "r"
    result = straight_line_crowds([path], out)
    assert result.exit_code == 2
    assert "no episode after 400 start times" in " ".join(result.output.split())
    assert not (out / "results").exists()


@pytest.mark.parametrize("value", ["nan", "-1", "inf"])
def test_compare_crowds_refuses_a_switch_distance_run_would_refuse(
    tmp_path: Path, value: str
) -> None:
    # second trial: NaN ran and was stored as "never react", pooled with plain replay
    hotel = crowd_data("eth_hotel_obsmat.txt")
    result = straight_line_crowds([hotel], tmp_path / "r", "--switch-distance", value)
    assert result.exit_code == 2
    assert "--switch-distance must be a finite distance >= 0 m" in " ".join(result.output.split())


def test_one_recording_under_two_paths_or_cases_runs_once_or_is_refused(tmp_path: Path) -> None:
    first, second = two_recordings_named_walk(tmp_path)
    (tmp_path / "c").mkdir()
    copy = tmp_path / "c" / "walk.txt"
    copy.write_bytes(first.read_bytes())
    assert unique_recordings([str(first), str(copy)]) == [str(first)]  # same bytes, same name
    upper = tmp_path / "c" / "Walk.txt"
    upper.write_bytes(second.read_bytes())
    with pytest.raises(ConfigurationError, match="same name 'walk' \\(case aside\\)"):
        unique_recordings([str(first), str(upper)])


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["compare", "--suite", "crowds", "--jobs", "0"], "--jobs must be a number of workers"),
        (["run", "queue_line", "--seed", "-1"], "Invalid value for '--seed'"),
        (["detect", "queue_line", "--seed", "-1"], "Invalid value for '--seed'"),
    ],
)
def test_a_negative_seed_or_no_workers_is_a_clean_error(
    tmp_path: Path, args: list[str], message: str
) -> None:
    # second trial: NumPy's "expected non-negative integer" and joblib's "n_jobs == 0"
    # tracebacks
    result = invoke(*args, "--out", tmp_path / "o")
    assert result.exit_code == 2 and isinstance(result.exception, SystemExit)
    assert message in " ".join(result.output.replace("│", " ").split())


def _late_slice(folder: Path) -> Path:
    """Two walkers annotated from frame 10 (0.4 s, as ETH hotel starts at 0.04 s, not 0) and a
    group list whose second line names someone the file never shows."""
    rows = []
    for frame in range(10, 260, 10):
        x = (frame - 10) / 24.0
        rows.append(f"{frame} 1 {x:.3f} 0 0.0 0.4 0 0")
        rows.append(f"{frame} 2 {x:.3f} 0 10.0 0.4 0 0")
    path = folder / "late_obsmat.txt"
    path.write_text("\n".join(rows) + "\n")
    (folder / "late_groups.txt").write_text("1 99\n")
    return path


def test_bug_run_crowd_starts_at_the_recordings_start_without_t0(tmp_path: Path) -> None:
    # Newcomer trial: --t0 defaulted to 0, outside ETH hotel's span (0.04–722.44 s), so a run
    # without --t0 always failed there; and the loader's group warning reached only Python's
    # stderr, not the run's own warnings.
    path = _late_slice(tmp_path)
    out = tmp_path / "run"
    task = ("--start", "3", "5", "--goal", "4", "5", "--planner", "straight_line")
    result = invoke("run", "--crowd", path, *task, "--out", out)
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert load_episode(out).meta["t0"] == pytest.approx(0.4)
    said = [w for w in summary["warnings"] if "group(s) name people" in w]
    assert len(said) == 1 and "late_groups.txt" in said[0] and "ids 99" in said[0]
    # the same warning once per file in a comparison, on the CLI's warning channel, before
    # the file is checked for episodes (two walkers yield none: a clean error, no traceback)
    result = invoke(
        "compare", "--suite", "crowds", "--data", path, "--seeds", "1", "--out", tmp_path / "c"
    )
    assert result.exit_code == 2 and "no episode" in result.stderr
    assert result.stderr.count("warning: ") == 1
    assert result.stderr.index("group(s) name people") < result.stderr.index("no episode")

"""``socialnav run``: bad input fails before the episode runs, in one line naming the option or
file, and a reused output folder holds one run's files. Tiny recordings written in tmp_path."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from socialnav.cli import app
from socialnav.core.errors import ConfigurationError
from socialnav.experiments.crowd import run_crowd_single

TASK = ("--t0", "0.4", "--start", "1", "2", "--goal", "2.5", "2")


def invoke(*args: str | Path):
    return CliRunner().invoke(app, [str(a) for a in args])


def obsmat(path: Path, people: dict[int, list[tuple[int, float, float]]]) -> Path:
    """An obsmat file: ``people[id] = [(frame, x, y), ...]`` (velocities zero)."""
    rows = [
        f"{frame} {pid} {x} 0 {y} 0 0 0"
        for pid, samples in people.items()
        for frame, x, y in samples
    ]
    path.write_text("\n".join(sorted(rows, key=lambda r: int(r.split()[0]))) + "\n")
    return path


@pytest.fixture
def small(tmp_path: Path) -> Path:
    """Two people over x 0 to 6 m, y 0 to 4 m, frames 0 to 100 (0 to 4 s)."""
    return obsmat(
        tmp_path / "small_obsmat.txt",
        {
            1: [(f, 0.06 * f, 0.0) for f in range(0, 101, 10)],
            2: [(f, 6.0, 4.0 - 0.02 * f) for f in range(0, 101, 10)],
        },
    )


def one_line(result) -> str:
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit)  # a message, not a traceback
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    return lines[0]


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--start", "50", "50"], ["--start 50 50", "x 0.00 to 6.00 m", "y 0.00 to 4.00 m"]),
        (["--goal", "-1", "2"], ["--goal -1 2", "x 0.00 to 6.00 m", "y 0.00 to 4.00 m"]),
        # inside the area, but the PR2's footprint would start across its border
        (["--start", "0.2", "2"], ["--start 0.2 2", "(the robot's radius) inside", "x 0.00"]),
        (["--t0", "-1"], ["--t0 -1", "time span 0 to 4 s"]),
        (["--t0", "4.5"], ["--t0 4.5", "time span 0 to 4 s"]),
        (["--switch-distance", "-0.5"], ["--switch-distance", "-0.5"]),
        (["--goal", "1.1", "2"], ["--start and --goal are 0.10 m apart"]),
    ],
)
def test_a_crowd_task_the_recording_cannot_hold_fails_before_the_run(
    small: Path, tmp_path: Path, args: list[str], words: list[str]
) -> None:
    out = tmp_path / "run"
    # later options override the task's: one bad value per case
    result = invoke("run", "--crowd", small, *TASK, *args, "--out", out)
    line = one_line(result)
    named = not ("switch" in args[0] or "apart" in words[0])  # these name no file
    for word in [*words] + (["small_obsmat.txt"] if named else []):
        assert word in line, line
    assert not out.exists()  # refused before the episode


def test_run_crowd_single_checks_the_task(small: Path, tmp_path: Path) -> None:
    with pytest.raises(ConfigurationError, match=r"--goal 9 9: outside the annotated area"):
        run_crowd_single(small, 0.4, (1, 2), (9, 9), "straight_line", "pr2", out=tmp_path / "o")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("people", "flat"),
    [
        ({1: [(1, 0.5, 2.0)]}, "zero width (every x is 0.5)"),
        ({1: [(0, 1.0, 0.0), (10, 1.0, 1.0)], 2: [(0, 1.0, 3.0)]}, "zero width (every x is 1)"),
        ({1: [(0, 0.0, 2.0), (10, 3.0, 2.0)]}, "zero height (every y is 2)"),
    ],
)
def test_a_degenerate_recording_names_the_file_and_the_flat_side(
    tmp_path: Path, people: dict, flat: str
) -> None:
    data = obsmat(tmp_path / "flat_obsmat.txt", people)
    out = tmp_path / "run"
    line = one_line(invoke("run", "--crowd", data, "--t0", "0", *TASK[2:], "--out", out))
    assert "flat_obsmat.txt: the recorded area has " + flat in line, line
    assert not out.exists()


def test_a_directory_given_as_crowd_is_called_a_directory(tmp_path: Path) -> None:
    line = one_line(invoke("run", "--crowd", tmp_path, *TASK, "--out", tmp_path / "run"))
    assert f"{tmp_path}: is a directory" in line and "no such file" not in line


@pytest.mark.parametrize("crowd", [False, True])
def test_out_that_is_a_file_fails_before_the_run(small: Path, tmp_path: Path, crowd: bool) -> None:
    taken = tmp_path / "taken"
    taken.write_text("mine")
    mode = ["--crowd", small, *TASK] if crowd else ["hallway_passing"]
    for out, why in ((taken, "is a file"), (taken / "sub", f"lies inside {taken}, a file")):
        line = one_line(invoke("run", *mode, "--out", out))
        assert f"--out {out}: {why}, not a folder" in line, line
    assert taken.read_text() == "mine"


@pytest.mark.parametrize("crowd", [False, True])
def test_mp4_without_the_video_extra_fails_before_the_run(
    small: Path, tmp_path: Path, crowd: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # find_spec: not installed
    out = tmp_path / "run"
    mode = ["--crowd", small, *TASK] if crowd else ["hallway_passing"]
    line = one_line(invoke("run", *mode, "--video", "mp4", "--out", out))
    assert "pip install 'socialnav[video]'" in line and "--video gif" in line, line
    assert not out.exists()


def test_run_help_says_mp4_needs_the_video_extra_and_what_out_replaces() -> None:
    text = " ".join(invoke("run", "--help").stdout.replace("│", " ").split())
    assert "mp4 needs the optional video extra" in text
    assert "are replaced, other files are kept" in text


@pytest.fixture
def reused(small: Path, tmp_path: Path) -> tuple[Path, object]:
    """``traditional`` (one objective: no decision figure) into a folder an earlier run used."""
    out = tmp_path / "run"
    out.mkdir()
    for name in ("trajectory.parquet", "episode.gif", "notes.txt"):
        (out / name).write_text("old")
    result = invoke(
        "run", "--crowd", small, *TASK, "--planner", "traditional", "--format", "csv", "--out", out
    )
    assert result.exit_code == 0, result.output
    return out, result


def test_a_reused_folder_holds_only_the_new_runs_files(reused) -> None:
    out, result = reused
    assert not (out / "trajectory.parquet").exists() and not (out / "episode.gif").exists()
    assert (out / "trajectory.csv").is_file() and (out / "metrics.json").is_file()
    assert (out / "notes.txt").read_text() == "old"  # not ours: kept
    assert "removed 2 files of an earlier run" in result.stderr


def test_progress_names_only_the_figures_drawn(reused) -> None:
    _, result = reused
    assert "drawing topdown.png …" in result.stderr.splitlines()
    assert "decision.png" not in result.stderr


def test_crowd_metrics_have_the_planner_step_time_and_no_seed(reused) -> None:
    out, _ = reused
    metrics = json.loads((out / "metrics.json").read_text())
    assert 0 < metrics["planner_ms_median"] <= metrics["planner_ms_p95"]
    assert "seed" not in json.loads((out / "episode.json").read_text())["meta"]


def test_crowd_figure_title_has_no_seed(reused) -> None:
    from socialnav.experiments.storage import load_episode
    from socialnav.viz.crowd import plot_crowd_episodes

    out, _ = reused
    figure = plot_crowd_episodes([load_episode(out)])
    assert figure.axes[0].get_title() == "traditional · pr2"


def test_an_unknown_scenario_fails_before_the_run_is_announced(tmp_path: Path) -> None:
    # it printed "running nope_scenario with paccet …" and then the error
    line = one_line(invoke("run", "nope_scenario", "--out", tmp_path / "run"))
    assert "unknown scenario 'nope_scenario'" in line
    assert not (tmp_path / "run").exists()
    line = one_line(invoke("run", "generated:hallwy", "--out", tmp_path / "run"))
    assert "unknown generated family 'hallwy'" in line
    assert not (tmp_path / "run").exists()


def test_a_generated_scene_runs_by_its_family_and_seed(tmp_path: Path) -> None:
    # the scenario check before the run must let generated:<family> names through
    out = tmp_path / "run"
    result = invoke(
        "run", "generated:queue", "--seed", "3", "--planner", "go_to_goal", "--out", out
    )
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["scenario"] == "queue_s3"  # the generated scene's name
    assert (out / "metrics.json").is_file()

"""Commands a new user tried that used to fail: a registered controller by name and a
``family: custom`` scenario."""

from __future__ import annotations

import json

import yaml
from typer.testing import CliRunner

from socialnav.cli import app
from socialnav.sim.scenario import load_scenario


def _run(*args: str):
    return CliRunner().invoke(app, ["run", *args])


def test_go_to_goal_is_a_planner_of_socialnav_run(tmp_path):
    result = _run("hallway_stationary", "--planner", "go_to_goal", "--out", str(tmp_path))
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["planner"] == "go_to_goal"
    assert (tmp_path / "metrics.json").exists()


def test_a_custom_family_scenario_runs_with_the_common_conditions(tmp_path):
    data = load_scenario("hallway_stationary").model_dump(mode="json")
    data.update(name="custom_stationary", family="custom")
    path = tmp_path / "custom.yaml"
    path.write_text(yaml.safe_dump(data))
    result = _run(str(path), "--planner", "traditional", "--out", str(tmp_path / "out"))
    assert result.exit_code == 0, result.output
    metrics = json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert set(metrics["success_conditions"]) == {"reached_goal", "no_collision", "success"}
    assert metrics["success_conditions"]["success"] is True


def test_version_is_defined_once_and_printed():
    from socialnav import __version__

    result = CliRunner().invoke(app, ["--version"])
    assert result.exit_code == 0
    assert result.stdout.strip() == f"socialnav {__version__}"

"""The other CLI commands and the CLI's failures: list, schema, validate, unknown names."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from typer.testing import CliRunner

from shared import ALL_PLANNERS
from socialnav.cli import app
from socialnav.experiments.planners import planner_names
from socialnav.sim.scenario import Scenario, builtin_scenarios, load_scenario

PLANNERS = set(ALL_PLANNERS)


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def listed(stdout: str) -> tuple[list[str], list[str]]:
    lines = stdout.splitlines()
    scenarios = next(ln for ln in lines if ln.startswith("scenarios:"))
    planners = [ln.split()[1].rstrip(":") for ln in lines if ln.startswith("planner ")]
    return [s.strip() for s in scenarios.removeprefix("scenarios:").split(",")], planners


def hallway_dict() -> dict:
    return load_scenario("hallway_passing").model_dump(mode="json")


# --- list / schema --------------------------------------------------------------------------------


def test_list_names_the_13_scenarios_and_every_planner_in_display_order() -> None:
    result = invoke("list")
    assert result.exit_code == 0
    scenarios, planners = listed(result.stdout)
    assert len(scenarios) == 13
    assert scenarios == builtin_scenarios()
    assert planners == planner_names()
    assert set(planners) >= PLANNERS and "go_to_goal" in planners


def test_list_and_compare_help_name_every_generated_family() -> None:
    from socialnav.cli import GENERATED_FAMILIES
    from socialnav.sim.generate import GENERATORS

    # the help text is spelled out (no simulator import on --help); it must track the registry
    assert [f.strip() for f in GENERATED_FAMILIES.split(",")] == sorted(GENERATORS)
    lines = invoke("list").stdout.splitlines()
    families = next(ln for ln in lines if ln.startswith("generated families"))
    assert families.split(": ", 1)[1].split(", ") == sorted(GENERATORS)
    # rich wraps the help column: compare without the table's borders and line breaks
    text = "".join(ch for ch in invoke("compare", "--help").stdout if ch not in "│ \n")
    assert all(name in text for name in GENERATORS)


def test_top_level_help_gives_each_command_a_one_line_summary() -> None:
    # a summary that wraps mid-sentence in `socialnav --help` reads as broken text
    for command in app.registered_commands:
        doc = (command.callback.__doc__ or "").strip() if command.callback else ""
        summary = doc.split("\n\n", 1)[0]
        assert "\n" not in summary, f"{command.name or command.callback}: {summary!r}"


def test_run_help_writes_start_and_goal_as_the_readme_does() -> None:
    # `--start X Y`, two numbers after one flag (the README's form), not "<float,float>..."
    lines = invoke("run", "--help").stdout.splitlines()
    for flag in ("--start", "--goal"):
        row = next(ln for ln in lines if ln.lstrip("│ ").startswith(f"{flag} "))  # its option row
        assert row.split(flag, 1)[1].split()[0:2] == ["X", "Y"], row


def test_installed_console_script_lists_the_same() -> None:
    script = Path(sys.executable).with_name("socialnav")
    proc = subprocess.run(
        [str(script), "list"], capture_output=True, text=True, timeout=60, check=False
    )
    assert proc.returncode == 0, proc.stderr
    # other test modules may register throwaway controllers in this process
    here = [ln for ln in invoke("list").stdout.splitlines() if "test_" not in ln]
    assert proc.stdout.splitlines() == here


def test_schema_is_a_json_schema_of_scenario_files(tmp_path: Path) -> None:
    result = invoke("schema")
    assert result.exit_code == 0
    schema = json.loads(result.stdout)
    assert schema["$schema"].startswith("https://json-schema.org/")
    assert schema["type"] == "object"
    assert set(schema["properties"]) == set(Scenario.model_fields)
    assert {"name", "family", "start", "goal"} <= set(schema["required"])
    assert schema["additionalProperties"] is False
    # every key of every shipped scenario file is described
    for name in builtin_scenarios():
        data = load_scenario(name).model_dump(exclude_unset=True)
        assert set(data) <= set(schema["properties"]), name
    out = tmp_path / "scenario.schema.json"
    assert invoke("schema", "--out", str(out)).exit_code == 0
    assert json.loads(out.read_text()) == schema


# --- validate -------------------------------------------------------------------------------------


def test_validate_accepts_a_builtin_and_a_written_file(tmp_path: Path) -> None:
    assert invoke("validate", "hallway_passing").exit_code == 0
    path = tmp_path / "mine.yaml"
    path.write_text(yaml.safe_dump({**hallway_dict(), "name": "mine"}))
    result = invoke("validate", str(path))
    assert result.exit_code == 0, result.output
    assert "ok" in result.stdout and "mine" in result.stdout


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"time_limit": -5.0}, "time_limit"),
        ({"start": [0.5, "left", 0.0]}, "start.1"),
        ({"goal_tolerence": 0.2}, "goal_tolerence"),  # misspelt key: extra fields are errors
        ({"family": "corridor"}, "family"),
    ],
)
def test_validate_names_the_file_and_the_field(tmp_path: Path, change: dict, field: str) -> None:
    path = tmp_path / "broken_scenario.yaml"
    path.write_text(yaml.safe_dump({**hallway_dict(), **change}))
    result = invoke("validate", str(path))
    assert result.exit_code != 0
    message = result.stderr
    assert "broken_scenario.yaml" in message
    assert f"{field}:" in message


def test_validate_names_a_nested_field(tmp_path: Path) -> None:
    data = hallway_dict()
    data["people"][0]["behavior"]["velocity"] = [0.0, 0.0]
    path = tmp_path / "standing_walker.yaml"
    path.write_text(yaml.safe_dump(data))
    result = invoke("validate", str(path))
    assert result.exit_code != 0
    assert "standing_walker.yaml: people.0.behavior" in result.stderr


def test_validate_reports_invalid_yaml_with_the_file_name(tmp_path: Path) -> None:
    path = tmp_path / "not_yaml.yaml"
    path.write_text("name: x\nstart: [0.5, -0.45\n")
    result = invoke("validate", str(path))
    assert result.exit_code != 0
    assert "not_yaml.yaml" in result.stderr and "YAML" in result.stderr


# --- unknown names --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "bad", "good"),
    [
        (["run", "hallway_passing", "--planner", "pacet"], "pacet", "paccet"),
        (["run", "hallway_passing", "--robot", "pr3"], "pr3", "pr2"),
        (["run", "hallway_pasing"], "hallway_pasing", "hallway_passing"),
        (["compare", "--planners", "traditionl"], "traditionl", "traditional"),
        (["compare", "--robots", "pr2,pionier"], "pionier", "pioneer"),
        (["compare", "--scenarios", "queue_lne"], "queue_lne", "queue_line"),
    ],
)
def test_unknown_names_fail_with_did_you_mean(
    tmp_path: Path, args: list[str], bad: str, good: str
) -> None:
    out = tmp_path / "out"
    result = invoke(*args, "--out", str(out))
    assert result.exit_code != 0
    message = result.stderr
    assert repr(bad) in message
    assert f"Did you mean {good!r}?" in message
    assert not (out / "results").exists()  # failed before running anything
    assert not (out / "trajectory.parquet").exists()


@pytest.mark.parametrize(
    ("option", "value"), [("--format", "xml"), ("--video", "avi"), ("--humans", "robots")]
)
def test_run_rejects_bad_options_before_running(tmp_path: Path, option: str, value: str) -> None:
    out = tmp_path / "out"
    result = invoke("run", "hallway_passing", option, value, "--out", str(out))
    assert result.exit_code != 0
    assert repr(value) in result.stderr
    assert not out.exists()


def test_compare_rejects_an_unknown_suite(tmp_path: Path) -> None:
    result = invoke("compare", "--suite", "papr", "--out", str(tmp_path / "r"))
    assert result.exit_code != 0
    assert "papr" in result.stderr


def test_ros2_list_params_prints_every_node_parameter_without_ros() -> None:
    """``socialnav ros2 --list-params`` is the node's parameter table (one row per declared
    parameter, the model's limits as defaults), available before the ROS extra is installed."""
    from socialnav.core.robot import PR2
    from socialnav.integrations.ros2.params import param_specs

    result = invoke("ros2", "--list-params", "--robot-model", "pr2")
    assert result.exit_code == 0, result.stdout
    rows = [ln for ln in result.stdout.splitlines() if ln.startswith("| `")]
    names = [ln.split("`")[1] for ln in rows]
    assert names == [spec.name for spec in param_specs("pr2")]
    by_name = dict(zip(names, rows, strict=True))
    assert f"| {PR2.max_vel_x} |" in by_name["max_vel_x"]
    assert "deferred, threaded, inline" in by_name["replan_mode"]
    assert by_name["path_distance_bias"].split("|")[4].strip() == "yes"
    assert by_name["sim_time"].split("|")[4].strip() == "no"

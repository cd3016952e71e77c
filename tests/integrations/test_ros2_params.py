"""The ROS 2 node's parameter table, params files, conversions and CLI — all without ROS."""

from __future__ import annotations

import dataclasses
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from socialnav.cli import app
from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.robot import PIONEER, PR2
from socialnav.integrations.ros2.convert import (
    compose,
    costmap_from_occupancy,
    decelerate,
    quaternion_from_yaw,
    yaw_from_quaternion,
)
from socialnav.integrations.ros2.params import (
    DYNAMIC,
    load_params_file,
    local_planner_params,
    param_specs,
    planner_defaults,
    robot_from_params,
)
from socialnav.planner.local_planner import LocalPlannerParams
from socialnav.world.grid import FREE, LETHAL, UNKNOWN


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "params.yaml"
    path.write_text(text)
    return path


def test_every_planner_field_is_a_parameter_with_range_and_description() -> None:
    specs = {s.name: s for s in param_specs()}
    for f in dataclasses.fields(LocalPlannerParams):
        if f.name == "controller_period":
            continue  # from controller_frequency
        spec = specs[f.name]
        assert spec.description and spec.default == getattr(planner_defaults("paccet"), f.name)
        if spec.kind in (int, float):
            assert spec.min is not None and spec.max is not None
            assert spec.min <= spec.default <= spec.max
    assert set(specs) >= DYNAMIC and all(specs[n].dynamic for n in DYNAMIC)
    assert not specs["planner"].dynamic and not specs["max_vel_x"].dynamic


def test_bug_the_planner_parameters_default_to_the_chosen_presets() -> None:
    # The node declared LocalPlannerParams() for every planner, so `paccet` on a robot ran
    # without the rollouts that stop at the goal, the 0.07 m tolerance and the goal term along
    # the plan that the suites measured.
    from socialnav.planner.presets import PRESETS

    for planner in ("paccet", "traditional"):
        specs = param_specs("pr2", planner)
        values = {s.name: s.default for s in specs}
        assert values["planner"] == planner
        want = PRESETS.get(planner).params or LocalPlannerParams()
        got = local_planner_params(values)
        assert dataclasses.replace(got, controller_period=want.controller_period) == want
    paccet = {s.name: s.default for s in param_specs(planner="paccet")}
    assert paccet["stop_at_goal"] is True
    assert paccet["goal_distance_measure"] == "along_plan"


def test_a_params_file_is_checked_against_its_planners_defaults(tmp_path: Path) -> None:
    path = tmp_path / "p.yaml"
    path.write_text(
        "socialnav:\n  ros__parameters:\n    planner: traditional\n"
        "    goal_distance_measure: along_plan\n"
    )
    assert load_params_file(path)["goal_distance_measure"] == "along_plan"
    path.write_text("socialnav:\n  ros__parameters:\n    goal_distance_measure: euclid\n")
    with pytest.raises(ConfigurationError, match=r"goal_distance_measure.*bfs, along_plan"):
        load_params_file(path)


def test_robot_limits_default_to_the_model() -> None:
    specs = {s.name: s for s in param_specs("pr2")}
    assert specs["max_vel_y"].default == PR2.max_vel_y
    assert {s.name: s for s in param_specs("pioneer")}["max_vel_y"].default == 0.0


def test_nav2_params_file(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        """
/**:
  ros__parameters:
    controller_frequency: 20.0
socialnav:
  ros__parameters:
    robot_model: pr2
    max_vel_x: 0.4
    footprint: "[[0.3, 0.3], [-0.3, 0.3], [-0.3, -0.3], [0.3, -0.3]]"
    xy_goal_tolerance: 0.2
    odom_to_global: [1, 2, 0.5]
""",
    )
    values = load_params_file(path)
    assert values["controller_frequency"] == 20.0 and values["odom_to_global"] == [1.0, 2.0, 0.5]
    robot = robot_from_params(values)
    assert robot.name == "pr2" and robot.max_vel_x == 0.4 and robot.polygon.shape == (4, 2)
    params = local_planner_params(values)
    assert params.controller_period == pytest.approx(0.05) and params.xy_goal_tolerance == 0.2


@pytest.mark.parametrize(
    ("body", "match"),
    [
        ("    max_vel_xx: 1.0", "max_vel_xx: unknown \\(did you mean 'max_vel_x'\\?\\)"),
        ("    max_vel_x: fast", "max_vel_x: expected a number"),
        ("    max_vel_x: 50.0", "max_vel_x: 50.0 is outside"),
        ("    vx_samples: 2.5", "vx_samples: expected an integer"),
        ("    planner: magic", "planner: 'magic' is not one of"),
        ("    footprint: '[[0, 0]]'", "footprint: needs at least 3"),
        ("    max_vel_y: 0.3", "max_vel_y must be 0 for the differential-drive"),
        ("    odom_to_global: [1, 2]", "odom_to_global: expected 3 numbers"),
        ("    xy_goal_tolerance: .nan", "xy_goal_tolerance: must be finite"),
    ],
)
def test_bad_params_name_file_and_field(tmp_path: Path, body: str, match: str) -> None:
    path = write(tmp_path, "socialnav:\n  ros__parameters:\n" + body + "\n")
    with pytest.raises(ConfigurationError, match=match) as info:
        load_params_file(path)
    assert str(path) in str(info.value)


def test_params_file_structure_errors(tmp_path: Path) -> None:
    with pytest.raises(ConfigurationError, match="no section for node 'socialnav'"):
        load_params_file(write(tmp_path, "controller_server:\n  ros__parameters: {}\n"))
    with pytest.raises(ConfigurationError, match="ros__parameters"):
        load_params_file(write(tmp_path, "socialnav: {max_vel_x: 1}\n"))
    with pytest.raises(ConfigurationError, match="not valid YAML"):
        load_params_file(write(tmp_path, "socialnav: [\n"))
    with pytest.raises(ConfigurationError, match="no such params file"):
        load_params_file(tmp_path / "missing.yaml")


def test_occupancy_grid_to_costmap() -> None:
    data = np.zeros((20, 30), dtype=np.int8)
    data[10, 15] = 100
    data[0, :] = -1
    cm = costmap_from_occupancy(data.ravel(), 30, 20, 0.1, [1.0, 2.0, 0.0], PIONEER, 0.5)
    assert cm.geometry.origin == (1.0, 2.0) and cm.costs.shape == (20, 30)
    assert cm.costs[10, 15] == LETHAL and cm.costs[0, 0] == UNKNOWN and cm.costs[19, 0] == FREE
    assert cm.cost_at([[1.0 + 1.55, 2.0 + 1.05]])[0] == LETHAL  # cell (10, 15) centre
    assert FREE < cm.costs[10, 18] < LETHAL  # inflated, 0.3 m away
    with pytest.raises(InvalidInputError, match="rotated"):
        costmap_from_occupancy(data.ravel(), 30, 20, 0.1, [0, 0, 0.3], PIONEER)
    with pytest.raises(InvalidInputError, match="expected 600"):
        costmap_from_occupancy(data.ravel()[:-1], 30, 20, 0.1, [0, 0, 0], PIONEER)


def test_quaternions_and_frames() -> None:
    for yaw in (-3.0, -1.0, 0.0, 0.5, 3.1):
        assert yaw_from_quaternion(*quaternion_from_yaw(yaw)) == pytest.approx(yaw)
    pose = compose([1.0, 2.0, math.pi / 2], [1.0, 0.0, 0.1])
    assert pose == pytest.approx([1.0, 3.0, math.pi / 2 + 0.1])


def test_decelerate_respects_the_limits() -> None:
    cmd = np.array([0.5, 0.0, 1.0])
    steps = [cmd]
    while np.any(steps[-1] != 0):
        steps.append(decelerate(steps[-1], PIONEER, 0.1))
        assert len(steps) < 100
    d = np.abs(np.diff(np.asarray(steps), axis=0))
    assert np.all(d[:, 0] <= PIONEER.acc_lim_x * 0.1 + 1e-12)
    assert np.all(d[:, 2] <= PIONEER.acc_lim_theta * 0.1 + 1e-12)
    assert len(steps) - 1 == math.ceil(0.5 / (PIONEER.acc_lim_x * 0.1))
    assert np.all(decelerate([np.nan, 0, 0], PIONEER, 0.1) == 0)


@pytest.mark.skipif(importlib.util.find_spec("rclpy") is not None, reason="rclpy installed")
def test_ros2_command_without_the_extra_says_how_to_install(tmp_path: Path) -> None:
    path = write(tmp_path, "socialnav:\n  ros__parameters:\n    planner: paccet\n")
    result = CliRunner().invoke(app, ["ros2", "--params", str(path)])
    assert result.exit_code == 2
    assert "pip install 'socialnav[ros]'" in result.output


@pytest.mark.skipif(importlib.util.find_spec("rclpy") is not None, reason="rclpy installed")
def test_ros2_command_without_the_extra_names_it_even_when_the_params_file_is_bad(
    tmp_path: Path,
) -> None:
    result = CliRunner().invoke(app, ["ros2", "--params", str(tmp_path / "missing.yaml")])
    assert result.exit_code == 2
    assert "no such params file" in result.output
    assert "pip install 'socialnav[ros]'" in result.output


def test_bug_parameters_missing_from_a_params_file_are_the_presets(tmp_path: Path) -> None:
    # local_planner_params filled what a file left out with LocalPlannerParams(): a file naming
    # only the planner gave paccet the ROS defaults (newcomer trial).
    path = write(tmp_path, "socialnav:\n  ros__parameters:\n    planner: paccet\n")
    got = local_planner_params(load_params_file(path))
    assert got == planner_defaults("paccet")
    assert got.goal_distance_measure == "along_plan" and got.stop_at_goal
    path = write(tmp_path, "socialnav:\n  ros__parameters:\n    planner: traditional\n")
    assert local_planner_params(load_params_file(path)) == LocalPlannerParams()


def test_list_params_shows_the_defaults_of_the_planner_and_of_a_params_file(
    tmp_path: Path,
) -> None:
    def row(args: list[str], name: str) -> str:
        result = CliRunner().invoke(app, ["ros2", "--list-params", *args])
        assert result.exit_code == 0, result.output
        return next(line for line in result.output.splitlines() if f"`{name}`" in line)

    assert "| along_plan |" in row([], "goal_distance_measure")
    assert "| bfs |" in row(["--planner", "traditional"], "goal_distance_measure")
    path = write(
        tmp_path, "socialnav:\n  ros__parameters:\n    planner: traditional\n    sim_time: 2.5\n"
    )
    assert "| bfs |" in row(["--params", str(path)], "goal_distance_measure")
    assert "| 2.5 |" in row(["--params", str(path)], "sim_time")


def test_a_good_params_file_is_said_to_be_ok(tmp_path: Path) -> None:
    path = write(tmp_path, "socialnav:\n  ros__parameters:\n    planner: traditional\n")
    result = CliRunner().invoke(app, ["ros2", "--params", str(path)])
    assert f"{path}: parameters OK" in result.output


def test_ros2_command_checks_the_params_file_first(tmp_path: Path) -> None:
    path = write(tmp_path, "socialnav:\n  ros__parameters:\n    max_vel_x: -1.0\n")
    result = CliRunner().invoke(app, ["ros2", "--params", str(path)])
    assert result.exit_code == 2 and "max_vel_x" in result.output


def test_readme_params_example_is_a_valid_params_file(tmp_path: Path) -> None:
    import re

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    section = readme.split("## On a robot", 1)[1].split("\n## ", 1)[0]
    (block,) = re.findall(r"```yaml\n(.*?)```", section, re.S)
    values = load_params_file(write(tmp_path, block))
    assert values["planner"] == "paccet" and robot_from_params(values).name == "pioneer"
    assert "socialnav ros2 --params" in section and "pip install 'socialnav[ros]'" in section

"""The navground behaviour plugin, as a navground user meets it: the entry point, the YAML
properties, navground's limits and targets, and ``navground_py run`` on Cross and Corridor."""

from __future__ import annotations

import dataclasses
import importlib.metadata
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from navground import core, sim

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import points_in_polygon
from socialnav.core.robot import PR2
from socialnav.integrations.navground_behavior import (
    BODY_SIDES,
    ROBOT_FIELDS,
    SocialNavBehavior,
    covering_footprint,
)
from socialnav.integrations.planner_options import our_planners, planner_options
from socialnav.planner.local_planner import LocalPlannerParams
from socialnav.sim.controller import CONTROLLERS, controller_names

h5py = pytest.importorskip("h5py")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "navground"


def _cli() -> list[str]:
    script = Path(sys.executable).with_name("navground_py")
    return [str(script)] if script.exists() else [sys.executable, "-m", "navground.sim"]


def _robot_group(behavior: dict, kinematics: dict | None = None, **extra: object) -> dict:
    return {
        "number": 1,
        "type": "robot",
        "radius": 0.46,
        "kinematics": kinematics or {"type": "Omni", "max_speed": 0.63, "max_angular_speed": 1.0},
        "behavior": {"type": "SocialNav", **behavior},
        "state_estimation": {"type": "Bounded", "range": 5.0},
        **extra,
    }


_ALIVE: list[sim.Experiment] = []  # a run's world lives as long as its experiment


def _run(experiment: dict, seed: int = 1) -> sim.ExperimentalRun:
    core.load_plugins()
    loaded = sim.load_experiment(yaml.safe_dump(experiment))
    _ALIVE[:] = [loaded]
    return loaded.run_once(seed=seed)


def _walls_and_point(target: tuple[float, float], steps: int = 60, **behavior: object) -> dict:
    return {
        "steps": steps,
        "time_step": 0.1,
        "record_pose": True,
        "record_twist": True,
        "scenario": {
            "walls": [{"line": [[-1, -1.5], [20, -1.5]]}, {"line": [[-1, 1.5], [20, 1.5]]}],
            "groups": [
                _robot_group(
                    behavior,
                    task={
                        "type": "Waypoints",
                        "waypoints": [list(target)],
                        "tolerance": 0.2,
                        "loop": False,
                    },
                    position=[0.0, 0.0],
                    orientation=0.0,
                )
            ],
        },
    }


# -- registration ------------------------------------------------------------------------------


def test_the_entry_point_names_the_class_and_navground_lists_the_behaviour() -> None:
    (ep,) = [
        e
        for e in importlib.metadata.entry_points(group="navground_behaviors")
        if e.name == "socialnav"
    ]
    assert ep.load() is SocialNavBehavior and SocialNavBehavior._type == "SocialNav"
    out = subprocess.run([*_cli(), "plugins"], capture_output=True, text=True, check=True)
    assert "SocialNav [Python]" in out.stdout
    assert "not been registered" not in out.stdout + out.stderr


def test_loading_only_the_entry_point_registers_every_planner_of_ours() -> None:
    # What navground does in a fresh process: load the entry point, nothing else of ours.
    code = (
        "import importlib.metadata as m\n"
        "[e.load() for e in m.entry_points(group='navground_behaviors') if e.name == 'socialnav']\n"
        "from socialnav.integrations.planner_options import our_planners\n"
        "print(','.join(our_planners()))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    names = out.stdout.strip().split(",")
    ours = [n for n in controller_names() if CONTROLLERS.get(n).kind != "navground"]
    assert names == ours
    assert {"traditional", "proxemic_layer", "weighted_social", "paccet_paper", "paccet"} <= set(
        names
    )
    assert "go_to_goal" in names
    assert not {"orca", "hl", "social_force"} & set(names)  # navground's own behaviours


def test_every_planner_option_and_robot_field_is_a_typed_property_with_its_default() -> None:
    core.load_plugins()
    props = core.Behavior.type_properties["SocialNav"]
    hints = {f.name: f for f in dataclasses.fields(LocalPlannerParams)}
    defaults = LocalPlannerParams()
    type_names = {bool: "bool", int: "int", float: "float", str: "str"}
    for name in hints:
        assert name in props, name
        value = getattr(defaults, name)
        assert props[name].type_name == type_names[type(value)], name
        if isinstance(value, float):
            assert props[name].default_value == pytest.approx(value, rel=1e-6)
        else:
            assert props[name].default_value == value
    for name in ROBOT_FIELDS:
        assert props[name].type_name == "float" and math.isnan(props[name].default_value)
    assert props["planner"].default_value == "paccet" and props["robot"].default_value == "pr2"
    assert props["footprint"].type_name == "[vector]"
    for name in ("gain", "angular_gain", "turn_in_place"):  # go_to_goal's options
        assert name in props
    # the property says which planners take the option
    assert "paccet" in props["sim_time"].description
    assert "go_to_goal" in props["gain"].description
    assert set(planner_options()) <= set(props)


def test_yaml_values_reach_the_planner_and_the_robot_model() -> None:
    experiment = _walls_and_point(
        (3.0, 0.0),
        steps=3,
        planner="traditional",
        robot="pioneer",
        sim_time=1.0,
        vx_samples=4,
        acc_lim_x=0.7,
        footprint=[[0.3, 0.2], [-0.3, 0.2], [-0.3, -0.2], [0.3, -0.2]],
    )
    experiment["scenario"]["groups"][0]["kinematics"] = {
        "type": "2WDiff",
        "wheel_axis": 0.4,
        "max_speed": 0.8,
    }
    experiment["scenario"]["groups"][0]["radius"] = 0.2  # the footprint covers the disc
    run = _run(experiment)
    behavior = run.world.agents[0].behavior
    controller = behavior.controller
    assert controller.preset == "traditional"
    assert controller.params.sim_time == 1.0 and controller.params.vx_samples == 4
    # defaults stay the preset's; the period is navground's time step
    assert controller.params.heading_scale == LocalPlannerParams().heading_scale
    assert controller.params.controller_period == pytest.approx(0.1)
    model = behavior.robot_model
    assert model.name == "pioneer" and not model.holonomic and model.acc_lim_x == 0.7
    assert model.max_vel_y == 0.0
    np.testing.assert_allclose(model.polygon[0], [0.3, 0.2])
    assert "sim_time: 1" in core.dump(behavior)


def test_the_planned_footprint_covers_navgrounds_disc_body() -> None:
    """navground collides discs: a footprint narrower than the agent's radius (the PR2 square,
    sides at 0.325 m, in a 0.46 m disc) let the planner drive past a person side-on inside the
    disc (a collision in the Cross example); the planned footprint now contains the disc."""
    experiment = _walls_and_point((3.0, 0.0), steps=2, planner="traditional", robot="pr2")
    behavior = _run(experiment).world.agents[0].behavior
    model = behavior.robot_model
    assert model.inscribed_radius >= 0.46 - 1e-6  # the disc is inside the footprint
    assert np.all(points_in_polygon(PR2.polygon * 0.999, model.polygon))  # and the square
    assert model.circumscribed_radius <= 0.46 / np.cos(np.pi / BODY_SIDES) + 1e-6
    assert covering_footprint(PR2.polygon, 0.3) is None  # a disc inside the square: as given
    assert covering_footprint(PR2.polygon, 0.0) is None


def test_an_invalid_option_is_an_error_naming_the_property() -> None:
    behavior = core.load_behavior("{type: SocialNav, planner: traditional, sim_time: -1}")
    behavior.kinematics = core.kinematics.OmnidirectionalKinematics(0.6, 1.0)
    behavior.target = core.Target.Point((2.0, 0.0))
    with pytest.raises(ConfigurationError, match=r"SocialNav behaviour.*sim_time"):
        behavior.compute_cmd_internal(0.1)
    behavior = core.load_behavior("{type: SocialNav, planner: pacet}")
    behavior.kinematics = core.kinematics.OmnidirectionalKinematics(0.6, 1.0)
    behavior.target = core.Target.Point((2.0, 0.0))
    with pytest.raises(ConfigurationError, match="Did you mean 'paccet'"):
        behavior.compute_cmd_internal(0.1)


# -- limits and targets --------------------------------------------------------------------------


def _speeds(run: sim.ExperimentalRun) -> tuple[np.ndarray, np.ndarray]:
    twists = np.asarray(run.twists)[:, 0]  # (steps, 3) world frame
    return np.hypot(twists[:, 0], twists[:, 1]), np.abs(twists[:, 2])


@pytest.mark.parametrize("planner", ["paccet", "go_to_goal"])
@pytest.mark.parametrize("where", ["kinematics", "behavior"])
def test_navground_speed_limits_bind_the_planner(planner: str, where: str) -> None:
    # navground's limits: the kinematics' max_speed, or the behaviour's optimal_speed.
    behavior: dict[str, object] = {"optimal_speed": 0.3} if where == "behavior" else {}
    experiment = _walls_and_point((6.0, 0.0), steps=80, planner=planner, **behavior)
    kinematics = experiment["scenario"]["groups"][0]["kinematics"]
    kinematics["max_angular_speed"] = 0.4
    if where == "kinematics":
        kinematics["max_speed"] = 0.3
    run = _run(experiment)
    speed, turn = _speeds(run)
    assert speed.max() <= 0.3 + 1e-4 and turn.max() <= 0.4 + 1e-4
    assert speed.max() > 0.25  # it did drive, at the limit
    model = run.world.agents[0].behavior.robot_model
    assert model.max_vel_x == pytest.approx(0.3) and model.max_vel_theta == pytest.approx(0.4)
    assert model.acc_lim_x == PR2.acc_lim_x


def test_a_differential_drive_is_never_commanded_sideways() -> None:
    experiment = _walls_and_point((6.0, 1.0), steps=80, planner="paccet", robot="pioneer")
    group = experiment["scenario"]["groups"][0]
    group["kinematics"] = {"type": "2WDiff", "wheel_axis": 0.38, "max_speed": 0.6}
    experiment["record_cmd"] = True
    run = _run(experiment)
    cmds = np.asarray(run.commands)[:, 0]  # body frame (vx, vy, wz), as commanded
    np.testing.assert_allclose(cmds[:, 1], 0.0, atol=1e-6)
    assert np.asarray(run.poses)[-1, 0, 0] > 2.0  # and it drove
    model = run.world.agents[0].behavior.robot_model
    assert not model.holonomic and model.max_vel_y == 0.0 and model.acc_lim_y == 0.0


def test_a_target_speed_caps_the_planner() -> None:
    behavior = core.load_behavior("{type: SocialNav, planner: paccet}")
    behavior.kinematics = core.kinematics.OmnidirectionalKinematics(0.63, 1.0)
    behavior.target = core.Target(position=(3.0, 0.0), speed=0.25)
    assert behavior.effective_robot().max_vel_x == pytest.approx(0.25)
    behavior.target = core.Target(position=(3.0, 0.0))
    assert behavior.effective_robot().max_vel_x == pytest.approx(PR2.max_vel_x)


def test_a_point_target_is_reached_within_the_task_tolerance() -> None:
    run = _run(_walls_and_point((3.0, 0.5), steps=120, planner="paccet"))
    agent = run.world.agents[0]
    assert agent.task.done()
    assert np.hypot(*(np.asarray(agent.position) - [3.0, 0.5])) < 0.2


def test_a_direction_target_makes_the_robot_drive_along_it() -> None:
    # navground's Corridor scenario gives Direction targets; the robot used to stand still.
    experiment = {
        "steps": 100,
        "time_step": 0.1,
        "record_pose": True,
        "scenario": {
            "type": "Corridor",
            "length": 10.0,
            "width": 3.0,
            "groups": [_robot_group({"planner": "paccet"})],
        },
    }
    run = _run(experiment, seed=3)
    travelled = _progress_along_x(np.asarray(run.poses)[:, 0, 0], 10.0)
    direction = run.world.agents[0].behavior.target.direction
    assert np.sign(travelled) == np.sign(direction[0])
    assert abs(travelled) > 3.5  # ~0.55 m/s for 10 s, after the start


def _progress_along_x(x: np.ndarray, period: float) -> float:
    """Signed distance (m) travelled along x in a world periodic in x with ``period``."""
    dx = np.diff(x)
    dx[dx < -period / 2] += period
    dx[dx > period / 2] -= period
    return float(dx.sum())


# -- navground's own command line ----------------------------------------------------------------


def _navground_run(path: Path, tmp_path: Path) -> h5py.Group:
    out = tmp_path / "out"
    out.mkdir()
    subprocess.run(
        [*_cli(), "run", str(path), "--save_directory", str(out)],
        check=True,
        capture_output=True,
        text=True,
        timeout=600,
    )
    (data,) = out.glob("*/data.h5")
    return h5py.File(data, "r")["run_0"]


def _robot_index(group: h5py.Group, experiment: dict) -> int:
    groups = experiment["scenario"]["groups"]
    robot = [i for i, g in enumerate(groups) if g["behavior"]["type"] == "SocialNav"]
    assert robot == [len(groups) - 1]  # the robot is the last group: the last uid
    return sum(g["number"] for g in groups) - 1


def _robot_collisions(group: h5py.Group, uid: int) -> int:
    collisions = np.asarray(group["collisions"])
    return int(((collisions[:, 1] == uid) | (collisions[:, 2] == uid)).sum())


def _run_example(name: str, tmp_path: Path) -> tuple[h5py.Group, int, dict]:
    path = EXAMPLES / name
    experiment = yaml.safe_load(path.read_text())
    run = _navground_run(path, tmp_path)
    return run, _robot_index(run, experiment), experiment


@pytest.mark.slow
def test_navground_run_cross_reaches_its_targets_without_collision(tmp_path: Path) -> None:
    run, uid, _ = _run_example("cross.yaml", tmp_path)
    events = np.asarray(run["task_events"][str(uid)])  # one row per target the task set
    reached = events[events[:, 0] > 0]
    assert len(reached) >= 1, "the SocialNav robot never reached a Cross target"
    assert _robot_collisions(run, uid) == 0


@pytest.mark.slow
def test_navground_run_corridor_crosses_it_without_collision(tmp_path: Path) -> None:
    run, uid, experiment = _run_example("corridor.yaml", tmp_path)
    length = experiment["scenario"]["length"]
    travelled = _progress_along_x(np.asarray(run["poses"])[:, uid, 0], length)
    assert abs(travelled) >= length, "the SocialNav robot did not cross the corridor"
    assert _robot_collisions(run, uid) == 0


def test_every_planner_of_ours_runs_by_name_from_yaml() -> None:
    for planner in our_planners():
        assert planner in CONTROLLERS
        run = _run(_walls_and_point((2.0, 0.0), steps=2, planner=planner))
        assert run.world.agents[0].behavior.controller is not None, planner


def test_keywords_bound_by_a_registry_entry_are_not_options() -> None:
    # straight_line is go_to_goal with its gain bound: the gain belongs to go_to_goal alone
    from socialnav.integrations.planner_options import planner_options

    options = planner_options()
    assert options["gain"].planners == ("go_to_goal",)
    assert options["gain"].default == 1.0
    assert "straight_line" in options["angular_gain"].planners

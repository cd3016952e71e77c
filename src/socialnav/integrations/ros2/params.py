"""The node's parameters: names, types, ranges and descriptions, and the params-file reader.

No ROS imports: the same table declares the ROS parameters in the node (types, ranges,
descriptions, read-only flags) and validates a params file in plain Python, so a bad file gives
an error naming the file and the parameter before any middleware starts.

Names follow Nav2 where Nav2 has the concept (``controller_frequency``, ``global_frame``,
``robot_base_frame``, ``odom_topic`` semantics via remapping, ``enable_stamped_cmd_vel``,
``footprint``, ``inflation_radius``, ``cost_scaling_factor``) and ROS ``dwa_local_planner`` for
the planner (``max_vel_x``, ``acc_lim_x``, ``path_distance_bias``, ``xy_goal_tolerance``, …:
the fields of :class:`~socialnav.planner.local_planner.LocalPlannerParams` and
:class:`~socialnav.core.robot.RobotModel`). Units: SI (m, s, rad, m/s, rad/s, Hz).

A params file is Nav2's layout (``ros2 run … --ros-args --params-file``)::

    socialnav:
      ros__parameters:
        planner: paccet
        robot_model: pioneer
        max_vel_x: 0.5

The node-name key may also be ``/**`` (every node), as rcl accepts.
"""

from __future__ import annotations

import ast
import dataclasses
import difflib
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import ROBOT_MODELS, RobotModel
from socialnav.planner.local_planner import LocalPlannerParams
from socialnav.planner.presets import PRESETS

__all__ = [
    "DEFAULT_NODE_NAME",
    "DYNAMIC",
    "ParamSpec",
    "load_params_file",
    "local_planner_params",
    "param_specs",
    "parse_footprint",
    "robot_from_params",
    "validate_value",
]

DEFAULT_NODE_NAME = "socialnav"
MAX_PARAMS_FILE_BYTES = 1_000_000  # a params file is a few kB; refuse to parse anything huge

Value = bool | int | float | str | list[float]


@dataclass(frozen=True)
class ParamSpec:
    """One parameter: ``default`` fixes its type (bool, int, float, str or list of floats);
    ``min``/``max`` bound numbers (inclusive); ``choices`` bound strings; ``dynamic`` ones may be
    changed while the node runs (the others are read-only after start)."""

    name: str
    default: Value
    description: str
    min: float | None = None
    max: float | None = None
    choices: tuple[str, ...] = ()
    dynamic: bool = False

    @property
    def kind(self) -> type:
        return list if isinstance(self.default, list) else type(self.default)


# Weights and tolerances: changeable at run time through the ROS parameter callbacks.
DYNAMIC = frozenset(
    {
        "path_distance_bias",
        "goal_distance_bias",
        "occdist_scale",
        "heading_scale",
        "xy_goal_tolerance",
        "yaw_goal_tolerance",
    }
)

# Ranges and descriptions of LocalPlannerParams' fields (ROS dwa_local_planner names).
_PLANNER: dict[str, tuple[float | None, float | None, str]] = {
    "vx_samples": (1, 50, "samples of forward velocity in the dynamic window"),
    "vy_samples": (1, 50, "samples of lateral velocity (holonomic robots)"),
    "vth_samples": (1, 100, "samples of angular velocity"),
    "sim_time": (0.1, 10.0, "s, forward simulation horizon of each sampled twist"),
    "sim_granularity": (0.001, 1.0, "m, translational step of the forward simulation"),
    "angular_sim_granularity": (0.001, 1.0, "rad, angular step of the forward simulation"),
    "xy_goal_tolerance": (0.01, 5.0, "m, goal position tolerance"),
    "yaw_goal_tolerance": (0.01, math.pi, "rad, goal orientation tolerance"),
    "latch_xy_goal_tolerance": (None, None, "once inside xy tolerance, only rotate"),
    "stop_at_goal": (None, None, "rollouts that reach the goal stand on it (no slow approach)"),
    "arrival_time_scale": (0.0, 100.0, "weight per s of the arrival time when stop_at_goal"),
    "trans_stopped_vel": (0.0, 1.0, "m/s, below this the robot counts as stopped"),
    "theta_stopped_vel": (0.0, 1.0, "rad/s, below this the robot counts as not turning"),
    "path_distance_bias": (0.0, 100.0, "weight of the distance to the global path"),
    "goal_distance_bias": (0.0, 100.0, "weight of the distance to the local goal"),
    "goal_distance_measure": (
        None,
        None,
        "bfs (free-space distance to the local goal, ROS) or along_plan (plan length to go)",
    ),
    "occdist_scale": (0.0, 100.0, "weight of the costmap cost along the trajectory"),
    "heading_scale": (0.0, 100.0, "weight of the heading error to the path ahead, per rad"),
    "heading_lookahead": (0.0, 5.0, "m, how far along the path the heading critic looks"),
    "heading_goal_align": (
        None,
        None,
        "holonomic bases only: turn to the goal's yaw on the way in, within reach of the goal",
    ),
    "footprint_check": (None, None, "check the footprint polygon, not only its centre"),
    "rollout_dtype": (None, None, "float64 or float32 rollouts (float32 ~1.5x faster)"),
    "oscillation_reset_dist": (0.0, 5.0, "m, motion that clears the oscillation guard"),
    "oscillation_reset_angle": (0.0, math.pi, "rad, rotation that clears the oscillation guard"),
}
# The string parameters' allowed values.
_CHOICES = {
    "rollout_dtype": ("float64", "float32"),
    "goal_distance_measure": ("bfs", "along_plan"),
}
# controller_period is set from the node's controller_frequency (Nav2's name for it).
_DERIVED = {"controller_period"}

_ROBOT: dict[str, tuple[float, float, str]] = {
    "max_vel_x": (0.0, 10.0, "m/s, maximum forward velocity"),
    "min_vel_x": (-10.0, 0.0, "m/s, minimum forward velocity (negative = reversing)"),
    "max_vel_y": (0.0, 10.0, "m/s, maximum lateral velocity (0 for differential drive)"),
    "max_vel_theta": (0.0, 10.0, "rad/s, maximum angular velocity"),
    "acc_lim_x": (0.0, 20.0, "m/s^2, forward acceleration limit"),
    "acc_lim_y": (0.0, 20.0, "m/s^2, lateral acceleration limit"),
    "acc_lim_theta": (0.0, 40.0, "rad/s^2, angular acceleration limit"),
    "min_vel_trans": (0.0, 1.0, "m/s, smallest translational speed sampled"),
    "min_vel_theta": (0.0, 1.0, "rad/s, smallest angular speed sampled"),
    "min_in_place_vel_theta": (0.0, 5.0, "rad/s, smallest in-place rotation speed"),
}

_NODE: tuple[ParamSpec, ...] = (
    ParamSpec(
        "planner",
        "paccet",
        "planner preset: traditional, proxemic_layer, weighted_social, paccet_paper, paccet",
        choices=tuple(PRESETS.names()),
    ),
    ParamSpec(
        "robot_model",
        "pioneer",
        "robot model whose kinematics, footprint and limits are the defaults",
        choices=tuple(ROBOT_MODELS),
    ),
    ParamSpec(
        "footprint",
        "",
        'footprint polygon "[[x, y], ...]" m in the base frame, Nav2 syntax; "" = the model\'s',
    ),
    ParamSpec("controller_frequency", 10.0, "Hz, control cycles per second", 1.0, 50.0),
    ParamSpec(
        "replan_mode",
        "deferred",
        "global replanning: deferred (on a worker, used 2 cycles later, planned from where the "
        "robot will be), threaded (used once done) or inline (inside the control cycle)",
        choices=("deferred", "threaded", "inline"),
    ),
    ParamSpec("global_frame", "map", "frame of the map, goals, people and plans"),
    ParamSpec("odom_frame", "odom", "frame of the odometry when it is not the global frame"),
    ParamSpec("robot_base_frame", "base_link", "the robot's body frame"),
    ParamSpec(
        "odom_to_global",
        [0.0, 0.0, 0.0],
        "[x m, y m, yaw rad] pose of odom_frame in global_frame (no tf listener: fixed)",
    ),
    ParamSpec("enable_stamped_cmd_vel", False, "publish geometry_msgs/TwistStamped on cmd_vel"),
    ParamSpec("odom_timeout", 0.5, "s, odometry older than this stops the robot", 0.01, 60.0),
    ParamSpec("people_timeout", 1.0, "s, people older than this stop the robot", 0.01, 60.0),
    ParamSpec("require_people", True, "stop when no people message arrived within the timeout"),
    ParamSpec(
        "people_gate", 1.0, "m, farthest a detection may be from a track's prediction", 0.05, 10.0
    ),
    ParamSpec("people_track_timeout", 1.0, "s, a person unseen this long is forgotten", 0.05, 60.0),
    ParamSpec(
        "people_max_speed", 3.0, "m/s, estimated person speeds are clipped to this", 0.1, 20.0
    ),
    ParamSpec("person_radius", 0.25, "m, radius of every detected person", 0.05, 2.0),
    ParamSpec("inflation_radius", 0.55, "m, costmap inflation radius", 0.0, 10.0),
    ParamSpec("cost_scaling_factor", 10.0, "costmap inflation decay rate, 1/m", 0.01, 100.0),
    ParamSpec(
        "social_context_file",
        "",
        'YAML file of groups, queues and artworks by member position; "" = none',
    ),
    ParamSpec(
        "social_match_radius",
        0.75,
        "m, farthest a tracked person may stand from a structure's member position",
        0.05,
        5.0,
    ),
    ParamSpec(
        "detect_social_context",
        True,
        "without social_context_file: groups and queues from the context estimator",
    ),
    ParamSpec("publish_candidates", True, "publish every candidate on socialnav/candidates"),
    ParamSpec("autostart", True, "configure and activate at start (retry activation every second)"),
)


def _planner_specs(defaults: LocalPlannerParams) -> list[ParamSpec]:
    out = []
    for f in dataclasses.fields(LocalPlannerParams):
        if f.name in _DERIVED:
            continue
        if f.name not in _PLANNER:
            raise ConfigurationError(f"LocalPlannerParams.{f.name} has no ROS parameter entry")
        lo, hi, text = _PLANNER[f.name]
        default = getattr(defaults, f.name)
        choices = _CHOICES.get(f.name, ())
        out.append(ParamSpec(f.name, default, text, lo, hi, choices, f.name in DYNAMIC))
    return out


def planner_defaults(planner: str) -> LocalPlannerParams:
    """The local-planner parameters ``planner``'s preset runs with (``PlannerPreset.params``;
    ``LocalPlannerParams()`` for a preset without its own, or an unknown name): the node's
    defaults, so a robot runs the configuration the suites measured."""
    preset = PRESETS.get(planner) if planner in PRESETS.names() else None
    params = preset.params if preset is not None else None
    return params if params is not None else LocalPlannerParams()


def param_specs(robot_model: str = "pioneer", planner: str = "paccet") -> list[ParamSpec]:
    """Every parameter the node declares; robot limits default to ``robot_model``'s, the
    local planner's parameters to ``planner``'s preset (:func:`planner_defaults`)."""
    robot = ROBOT_MODELS.get(robot_model, ROBOT_MODELS["pioneer"])
    specs = [dataclasses.replace(s, default=planner) if s.name == "planner" else s for s in _NODE]
    for name, (lo, hi, text) in _ROBOT.items():
        specs.append(ParamSpec(name, float(getattr(robot, name)), text, lo, hi))
    specs += _planner_specs(planner_defaults(planner))
    return specs


def validate_value(spec: ParamSpec, value: Any) -> Value:
    """``value`` converted to ``spec``'s type, or :class:`ConfigurationError` saying why."""
    kind = spec.kind
    if kind is bool:
        if not isinstance(value, bool):
            raise ConfigurationError(f"{spec.name}: expected a bool, got {value!r}")
        return value
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigurationError(f"{spec.name}: expected an integer, got {value!r}")
        out: Value = value
    elif kind is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigurationError(f"{spec.name}: expected a number, got {value!r}")
        if not math.isfinite(value):
            raise ConfigurationError(f"{spec.name}: must be finite, got {value!r}")
        out = float(value)
    elif kind is str:
        if not isinstance(value, str):
            raise ConfigurationError(f"{spec.name}: expected a string, got {value!r}")
        if spec.choices and value not in spec.choices:
            raise ConfigurationError(
                f"{spec.name}: {value!r} is not one of {', '.join(spec.choices)}"
            )
        if spec.name == "footprint" and value:
            parse_footprint(value)
        return value
    else:
        if not isinstance(value, list) or not all(
            isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
            for v in value
        ):
            raise ConfigurationError(
                f"{spec.name}: expected a list of finite numbers, got {value!r}"
            )
        if len(value) != len(spec.default):  # type: ignore[arg-type]
            raise ConfigurationError(
                f"{spec.name}: expected {len(spec.default)} numbers, got {len(value)}"  # type: ignore[arg-type]
            )
        return [float(v) for v in value]
    assert isinstance(out, int | float)
    if (spec.min is not None and out < spec.min) or (spec.max is not None and out > spec.max):
        raise ConfigurationError(f"{spec.name}: {out} is outside [{spec.min}, {spec.max}]")
    return out


def parse_footprint(text: str) -> tuple[tuple[float, float], ...]:
    """A Nav2 footprint string ``"[[x, y], [x, y], ...]"`` (m) → vertices; at least 3."""
    try:
        points = ast.literal_eval(text)
        verts = tuple((float(x), float(y)) for x, y in points)
    except (ValueError, TypeError, SyntaxError) as exc:
        raise ConfigurationError(f"footprint: cannot read {text!r} as [[x, y], ...]") from exc
    if len(verts) < 3 or not all(math.isfinite(c) for v in verts for c in v):
        raise ConfigurationError(f"footprint: needs at least 3 finite points, got {text!r}")
    return verts


def _flatten(prefix: str, node: Any, out: dict[str, Any]) -> None:
    if isinstance(node, dict):
        for key, value in node.items():
            _flatten(f"{prefix}.{key}" if prefix else str(key), value, out)
    else:
        out[prefix] = node


def read_yaml_file(path: Path, what: str, max_bytes: int = MAX_PARAMS_FILE_BYTES) -> Any:
    """The YAML document in ``path``; :class:`ConfigurationError` (naming the file) when it is
    missing, larger than ``max_bytes`` (refused before parsing) or not YAML."""
    where = str(path)
    if not path.is_file():
        raise ConfigurationError(f"{where}: no such {what}")
    if path.stat().st_size > max_bytes:
        raise ConfigurationError(f"{where}: larger than {max_bytes} bytes")
    try:
        return yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError) as exc:
        raise ConfigurationError(f"{where}: not valid YAML ({exc})") from None


def load_params_file(path: str | Path, node_name: str = DEFAULT_NODE_NAME) -> dict[str, Value]:
    """The validated parameters of ``node_name`` in a Nav2-style params file.

    Entries under ``/**`` apply first, then those under the node's own name (with or without
    a leading ``/``). Unknown names, wrong types and out-of-range values raise
    :class:`ConfigurationError` naming the file and the parameter.
    """
    path = Path(path)
    where = str(path)
    doc = read_yaml_file(path, "params file")
    if not isinstance(doc, dict):
        raise ConfigurationError(f"{where}: expected a mapping '<node>: ros__parameters: ...'")
    sections = [k for k in ("/**", node_name, f"/{node_name}") if k in doc]
    if not sections:
        raise ConfigurationError(
            f"{where}: no section for node {node_name!r} "
            f"(top-level keys: {', '.join(map(str, doc))})"
        )
    raw: dict[str, Any] = {}
    for key in sections:
        section = doc[key]
        if not isinstance(section, dict) or not isinstance(section.get("ros__parameters"), dict):
            raise ConfigurationError(f"{where}: {key}: expected a 'ros__parameters' mapping")
        _flatten("", section["ros__parameters"], raw)
    model, planner = raw.get("robot_model", "pioneer"), raw.get("planner", "paccet")
    specs = {
        s.name: s
        for s in param_specs(
            model if isinstance(model, str) else "pioneer",
            planner if isinstance(planner, str) else "paccet",
        )
    }
    out: dict[str, Value] = {}
    for name, value in raw.items():
        if name not in specs:
            close = difflib.get_close_matches(name, specs, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ConfigurationError(f"{where}: {node_name}.ros__parameters.{name}: unknown{hint}")
        try:
            out[name] = validate_value(specs[name], value)
        except ConfigurationError as exc:
            raise ConfigurationError(f"{where}: {node_name}.ros__parameters.{exc}") from None
    try:
        merged = {s: out.get(s, specs[s].default) for s in specs}
        robot_from_params(merged)
        local_planner_params(merged)
    except ConfigurationError as exc:
        raise ConfigurationError(f"{where}: {exc}") from None
    return out


def robot_from_params(values: dict[str, Any]) -> RobotModel:
    """The :class:`RobotModel` of ``robot_model`` with the limits and footprint in ``values``."""
    base = ROBOT_MODELS[str(values.get("robot_model", "pioneer"))]
    changes: dict[str, Any] = {k: float(values[k]) for k in _ROBOT if k in values}
    if values.get("footprint"):
        changes["footprint"] = parse_footprint(str(values["footprint"]))
    robot = dataclasses.replace(base, **changes)
    if robot.min_vel_x > robot.max_vel_x:
        raise ConfigurationError("min_vel_x must not exceed max_vel_x")
    if not robot.holonomic and robot.max_vel_y != 0:
        raise ConfigurationError(f"max_vel_y must be 0 for the differential-drive {base.name}")
    return robot


def local_planner_params(values: dict[str, Any]) -> LocalPlannerParams:
    """:class:`LocalPlannerParams` from the parameter ``values``; missing ones are the
    ``planner`` preset's (:func:`planner_defaults`, ``paccet`` when ``planner`` is missing)."""
    names = {f.name for f in dataclasses.fields(LocalPlannerParams)} - _DERIVED
    kwargs = {k: values[k] for k in names if k in values}
    if "controller_frequency" in values:
        kwargs["controller_period"] = 1.0 / float(values["controller_frequency"])
    return dataclasses.replace(planner_defaults(str(values.get("planner", "paccet"))), **kwargs)

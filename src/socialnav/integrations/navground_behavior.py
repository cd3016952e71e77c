"""socialnav planners as a navground behaviour: ``type: SocialNav`` in navground YAML.

navground finds the behaviour through the ``navground_behaviors`` entry point
``socialnav.integrations.navground_behavior:SocialNavBehavior`` (navground 0.7 loads the
``module:Class`` object and reads its registered type name), so ``navground_py run``,
``navground_py info`` and navground's Python API all know it::

    behavior:
      type: SocialNav
      planner: paccet          # any planner of ours: paccet, traditional, go_to_goal, …
      robot: pr2               # the socialnav robot model: footprint, accelerations, limits
      sim_time: 1.7            # every planner option is a property (LocalPlannerParams, …)

*Properties* (all typed, with defaults; ``navground_py info --behaviors --properties`` lists
them): ``planner`` [str], ``robot`` [str], ``footprint`` [list of vectors, body frame, m; empty =
the model's], the robot model's numbers (``max_vel_x``, ``acc_lim_x``, …; ``.nan`` = the model's),
``direction_horizon`` [m], and every option of every planner of ours
(:func:`socialnav.integrations.planner_options.planner_options`; an option a planner does not take
is ignored by it). ``controller_period`` defaults to navground's time step.

What is honoured from navground:

- *speed limits*: the planner's box limits are capped by the behaviour's ``max_speed`` (which
  navground already caps by the kinematics), the target's speed (``get_target_speed``: the task's
  speed, else ``optimal_speed``), ``max_angular_speed`` and, for a differential drive, the
  kinematics' ``max_backward_speed``; the kinematics decides holonomic (``dof() == 3``) or not;
  the command is finally made feasible by navground (``feasible_twist``: the Omni speed disc,
  the wheel-speed coupling);
- *targets*: a point target (``position``, optional ``orientation``; without one any final yaw is
  accepted, the goal is reached within ``min(xy_goal_tolerance, position_tolerance)``) is driven
  to by the planner; a direction target (navground's Corridor scenario) is followed through a goal
  ``direction_horizon`` metres ahead along it, moved forward whenever the robot has covered half
  of it (or was wrapped by a periodic world); any other target (a velocity, an orientation
  alone) or none: the robot stops.

What the planner sees here differs from ``socialnav.sim.runner`` (the scenario's ground truth):
people are navground's neighbours (no groups, queues or artworks are known), walls and disc
obstacles are those the agent's state estimation reports when the goal is set, and the planner is
rebuilt whenever the goal moves (a new waypoint, a moved direction goal) or a limit changes.
"""

from __future__ import annotations

import dataclasses
import math
import types
from typing import Any

import numpy as np
from navground import core
from scipy.spatial import ConvexHull

from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import ROBOT_MODELS, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.integrations.planner_options import build_planner, our_planners, planner_options
from socialnav.sim.engine import ControllerBehavior, pose_of
from socialnav.sim.scenario import Scenario

__all__ = ["BODY_SIDES", "ROBOT_FIELDS", "SocialNavBehavior", "covering_footprint"]

#: RobotModel numbers settable as properties (``nan``: the named model's value)
ROBOT_FIELDS = (
    "max_vel_x",
    "min_vel_x",
    "max_vel_y",
    "max_vel_theta",
    "acc_lim_x",
    "acc_lim_y",
    "acc_lim_theta",
    "min_vel_trans",
    "min_vel_theta",
    "min_in_place_vel_theta",
)
DEFAULT_DIRECTION_HORIZON = 4.0
# The goal of a point target counts as moved beyond this (m, rad): navground stores float32.
MOVED = 1e-4


def _make_property(name: str, kind: Any, default: Any, description: str) -> property:
    def fget(self: Any) -> Any:
        return self._values.get(name, default)

    fget.__annotations__ = {"return": kind}
    fget.__name__ = name

    def fset(self: Any, value: Any) -> None:
        if kind is float:
            # navground passes YAML numbers as float32: 0.7 arrives as 0.699999988; keep the
            # shortest decimal that float32 value stands for (what the user wrote).
            value = float(str(np.float32(value)))
        self._values[name] = value
        self._changed()

    return property(core.register(default, description)(fget), fset)


def _properties() -> dict[str, property]:
    props = {
        "planner": _make_property(
            "planner", str, "paccet", f"planner of ours: {', '.join(our_planners())}"
        ),
        "robot": _make_property(
            "robot", str, "pr2", f"socialnav robot model: {', '.join(ROBOT_MODELS)}"
        ),
        "footprint": _make_property(
            "footprint",
            list[core.Vector2],
            [],
            "footprint polygon (body frame, m); empty: the robot model's",
        ),
        "direction_horizon": _make_property(
            "direction_horizon",
            float,
            DEFAULT_DIRECTION_HORIZON,
            "direction targets: distance (m) of the goal ahead along the direction",
        ),
    }
    for name in ROBOT_FIELDS:
        props[name] = _make_property(
            name, float, math.nan, f"robot model {name} (SI units); nan: the model's value"
        )
    for name, option in planner_options().items():
        if name in props:
            raise ConfigurationError(f"planner option {name!r} clashes with a behaviour property")
        props[name] = _make_property(name, option.type, option.default, option.description)
    return props


#: Sides of the polygon that stands in for navground's disc body in the planner's footprint.
BODY_SIDES = 16


def covering_footprint(
    polygon: np.ndarray, radius: float
) -> tuple[tuple[float, float], ...] | None:
    """The footprint covering both the model's ``polygon (V, 2)`` (body frame, m) and
    navground's disc body of ``radius`` (m) centred on the agent, or ``None`` when the polygon
    already contains the disc (``radius`` at most its inscribed radius, or 0).

    navground checks collisions between discs: an agent of radius r collides whenever a person
    comes within r, whatever footprint the planner keeps clear. A PR2 square (sides at 0.325 m)
    in a 0.46 m disc let the planner pass a person side-on 9–13 cm from the square but inside
    the disc (a "collision" in navground's Cross example). The cover is the convex hull of the
    polygon and a regular ``BODY_SIDES``-gon circumscribed about the disc (its inscribed
    circle is the disc), counter-clockwise.
    """
    poly = np.asarray(polygon, dtype=float)
    if not (radius > 0.0):
        return None
    a, b = poly, np.roll(poly, -1, axis=0)
    ab = b - a
    t = np.clip(-(a * ab).sum(axis=1) / np.maximum((ab * ab).sum(axis=1), 1e-300), 0.0, 1.0)
    inscribed = float(np.hypot(*(a + t[:, None] * ab).T).min())
    if radius <= inscribed:
        return None
    angles = (np.arange(BODY_SIDES) + 0.5) * (2.0 * math.pi / BODY_SIDES)
    outer = radius / math.cos(math.pi / BODY_SIDES)
    gon = np.column_stack([np.cos(angles), np.sin(angles)]) * outer
    points = np.concatenate([poly, gon])
    hull = ConvexHull(points)  # 2-D: vertices counter-clockwise
    return tuple((float(x), float(y)) for x, y in points[hull.vertices])


class _SocialNavBase(ControllerBehavior):
    """The behaviour's logic; :class:`SocialNavBehavior` adds the registered properties."""

    def __init__(self, kinematics: core.Kinematics | None = None, radius: float = 0.0) -> None:
        ControllerBehavior.__init__(self, kinematics, radius)
        self._values: dict[str, Any] = {}
        self._clock = 0.0
        self._goal: tuple[float, float, float] | None = None
        self._key: tuple[Any, ...] | None = None

    def _changed(self) -> None:
        self.controller = None

    # -- configuration ---------------------------------------------------------------------

    def effective_robot(self) -> RobotModel:
        """The robot model the planner uses: the named model, the property overrides, and
        navground's kinematics and speed limits (see the module docstring)."""
        name = str(self._values.get("robot", "pr2"))
        if name not in ROBOT_MODELS:
            raise ConfigurationError(
                f"SocialNav behaviour: robot: unknown robot model {name!r}; "
                f"known: {', '.join(ROBOT_MODELS)}"
            )
        model = ROBOT_MODELS[name]
        update: dict[str, Any] = {
            f: float(self._values[f])
            for f in ROBOT_FIELDS
            if f in self._values and math.isfinite(float(self._values[f]))
        }
        footprint = self._values.get("footprint") or []
        if len(footprint):
            if len(footprint) < 3:
                raise ConfigurationError("SocialNav behaviour: footprint: needs at least 3 points")
            update["footprint"] = tuple((float(p[0]), float(p[1])) for p in footprint)
        model = dataclasses.replace(model, **update)
        body = covering_footprint(model.polygon, float(self.radius))
        if body is not None:
            model = dataclasses.replace(model, footprint=body)
        kin = self.kinematics
        holonomic = model.holonomic if kin is None else kin.dof() == 3
        speed = float(self.max_speed) if kin is not None or self.max_speed > 0 else math.inf
        target_speed = float(self.get_target_speed())
        if target_speed > 0:
            speed = min(speed, target_speed)
        angular = float(self.max_angular_speed) if self.max_angular_speed > 0 else math.inf
        backward = speed
        if kin is not None and hasattr(kin, "max_backward_speed") and kin.max_backward_speed >= 0:
            backward = min(backward, float(kin.max_backward_speed))
        return dataclasses.replace(
            model,
            holonomic=holonomic,
            max_vel_x=min(model.max_vel_x, speed),
            min_vel_x=max(model.min_vel_x, -backward),
            max_vel_y=min(model.max_vel_y, speed) if holonomic else 0.0,
            acc_lim_y=model.acc_lim_y if holonomic else 0.0,
            max_vel_theta=min(model.max_vel_theta, angular),
        )

    def _options(self, time_step: float, tolerance: float | None, any_yaw: bool) -> dict[str, Any]:
        values = {k: v for k, v in self._values.items() if k not in ("planner", "robot")}
        values.setdefault("controller_period", float(time_step))
        if tolerance is not None and tolerance > 0:
            for name in ("xy_goal_tolerance", "xy_tolerance"):
                own = float(values.get(name, planner_options()[name].default))
                values[name] = min(own, tolerance)
        if any_yaw:
            values["yaw_goal_tolerance"] = values["yaw_tolerance"] = math.pi
        return values

    # -- targets --------------------------------------------------------------------------

    def _target_goal(self) -> tuple[tuple[float, float, float] | None, float | None, bool]:
        """``(goal pose, xy tolerance, any yaw)`` for the current navground target."""
        target = self.target
        here = np.asarray(self.position, dtype=float)
        if target.position is not None:
            p = np.asarray(target.position, dtype=float)
            tolerance = float(target.position_tolerance)
            if target.orientation is not None:
                return (float(p[0]), float(p[1]), float(target.orientation)), tolerance, False
            if self._goal is not None and np.allclose(p, self._goal[:2], atol=MOVED):
                return self._goal, tolerance, True  # keep the yaw chosen when it was set
            dx, dy = p - here
            yaw = math.atan2(dy, dx) if (dx or dy) else float(self.orientation)
            return (float(p[0]), float(p[1]), yaw), tolerance, True
        if target.direction is not None:
            d = np.asarray(target.direction, dtype=float)
            norm = float(np.hypot(*d))
            if norm <= 0:
                return None, None, False
            d = d / norm
            horizon = float(self._values.get("direction_horizon", DEFAULT_DIRECTION_HORIZON))
            ahead = here + d * horizon
            if self._goal is not None:
                kept = np.asarray(self._goal[:2])
                # Keep the goal while it is between half and 1.5 horizons ahead (a periodic
                # world's wrap moves the robot, not the goal, and so re-places it).
                if abs(float(np.dot(kept - ahead, d))) < 0.5 * horizon:
                    return self._goal, None, False
            return (float(ahead[0]), float(ahead[1]), math.atan2(d[1], d[0])), None, False
        return None, None, False

    # -- state conversion -------------------------------------------------------------------

    def _scenario(self, goal: tuple[float, float, float]) -> Scenario:
        walls = [
            (tuple(map(float, s.p1)), tuple(map(float, s.p2)))
            for s in self._state.line_obstacles
            if float(s.length) > 0
        ]
        discs = [
            {"center": tuple(map(float, d.position)), "radius": float(d.radius)}
            for d in self._state.static_obstacles
            if float(d.radius) > 0
        ]
        return Scenario.model_validate(
            {
                "name": "navground",
                "family": "custom",
                "description": "built from a navground agent's state",
                "map": {"walls": walls, "discs": discs},
                "start": tuple(map(float, pose_of(self))),
                "goal": goal,
            }
        )

    def _social(self) -> SocialContext:
        neighbors = list(self._state.neighbors)
        ids = [int(n.id) for n in neighbors]
        if len(set(ids)) != len(ids):  # navground ids are optional: fall back to the order
            ids = list(range(len(neighbors)))
        people = []
        for i, n in zip(ids, neighbors, strict=True):
            v = np.asarray(n.velocity, dtype=float)
            yaw = math.atan2(v[1], v[0]) if np.hypot(*v) > 1e-6 else 0.0
            people.append(
                Person(
                    i,
                    (float(n.position[0]), float(n.position[1])),
                    (float(v[0]), float(v[1])),
                    yaw,
                    max(float(n.radius), 1e-3),
                )
            )
        return SocialContext(tuple(people))

    def observation(self, time_step: float) -> tuple[float, SocialContext]:
        now = self._clock
        self._clock += time_step
        return now, self._social()

    # -- the control step -------------------------------------------------------------------

    def compute_cmd_internal(self, time_step: float) -> core.Twist2:  # type: ignore[override]
        goal, tolerance, any_yaw = self._target_goal()
        if goal is None:
            self.last_output, self.last_cmd = None, np.zeros(3)
            self._clock += float(time_step)
            return self.cmd_twist_towards_stopping(time_step)
        model = self.effective_robot()
        key = (model, tolerance, any_yaw, float(time_step))
        if (
            self.controller is None
            or self._key != key
            or not np.allclose(
                goal, self._goal if self._goal is not None else np.full(3, np.nan), atol=MOVED
            )
        ):
            planner = str(self._values.get("planner", "paccet"))
            try:
                controller = build_planner(planner, self._options(time_step, tolerance, any_yaw))
            except ConfigurationError as exc:
                raise ConfigurationError(f"SocialNav behaviour: {exc}") from None
            controller.reset(self._scenario(goal), model)
            self.controller, self.robot_model, self._goal, self._key = (
                controller,
                model,
                goal,
                key,
            )
        ControllerBehavior.compute_cmd_internal(self, time_step)
        cmd = self.last_cmd
        twist = core.Twist2(
            (float(cmd[0]), float(cmd[1])), float(cmd[2]), frame=core.Frame.relative
        )
        if self.kinematics is not None:
            twist = self.feasible_twist(twist)
            self.last_cmd = np.array([*twist.velocity, twist.angular_speed], dtype=float)
        return twist


def _exec_body(namespace: dict[str, Any]) -> None:
    props = _properties()
    namespace.update(props)
    namespace["__doc__"] = (
        "A navground behaviour running a planner of ours (see the module docstring).\n\n"
        "*State*: :py:class:`GeometricState`. *Registered properties*: "
        + ", ".join(sorted(props))
        + "."
    )
    namespace["__module__"] = __name__


#: registered with navground as ``SocialNav`` (navground registers a subclass given ``name=``)
SocialNavBehavior: type[_SocialNavBase] = types.new_class(
    "SocialNavBehavior", (_SocialNavBase,), {"name": "SocialNav"}, _exec_body
)

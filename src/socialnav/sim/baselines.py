"""Baselines that need no planner: navground's own behaviours and a naive go-to-goal law.

- ``orca``, ``hl``, ``social_force``: navground behaviours (``ORCA``, ``HL``, ``SocialForce``)
  wrapped as a :class:`NavgroundController`, driving the robot disc (circumscribed radius) toward
  the scenario's target (the social waypoint first where there is one); they see the walls and
  the people within navground's sensing range. These are the peers a navground user would pick.
- ``go_to_goal``: :class:`GoToGoalController`, a proportional law straight at the goal that
  ignores everyone — a lower bound and the test controller of the simulator.
- ``straight_line``: the crowd suite's reference (SocNavBench's "how crowded is this
  episode"): the start→goal line at full speed, no planner, ignoring everyone, stopping at the
  goal (:class:`GoToGoalController` with an unbounded gain).
"""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING, cast

import numpy as np
from navground import core

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.sim.controller import CONTROLLERS, GOAL_REACHED, register_controller
from socialnav.sim.engine import make_kinematics, static_segments
from socialnav.sim.humans import SENSING_RANGE
from socialnav.sim.target import resolve_target

if TYPE_CHECKING:
    from socialnav.sim.scenario import Scenario

#: navground behaviours registered as controllers: name → (navground type, description, order)
NAVGROUND_CONTROLLERS: dict[str, tuple[str, str, int]] = {
    "orca": ("ORCA", "navground ORCA (velocity obstacles) driving the robot", 40),
    "hl": ("HL", "navground HL, the human-like behaviour", 50),
    "social_force": ("SocialForce", "navground SocialForce (Helbing) driving the robot", 60),
}


def make_behavior(name: str, robot: RobotModel) -> core.Behavior:
    """navground behaviour ``name`` for ``robot``: its kinematics, circumscribed radius, and
    speeds capped at the robot's ``max_vel_x`` (m/s) / ``max_vel_theta`` (rad/s).

    Raises ``ConfigurationError`` when navground has no behaviour of that name.
    """
    behavior = core.Behavior.make_type(name)
    if behavior is None:
        raise ConfigurationError(f"navground has no behaviour {name!r}")
    behavior.max_speed = float(robot.max_vel_x)
    behavior.optimal_speed = float(robot.max_vel_x)
    behavior.max_angular_speed = float(robot.max_vel_theta)
    behavior.optimal_angular_speed = float(robot.max_vel_theta)
    # Kinematics last, as a navground agent sets them (navground then raises the speed caps to
    # the kinematics' own; the box limits are enforced by clamp_to_robot).
    behavior.kinematics = make_kinematics(robot)
    behavior.radius = float(robot.circumscribed_radius)
    return behavior


class NavgroundController:
    """A navground behaviour (``ORCA``, ``HL``, ``SocialForce``, …) as a :class:`Controller`.

    What a navground user would run instead of our planner, given what navground's ``Bounded``
    state estimation and ``Waypoints`` task would give it: the walls, polygon edges and obstacle
    discs of the scenario; the people within ``sensing_range`` m (their position, velocity and
    radius); the waypoints ``[social waypoint, target]`` (the social goal where there is one,
    :func:`~socialnav.sim.target.resolve_target`) in turn, each with the target's yaw and
    ``tolerance_factor × goal_tolerance`` m / ``angular_tolerance`` rad. ``GOAL_REACHED`` with a
    zero command once the last waypoint is satisfied.
    """

    def __init__(
        self,
        behavior: str,
        sensing_range: float = SENSING_RANGE,
        tolerance_factor: float = 0.5,
        angular_tolerance: float = 0.2,
        record: bool = False,
    ) -> None:
        del record  # navground evaluates no candidate set to record
        self.behavior_name = behavior
        self.sensing_range = float(sensing_range)
        self.tolerance_factor = float(tolerance_factor)
        self.angular_tolerance = float(angular_tolerance)
        self._behavior: core.Behavior | None = None
        self._waypoints: list[FloatArray] = []
        self._index = 0
        self._target = np.zeros(3)
        self._dt = 0.1

    def reset(
        self, scenario: Scenario, robot: RobotModel, social: SocialContext | None = None
    ) -> None:
        """Plan the waypoints to the social goal of ``social`` (what the robot sees at the
        start; default the scenario's own context)."""
        seen = scenario.social_context(scenario.start) if social is None else social
        target = resolve_target(scenario, seen)
        self._target = np.asarray(target.pose, dtype=float)
        self._waypoints = [] if target.waypoint is None else [target.waypoint]
        self._waypoints.append(self._target[:2])
        self._index = 0
        self._tolerance = self.tolerance_factor * float(scenario.goal_tolerance)
        self._dt = float(scenario.control_period)
        behavior = make_behavior(self.behavior_name, robot)
        state = cast(core.GeometricState, behavior.environment_state)
        state.line_obstacles = [
            core.LineSegment(tuple(a), tuple(b)) for a, b in static_segments(scenario)
        ]
        state.static_obstacles = [
            core.Disc((float(x), float(y)), float(r)) for x, y, r in scenario.discs_array()
        ]
        self._behavior = behavior
        self._set_target()

    def _set_target(self) -> None:
        assert self._behavior is not None
        point = self._waypoints[self._index]
        self._behavior.target = core.Target(
            position=(float(point[0]), float(point[1])),
            orientation=float(self._target[2]),
            position_tolerance=self._tolerance,
            orientation_tolerance=self.angular_tolerance,
        )

    def step(
        self, time: float, pose: FloatArray, velocity: FloatArray, social: SocialContext
    ) -> PlannerResult:
        b = self._behavior
        if b is None:
            return PlannerResult(np.zeros(3), PlannerStatus.INVALID_INPUT, None, "reset() first")
        b.pose = core.Pose2((float(pose[0]), float(pose[1])), float(pose[2]))
        # World-frame twist, also as the actuated one: ORCA smooths from the actuated twist and
        # keeps it in the frame it was set in.
        c, s = math.cos(pose[2]), math.sin(pose[2])
        vx, vy = velocity[0] * c - velocity[1] * s, velocity[0] * s + velocity[1] * c
        twist = core.Twist2((float(vx), float(vy)), float(velocity[2]), frame=core.Frame.absolute)
        b.twist = twist
        b.actuated_twist = twist
        if b.check_if_target_satisfied():
            if self._index + 1 >= len(self._waypoints):
                return PlannerResult(np.zeros(3), GOAL_REACHED, None, "", self._target)
            self._index += 1
            self._set_target()
        positions, velocities, radii = social.positions(), social.velocities(), social.radii()
        near = np.hypot(*(positions - pose[:2]).T) <= self.sensing_range
        cast(core.GeometricState, b.environment_state).neighbors = [
            core.Neighbor(
                (float(p[0]), float(p[1])), float(r), (float(v[0]), float(v[1])), int(person.id)
            )
            for p, v, r, person, keep in zip(
                positions, velocities, radii, social.people, near, strict=True
            )
            if keep
        ]
        out = b.compute_cmd(self._dt, core.Frame.relative)
        cmd = np.array([out.velocity[0], out.velocity[1], out.angular_speed], dtype=float)
        return PlannerResult(cmd, PlannerStatus.OK, None, "", self._target)


class GoToGoalController:
    """Proportional control straight at the goal, then turn to the goal's yaw; ignores people.

    ``gain`` (1/s) on the distance, ``angular_gain`` (1/s) on the heading error; a differential
    drive turns in place while the goal is more than ``turn_in_place`` rad off its heading.
    """

    def __init__(
        self,
        gain: float = 1.0,
        angular_gain: float = 2.0,
        xy_tolerance: float = 0.1,
        yaw_tolerance: float = 0.1,
        turn_in_place: float = 0.5,
        record: bool = False,
    ) -> None:
        del record  # nothing to record
        self.gain = gain
        self.angular_gain = angular_gain
        self.xy_tolerance = xy_tolerance
        self.yaw_tolerance = yaw_tolerance
        self.turn_in_place = turn_in_place
        self.goal = np.zeros(3)
        self.robot: RobotModel | None = None

    def reset(self, scenario: Scenario, robot: RobotModel) -> None:
        self.goal = np.asarray(scenario.goal, dtype=float)
        self.robot = robot

    def step(
        self, time: float, pose: FloatArray, velocity: FloatArray, social: SocialContext
    ) -> PlannerResult:
        assert self.robot is not None, "reset() first"
        delta = self.goal[:2] - pose[:2]
        dist = float(np.hypot(*delta))
        if dist <= self.xy_tolerance:
            err = float(wrap_angle(self.goal[2] - pose[2]))
            if abs(err) <= self.yaw_tolerance:
                return PlannerResult(np.zeros(3), GOAL_REACHED, target=self.goal)
            return PlannerResult(
                np.array([0.0, 0.0, self.angular_gain * err]),
                PlannerStatus.ROTATING_TO_GOAL,
                target=self.goal,
            )
        c, s = math.cos(pose[2]), math.sin(pose[2])
        body = np.array([c * delta[0] + s * delta[1], -s * delta[0] + c * delta[1]])
        speed = self.gain * dist
        heading_err = float(math.atan2(body[1], body[0]))
        if self.robot.holonomic:
            # Straight at the goal, scaled into the (vx, vy) box keeping the direction.
            v = body / dist * min(speed, self.robot.max_vel_x)
            limits = (
                self.robot.max_vel_x if v[0] >= 0 else -self.robot.min_vel_x,
                self.robot.max_vel_y,
            )
            scale = min(
                [1.0] + [lim / abs(c) for lim, c in zip(limits, v, strict=True) if abs(c) > 1e-12]
            )
            v = v * max(scale, 0.0)
            cmd = np.array([v[0], v[1], self.angular_gain * heading_err])
            return PlannerResult(cmd, PlannerStatus.OK, target=self.goal)
        if abs(heading_err) > self.turn_in_place:
            cmd = np.array([0.0, 0.0, self.angular_gain * heading_err])
            return PlannerResult(cmd, PlannerStatus.OK, target=self.goal)
        vx = min(speed, self.robot.max_vel_x) * math.cos(heading_err)
        cmd = np.array([vx, 0.0, self.angular_gain * heading_err])
        return PlannerResult(cmd, PlannerStatus.OK, target=self.goal)


for _name, (_type, _description, _order) in NAVGROUND_CONTROLLERS.items():
    if _name not in CONTROLLERS:
        register_controller(
            _name, partial(NavgroundController, _type), _description, order=_order, kind="navground"
        )
if "go_to_goal" not in CONTROLLERS:
    register_controller(
        "go_to_goal",
        GoToGoalController,
        "proportional control straight at the goal, ignoring people (a lower bound)",
        order=900,
        compared=False,
    )
#: gain (1/s) so large that the speed saturates at the robot's limit until the goal
STRAIGHT_LINE_GAIN = 1.0e6
if "straight_line" not in CONTROLLERS:
    register_controller(
        "straight_line",
        partial(GoToGoalController, gain=STRAIGHT_LINE_GAIN),
        "the start-goal line at full speed, ignoring people (the crowd suite's reference)",
        order=950,
        compared=False,
    )

"""Baselines that need no planner: navground's own behaviours and a naive go-to-goal law.

- ``ORCA``, ``HL``, ``SocialForce`` (and ``HRVO``, ``Dummy``): navground behaviours driving the
  robot disc (circumscribed radius) toward the scenario's target through a ``Waypoints`` task
  (the social waypoint first where there is one); they see walls and people through navground's
  ``Bounded`` state estimation. These are the peers a navground user would pick.
- ``go_to_goal``: :class:`GoToGoalController`, a proportional law straight at the goal that
  ignores everyone — a lower bound and the test controller of the simulator.
- ``straight_line``: the crowd suite's reference (SocNavBench's "how crowded is this
  episode"): the start→goal line at full speed, no planner, ignoring everyone, stopping at the
  goal (:class:`GoToGoalController` with an unbounded gain).
"""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
from navground import core, sim

from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.sim.controller import CONTROLLERS, GOAL_REACHED, ControlOutput

if TYPE_CHECKING:
    from socialnav.sim.scenario import Scenario

NAVGROUND_BEHAVIORS = ("ORCA", "HL", "SocialForce", "HRVO", "Dummy")


def make_baseline(
    name: str,
    robot: RobotModel,
    waypoints: list[FloatArray],
    final_yaw: float | None,
    tolerance: float,
    angular_tolerance: float = 0.2,
) -> tuple[core.Behavior, sim.Task]:
    """A navground behaviour ``name`` and its ``Waypoints`` task through ``waypoints`` ``[(2,)]``.

    Speeds are capped at the robot's ``max_vel_x`` / ``max_vel_theta``.
    """
    behavior = core.Behavior.make_type(name)
    if behavior is None:  # pragma: no cover - names are checked by the caller
        raise ValueError(f"navground has no behaviour {name!r}")
    behavior.max_speed = float(robot.max_vel_x)
    behavior.optimal_speed = float(robot.max_vel_x)
    behavior.max_angular_speed = float(robot.max_vel_theta)
    behavior.optimal_angular_speed = float(robot.max_vel_theta)
    kwargs: dict[str, object] = {}
    if final_yaw is not None:
        kwargs["orientations"] = [float(final_yaw)] * len(waypoints)
        kwargs["angular_tolerance"] = float(angular_tolerance)
    task = sim.tasks.WaypointsTask(
        waypoints=[np.asarray(w, dtype=float) for w in waypoints],
        loop=False,
        tolerance=float(tolerance),
        **kwargs,
    )
    return behavior, task


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
    ) -> None:
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
    ) -> ControlOutput:
        assert self.robot is not None, "reset() first"
        delta = self.goal[:2] - pose[:2]
        dist = float(np.hypot(*delta))
        if dist <= self.xy_tolerance:
            err = float(wrap_angle(self.goal[2] - pose[2]))
            if abs(err) <= self.yaw_tolerance:
                return ControlOutput(np.zeros(3), GOAL_REACHED)
            return ControlOutput(np.array([0.0, 0.0, self.angular_gain * err]), "ROTATING_TO_GOAL")
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
            return ControlOutput(np.array([v[0], v[1], self.angular_gain * heading_err]))
        if abs(heading_err) > self.turn_in_place:
            return ControlOutput(np.array([0.0, 0.0, self.angular_gain * heading_err]))
        vx = min(speed, self.robot.max_vel_x) * math.cos(heading_err)
        return ControlOutput(np.array([vx, 0.0, self.angular_gain * heading_err]))


CONTROLLERS.add("go_to_goal", GoToGoalController)
#: gain (1/s) so large that the speed saturates at the robot's limit until the goal
STRAIGHT_LINE_GAIN = 1.0e6
CONTROLLERS.add("straight_line", partial(GoToGoalController, gain=STRAIGHT_LINE_GAIN))

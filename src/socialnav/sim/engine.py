"""Build a navground world from a :class:`Scenario` and drive the robot with a Controller.

Modelling choices (navground agents are discs):

- the robot is a disc of its *circumscribed* radius for navground (what other agents and the
  navground baselines avoid); collisions are measured on its polygon footprint (recorder.py);
- polygonal obstacles (the desk) are represented by their edges as navground walls, discs stay
  navground disc obstacles;
- ``ignore_collisions = True``: motion is kinematic and nobody is pushed apart;
- navground's kinematic limits are set so they never bind inside the RobotModel's box limits
  (Omni: ``hypot(max_vel_x, max_vel_y)``; 2WDiff: wheel speeds that allow ``max_vel_x`` together
  with ``max_vel_theta``); the box itself is enforced by :func:`clamp_to_robot`;
- commands act instantly (as in Stage); acceleration limits are the planner's business.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import SupportsFloat

import numpy as np
from navground import core, sim

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.local_planner import PlannerResult
from socialnav.sim.controller import Controller, clamp_to_robot
from socialnav.sim.humans import make_person_agent
from socialnav.sim.scenario import Scenario

#: the largest episode seed: navground's ``World.seed`` is an unsigned 32-bit integer
MAX_SEED = 2**32 - 1


def wheel_axis(robot: RobotModel) -> float:
    """Distance between the wheels of a differential drive: the footprint's width (m)."""
    ys = robot.polygon[:, 1]
    return float(ys.max() - ys.min())


def make_kinematics(robot: RobotModel) -> core.Kinematics:
    """navground kinematics for ``robot``: ``Omni`` (holonomic) or ``2WDiff``."""
    if robot.holonomic:
        return core.kinematics.OmnidirectionalKinematics(
            robot.max_speed, float(robot.max_vel_theta)
        )
    axis = wheel_axis(robot)
    turn = robot.max_vel_theta * axis / 2.0  # wheel speed used by turning at full rate
    forward = robot.max_vel_x + turn
    return core.kinematics.TwoWheelsDifferentialDriveKinematics(
        max_speed=forward,
        wheel_axis=axis,
        max_angular_speed=float(robot.max_vel_theta),
        max_forward_speed=forward,
        max_backward_speed=max(-robot.min_vel_x, 0.0) + turn,
    )


def pose_of(agent: sim.Agent | core.Behavior) -> FloatArray:
    """World pose ``(3,)`` of a navground agent or behaviour (float64)."""
    p = agent.pose
    return np.array([p.position[0], p.position[1], p.orientation], dtype=float)


class ControllerBehavior(core.Behavior):
    """A navground behaviour that asks a :class:`Controller` for each command.

    ``observe()`` returns ``(time, social)`` for the current step; the runner sets it to the
    ground truth of the scenario. The controller's body twist is clipped to the robot's limits.
    ``last_output`` / ``last_cmd`` keep what was returned for recording.
    """

    def __init__(self, kinematics: core.Kinematics | None = None, radius: float = 0.0) -> None:
        core.Behavior.__init__(self, kinematics, radius)
        self._state = core.GeometricState()
        self.controller: Controller | None = None
        self.robot_model: RobotModel | None = None
        self.observe: Callable[[float], tuple[float, SocialContext]] | None = None
        self.last_output: PlannerResult | None = None
        self.last_cmd: FloatArray = np.zeros(3)

    def get_environment_state(self) -> core.GeometricState:
        return self._state

    def observation(self, time_step: float) -> tuple[float, SocialContext]:
        """``(time, social)`` for this step (override or set ``observe``)."""
        if self.observe is None:
            return 0.0, SocialContext()
        return self.observe(time_step)

    def compute_cmd_internal(self, time_step: SupportsFloat) -> core.Twist2:
        if self.controller is None or self.robot_model is None:
            self.last_output, self.last_cmd = None, np.zeros(3)
            return core.Twist2((0.0, 0.0), 0.0, frame=core.Frame.relative)
        time, social = self.observation(float(time_step))
        # The body velocity is the previous command (commands act instantly); navground's own
        # twist is stored in the world frame of the previous pose and would show a spurious
        # lateral component once rotated into the new heading.
        out = self.controller.step(time, pose_of(self), self.last_cmd.copy(), social)
        cmd = clamp_to_robot(out.cmd, self.robot_model)
        self.last_output, self.last_cmd = out, cmd
        return core.Twist2((float(cmd[0]), float(cmd[1])), float(cmd[2]), frame=core.Frame.relative)


@dataclass
class SimWorld:
    """The navground world of one episode; ``people`` in the scenario's order."""

    world: sim.World
    robot: sim.Agent
    people: list[sim.Agent]
    people_ids: np.ndarray

    def people_state(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Positions ``(K, 2)``, world velocities ``(K, 2)`` and yaws ``(K,)``, float64."""
        k = len(self.people)
        pos = np.array([a.position for a in self.people], dtype=float).reshape(k, 2)
        vel = np.array([a.velocity for a in self.people], dtype=float).reshape(k, 2)
        yaw = np.array([a.orientation for a in self.people], dtype=float).reshape(k)
        return pos, vel, yaw


def static_segments(scenario: Scenario) -> list[tuple[FloatArray, FloatArray]]:
    """The line segments navground sees: the walls, then every obstacle polygon's edges
    (rectangles included), each as ``(a (2,), b (2,))`` world points (m)."""
    segments = [(a, b) for a, b in scenario.walls_array()]
    polygons = [np.asarray(p, dtype=float) for p in scenario.map.polygons]
    polygons += [r.polygon() for r in scenario.map.rectangles]
    for poly in polygons:
        segments += list(zip(poly, np.roll(poly, -1, axis=0), strict=True))
    return segments


def add_static_geometry(world: sim.World, scenario: Scenario) -> None:
    """Walls and polygon edges as navground walls (:func:`static_segments`), discs as disc
    obstacles."""
    for a, b in static_segments(scenario):
        world.add_wall(sim.Wall(tuple(a), tuple(b)))
    for x, y, r in scenario.discs_array():
        world.add_obstacle(sim.Obstacle((float(x), float(y)), float(r)))


def build_world(
    scenario: Scenario,
    robot: RobotModel,
    robot_behavior: core.Behavior,
    humans: str = "scripted",
    reactive_behavior: str = "HL",
    robot_task: sim.Task | None = None,
    sensing: bool = False,
    seed: int = 0,
) -> SimWorld:
    """The world of one episode: static geometry, the robot agent (index 0) and the people.

    ``sensing`` gives the robot navground's ``Bounded`` state estimation (navground baselines
    need it; a :class:`ControllerBehavior` reads the scenario's ground truth instead).
    """
    from socialnav.sim.humans import SENSING_RANGE

    if not 0 <= int(seed) <= MAX_SEED:
        raise ConfigurationError(f"seed must be an integer in [0, {MAX_SEED}], got {seed!r}")
    world = sim.World()
    world.seed = int(seed)
    world.ignore_collisions = True
    add_static_geometry(world, scenario)
    estimations = (
        [sim.state_estimations.BoundedStateEstimation(range=SENSING_RANGE)] if sensing else []
    )
    agent = sim.Agent(
        radius=robot.circumscribed_radius,
        behavior=robot_behavior,
        kinematics=make_kinematics(robot),
        task=robot_task,
        state_estimations=estimations,
        control_period=0.0,  # every world update (= the scenario's control period)
        id=0,
    )
    robot_behavior.radius = robot.circumscribed_radius
    x, y, yaw = scenario.start
    agent.pose = core.Pose2((float(x), float(y)), float(yaw))
    agent.type = robot.name
    world.add_agent(agent)
    people = [make_person_agent(p, humans, reactive_behavior) for p in scenario.people]
    for a in people:
        world.add_agent(a)
    ids = np.array([p.id for p in scenario.people], dtype=int)
    return SimWorld(world, agent, people, ids)

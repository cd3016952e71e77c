"""socialnav planners as a navground behaviour: ``type: SocialNav`` in navground YAML.

Registered with navground by subclassing (``name="SocialNav"``) and discovered through the
``navground_behaviors`` entry point, so navground's own experiments, CLI and tools can drive an
agent with any controller registered in :data:`socialnav.sim.controller.CONTROLLERS`::

    behavior:
      type: SocialNav
      planner: paccet      # a CONTROLLERS name
      robot: pr2           # a socialnav robot model (limits and footprint)

What the planner sees here differs from ``socialnav.sim.runner`` (which uses the scenario's
ground truth): people are navground's neighbours (no groups, queues or artworks are known), walls
and disc obstacles are those the agent's state estimation reports on the first step, and the goal
is the behaviour's navground target (the controller is reset whenever that target moves).
"""

from __future__ import annotations

import math

import numpy as np
from navground import core

from socialnav.core.robot import ROBOT_MODELS
from socialnav.core.scene import Person, SocialContext
from socialnav.sim.controller import CONTROLLERS
from socialnav.sim.engine import ControllerBehavior, pose_of
from socialnav.sim.scenario import Scenario

__all__ = ["SocialNavBehavior"]


class SocialNavBehavior(ControllerBehavior, name="SocialNav"):
    """A navground behaviour running a socialnav controller (see the module docstring).

    *State*: :py:class:`GeometricState`. *Registered properties*: ``planner`` [str],
    ``robot`` [str].
    """

    def __init__(self, kinematics: core.Kinematics | None = None, radius: float = 0.0) -> None:
        ControllerBehavior.__init__(self, kinematics, radius)
        self._planner = "paccet"
        self._robot = "pr2"
        self._clock = 0.0
        self._goal: tuple[float, float, float] | None = None

    @property
    @core.register("paccet", "Name of a socialnav controller (CONTROLLERS registry)")
    def planner(self) -> str:
        return self._planner

    @planner.setter
    def planner(self, value: str) -> None:
        self._planner = str(value)
        self.controller = None

    @property
    @core.register("pr2", "socialnav robot model: limits and footprint")
    def robot(self) -> str:
        return self._robot

    @robot.setter
    def robot(self, value: str) -> None:
        self._robot = str(value)
        self.controller = None

    # -- state conversion ----------------------------------------------------------------------

    def _target_pose(self) -> tuple[float, float, float] | None:
        target = self.target
        if target.position is None:
            return None
        yaw = target.orientation
        if yaw is None:
            dx, dy = np.asarray(target.position) - np.asarray(self.position)
            yaw = math.atan2(dy, dx) if (dx or dy) else float(self.orientation)
        return float(target.position[0]), float(target.position[1]), float(yaw)

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
        start = pose_of(self)
        return Scenario.model_validate(
            {
                "name": "navground",
                "family": "custom",
                "description": "built from a navground agent's state",
                "map": {"walls": walls, "discs": discs},
                "start": tuple(map(float, start)),
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

    def compute_cmd_internal(self, time_step: float) -> core.Twist2:
        goal = self._target_pose()
        if goal is None:
            return self.cmd_twist_towards_stopping(time_step)
        if self.controller is None or goal[:2] != (self._goal or (None, None, None))[:2]:
            model = ROBOT_MODELS[self._robot]
            controller = CONTROLLERS.get(self._planner).factory()
            controller.reset(self._scenario(goal), model)
            self.controller, self.robot_model, self._goal = controller, model, goal
        return ControllerBehavior.compute_cmd_internal(self, time_step)

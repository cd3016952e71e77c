"""The navground behaviour plugin: usable by name from navground's own YAML experiments."""

from __future__ import annotations

import numpy as np
from navground import core, sim

from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.sim.controller import CONTROLLERS, GOAL_REACHED, register_controller


class StraightToGoal:
    """Trivial test controller: drive straight toward the goal at 0.4 m/s, stop within 0.15 m."""

    def reset(self, scenario, robot) -> None:
        self.goal = np.asarray(scenario.goal[:2], dtype=float)
        self.walls = scenario.walls_array()

    def step(self, time, pose, velocity, social) -> PlannerResult:
        delta = self.goal - pose[:2]
        dist = float(np.hypot(*delta))
        if dist < 0.15:
            return PlannerResult(np.zeros(3), GOAL_REACHED)
        c, s = np.cos(pose[2]), np.sin(pose[2])
        body = np.array([c * delta[0] + s * delta[1], -s * delta[0] + c * delta[1]]) / dist
        return PlannerResult(np.array([*(0.4 * body), 0.0]), PlannerStatus.OK)


if "test_straight" not in CONTROLLERS:
    register_controller(
        "test_straight", StraightToGoal, "test: straight at the goal", compared=False
    )

EXPERIMENT = """
steps: 60
time_step: 0.1
record_pose: true
scenario:
  walls:
    - line: [[0, -1.5], [20, -1.5]]
    - line: [[0, 1.5], [20, 1.5]]
  groups:
    - number: 1
      type: robot
      radius: 0.46
      kinematics: {type: Omni, max_speed: 0.63, max_angular_speed: 1.0}
      behavior: {type: SocialNav, planner: test_straight, robot: pr2}
      task: {type: Waypoints, waypoints: [[2.0, 0.0]], tolerance: 0.2}
      state_estimation: {type: Bounded, range: 5.0}
      position: [0.0, 0.0]
      orientation: 0.0
    - number: 1
      type: human
      radius: 0.25
      kinematics: {type: Omni, max_speed: 1.0, max_angular_speed: 1.0}
      behavior: {type: HL}
      task: {type: Waypoints, waypoints: [[0.0, 1.0]], tolerance: 0.2}
      state_estimation: {type: Bounded, range: 5.0}
      position: [4.0, 1.0]
"""


def test_plugin_is_registered_through_the_entry_point() -> None:
    core.load_plugins()
    assert "SocialNav" in core.Behavior.types
    assert set(core.Behavior.type_properties["SocialNav"]) == {"planner", "robot"}


def test_yaml_experiment_runs_the_behaviour_by_name() -> None:
    core.load_plugins()
    experiment = sim.load_experiment(EXPERIMENT)
    run = experiment.run_once(seed=1)
    poses = np.asarray(run.poses)  # (steps, agents, 3)
    assert poses.shape[0] == 60
    robot = run.world.agents[0].behavior
    assert robot.type == "SocialNav" and robot.planner == "test_straight"
    # The controller drove the robot to the task's waypoint and saw the person.
    assert np.linalg.norm(poses[-1, 0, :2] - [2.0, 0.0]) < 0.2
    assert robot.last_output is not None and robot.last_output.status == GOAL_REACHED
    np.testing.assert_allclose(robot.controller.walls[:, :, 1].ravel(), [-1.5, -1.5, 1.5, 1.5])
    speeds = np.linalg.norm(np.diff(poses[:10, 0, :2], axis=0), axis=1) / 0.1
    np.testing.assert_allclose(speeds[1:], 0.4, atol=1e-3)
    assert "planner: test_straight" in core.dump(robot)

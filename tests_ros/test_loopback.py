"""Loopback integration: fake base, people publisher, map publisher and the socialnav node, each
in its own process, over DDS on loopback; this process sends the goal and watches.

The Table 1 situation (hallway_passing): a Pioneer goes 5 m along a 3 m corridor while a person
walks the opposite way 0.9 m to its side. The robot must reach the goal, keep ≥ 1.2 m
(centre to centre) from the person and touch neither the person nor a wall. Bounded: 60 s.
The odometry-to-command latency (a command's stamp is the odometry it answers) is printed.
"""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseArray, PoseStamped, TwistStamped
from nav_msgs.msg import Odometry
from nav_msgs.msg import Path as PathMsg
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from visualization_msgs.msg import MarkerArray

from socialnav.core.geometry import body_to_world, signed_distance_to_polygon
from socialnav.core.robot import PIONEER
from socialnav.integrations.ros2.convert import compose, yaw_from_quaternion
from socialnav.sim.scenario import load_scenario
from socialnav.world.grid import LETHAL
from socialnav.world.mapio import OccupancyMap, save_map

NODES = Path(__file__).parent / "nodes"
START = (0.5, -0.45, 0.0)  # Table 1 robot start = the odom frame's pose in map
GOAL = (5.5, -0.45, 0.0)
PERSON = (6.0, 0.45, -0.5, 0.0, 0.0)  # x0, y0, vx, vy, x_end
BUDGET_S = 60.0
PARAMS = f"""\
socialnav:
  ros__parameters:
    planner: paccet
    robot_model: pioneer
    controller_frequency: 10.0
    enable_stamped_cmd_vel: true
    odom_to_global: [{START[0]}, {START[1]}, {START[2]}]
    xy_goal_tolerance: 0.1
"""


def write_map(folder: Path) -> Path:
    """hallway_passing's walls as a ROS map file (what map_server would serve)."""
    costmap = load_scenario("hallway_passing").static_costmap(PIONEER)
    omap = OccupancyMap.from_masks(costmap.costs == LETHAL, costmap.geometry)
    path = folder / "hallway.yaml"
    save_map(omap, path)
    return path


class Observer(Node):
    def __init__(self) -> None:
        super().__init__("observer")
        self.poses: list[np.ndarray] = []
        self.person: np.ndarray | None = None
        self.min_center = math.inf
        self.min_person_gap = math.inf
        self.min_wall_gap = math.inf
        self.latency: list[float] = []
        self.state = ""
        self.status = ""
        self.goal_pub = self.create_publisher(PoseStamped, "goal_pose", 10)
        self.create_subscription(Odometry, "odom", self.on_odom, qos_profile_sensor_data)
        self.create_subscription(PoseArray, "people", self.on_people, qos_profile_sensor_data)
        self.create_subscription(TwistStamped, "cmd_vel", self.on_cmd, 10)
        self.create_subscription(DiagnosticArray, "/diagnostics", self.on_diag, 10)
        self.seen: dict[str, object] = {}
        for topic, kind in (
            ("plan", PathMsg),
            ("local_plan", PathMsg),
            ("social_goal", PoseStamped),
            ("socialnav/candidates", MarkerArray),
            ("socialnav/people", MarkerArray),
        ):
            self.create_subscription(kind, topic, lambda m, t=topic: self.seen.update({t: m}), 1)

    def now(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    def on_odom(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        pose = compose(START, [p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w)])
        self.poses.append(pose)
        foot = body_to_world(PIONEER.polygon, pose)
        self.min_wall_gap = min(self.min_wall_gap, float(1.5 - np.abs(foot[:, 1]).max()))
        if self.person is not None:
            self.min_center = min(self.min_center, float(np.hypot(*(pose[:2] - self.person))))
            gap = float(signed_distance_to_polygon(self.person[None], foot)[0]) - 0.25
            self.min_person_gap = min(self.min_person_gap, gap)

    def on_people(self, msg: PoseArray) -> None:
        if msg.poses:
            self.person = np.array([msg.poses[0].position.x, msg.poses[0].position.y])

    def on_cmd(self, msg: TwistStamped) -> None:
        stamp = msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec
        self.latency.append(self.now() - stamp)

    def on_diag(self, msg: DiagnosticArray) -> None:
        for s in msg.status:
            if s.name == "socialnav: controller":
                values = {kv.key: kv.value for kv in s.values}
                self.state = values.get("lifecycle_state", "")
                self.status = values.get("status", self.status)

    def send_goal(self) -> None:
        msg = PoseStamped()
        msg.header.frame_id = "map"
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.pose.position.x, msg.pose.position.y = GOAL[0], GOAL[1]
        msg.pose.orientation.w = 1.0
        self.goal_pub.publish(msg)


def spawn(args: list[str], log: Path) -> subprocess.Popen[bytes]:
    out = log.open("wb")
    return subprocess.Popen(
        [sys.executable, *args], stdout=out, stderr=subprocess.STDOUT, env=os.environ.copy()
    )


def test_loopback_hallway_passing(tmp_path: Path) -> None:
    t_start = time.monotonic()
    params = tmp_path / "params.yaml"
    params.write_text(PARAMS)
    procs = [
        spawn([str(NODES / "map_publisher.py"), str(write_map(tmp_path))], tmp_path / "map.log"),
        spawn([str(NODES / "fake_base.py"), "pioneer", "50", "--stamped"], tmp_path / "base.log"),
        spawn([str(NODES / "people_publisher.py"), *map(str, PERSON)], tmp_path / "people.log"),
        spawn(["-m", "socialnav.cli", "ros2", "--params", str(params)], tmp_path / "node.log"),
    ]
    rclpy.init()
    obs = Observer()
    goal_sent_at = math.inf
    try:
        while time.monotonic() - t_start < BUDGET_S:
            rclpy.spin_once(obs, timeout_sec=0.05)
            assert all(p.poll() is None for p in procs), "a node process died"
            if goal_sent_at == math.inf:
                # the node and the people publisher both listen before the walk starts
                if obs.state == "active" and obs.goal_pub.get_subscription_count() >= 2:
                    obs.send_goal()
                    goal_sent_at = time.monotonic()
            elif obs.status == "GOAL_REACHED":
                break
        elapsed = time.monotonic() - t_start
    finally:
        obs.destroy_node()
        rclpy.try_shutdown()
        for p in procs:
            p.send_signal(signal.SIGINT)
        for p in procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
    logs = "\n".join(f"--- {f.name}\n{f.read_text()[-2000:]}" for f in tmp_path.glob("*.log"))
    assert goal_sent_at < math.inf, f"the node never became active\n{logs}"
    assert obs.status == "GOAL_REACHED", f"no goal within {BUDGET_S} s ({obs.status})\n{logs}"
    assert set(obs.seen) == {
        "plan",
        "local_plan",
        "social_goal",
        "socialnav/candidates",
        "socialnav/people",
    }
    end = obs.seen["plan"].poses[-1].pose.position
    assert math.hypot(end.x - GOAL[0], end.y - GOAL[1]) < 0.1
    final = obs.poses[-1]
    assert np.hypot(final[0] - GOAL[0], final[1] - GOAL[1]) <= 0.15
    assert obs.min_center >= 1.2, obs.min_center
    assert obs.min_person_gap > 0 and obs.min_wall_gap > 0
    lat = np.asarray(obs.latency) * 1e3
    p50, p95 = np.percentile(lat, [50, 95])
    print(
        f"\nloopback: {elapsed:.1f} s wall, min distance to the person {obs.min_center:.2f} m, "
        f"min gap person {obs.min_person_gap:.2f} m, wall {obs.min_wall_gap:.2f} m; "
        f"odometry-to-command latency p50 {p50:.1f} ms, p95 {p95:.1f} ms ({lat.size} commands)"
    )
    # not a timing target (the machine may be loaded): a command older than the node's
    # odom_timeout would answer odometry the node itself treats as stale
    assert p95 < 500.0

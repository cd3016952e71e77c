"""A fake robot base: integrates cmd_vel with the robot's kinematics and limits, publishes odom.

Velocities are clipped to the robot's limits and slewed at its acceleration limits every tick
(a differential-drive base ignores lateral velocity); a command older than 0.5 s is replaced by
zero, as a base's watchdog does. Odometry (frame ``odom``, child ``base_link``) starts at the
odom origin; the pose is integrated exactly for a constant twist over each tick.

    python fake_base.py ROBOT_MODEL RATE_HZ [--stamped]
"""

from __future__ import annotations

import math
import sys

from _spin import run
from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data

from socialnav.core.robot import ROBOT_MODELS

CMD_TIMEOUT = 0.5


class FakeBase(Node):
    def __init__(self, robot_name: str, rate: float, stamped: bool) -> None:
        super().__init__("fake_base")
        self.robot = ROBOT_MODELS[robot_name]
        self.dt = 1.0 / rate
        self.pose = [0.0, 0.0, 0.0]
        self.vel = [0.0, 0.0, 0.0]
        self.cmd = [0.0, 0.0, 0.0]
        self.cmd_time = -math.inf
        kind = TwistStamped if stamped else Twist
        self.create_subscription(kind, "cmd_vel", self.on_cmd, 10)
        self.pub = self.create_publisher(Odometry, "odom", qos_profile_sensor_data)
        self.create_timer(self.dt, self.tick)

    def on_cmd(self, msg: Twist | TwistStamped) -> None:
        t = msg.twist if isinstance(msg, TwistStamped) else msg
        self.cmd = [t.linear.x, t.linear.y, t.angular.z]
        self.cmd_time = self.get_clock().now().nanoseconds * 1e-9

    def tick(self) -> None:
        r = self.robot
        now = self.get_clock().now()
        target = (
            list(self.cmd) if now.nanoseconds * 1e-9 - self.cmd_time < CMD_TIMEOUT else [0.0] * 3
        )
        if not r.holonomic:
            target[1] = 0.0
        lo = (r.min_vel_x, -r.max_vel_y, -r.max_vel_theta)
        hi = (r.max_vel_x, r.max_vel_y, r.max_vel_theta)
        acc = (r.acc_lim_x, r.acc_lim_y, r.acc_lim_theta)
        for k in range(3):
            goal = min(max(target[k], lo[k]), hi[k])
            step = acc[k] * self.dt
            self.vel[k] += min(max(goal - self.vel[k], -step), step)
        vx, vy, w = self.vel
        x, y, th = self.pose
        if abs(w) < 1e-9:
            x += (vx * math.cos(th) - vy * math.sin(th)) * self.dt
            y += (vx * math.sin(th) + vy * math.cos(th)) * self.dt
        else:  # exact arc for a constant body twist
            th2 = th + w * self.dt
            x += (vx * (math.sin(th2) - math.sin(th)) + vy * (math.cos(th2) - math.cos(th))) / w
            y += (-vx * (math.cos(th2) - math.cos(th)) + vy * (math.sin(th2) - math.sin(th))) / w
            th = math.atan2(math.sin(th2), math.cos(th2))
        self.pose = [x, y, th]
        msg = Odometry()
        msg.header.stamp = now.to_msg()
        msg.header.frame_id = "odom"
        msg.child_frame_id = "base_link"
        msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
        msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = (
            math.sin(th / 2),
            math.cos(th / 2),
        )
        msg.twist.twist.linear.x, msg.twist.twist.linear.y = vx, vy
        msg.twist.twist.angular.z = w
        self.pub.publish(msg)


def main() -> None:
    run(lambda: FakeBase(sys.argv[1], float(sys.argv[2]), "--stamped" in sys.argv))


if __name__ == "__main__":
    main()

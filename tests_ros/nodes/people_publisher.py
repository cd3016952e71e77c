"""People publisher: one person walking the Table 1 line (hallway_passing), as a PoseArray.

The person stands at the start until the first goal_pose arrives (so the walk starts with the
robot's task, as in the scenario's t = 0), then walks at the given velocity until the end point.
Published at 10 Hz in frame ``map``, facing the direction of the walk.

    python people_publisher.py X0 Y0 VX VY X_END
"""

from __future__ import annotations

import math
import sys

from _spin import run
from geometry_msgs.msg import Pose, PoseArray, PoseStamped
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data

RATE = 10.0


class PeoplePublisher(Node):
    def __init__(self, x0: float, y0: float, vx: float, vy: float, x_end: float) -> None:
        super().__init__("people_publisher")
        self.start, self.v, self.x_end = (x0, y0), (vx, vy), x_end
        self.t0: float | None = None
        self.create_subscription(PoseStamped, "goal_pose", self.on_goal, 10)
        self.pub = self.create_publisher(PoseArray, "people", qos_profile_sensor_data)
        self.create_timer(1.0 / RATE, self.tick)

    def on_goal(self, msg: PoseStamped) -> None:
        if self.t0 is None:
            self.t0 = self.get_clock().now().nanoseconds * 1e-9

    def tick(self) -> None:
        now = self.get_clock().now()
        t = 0.0 if self.t0 is None else now.nanoseconds * 1e-9 - self.t0
        span = abs((self.x_end - self.start[0]) / self.v[0]) if self.v[0] else math.inf
        t = min(t, span)
        pose = Pose()
        pose.position.x = self.start[0] + self.v[0] * t
        pose.position.y = self.start[1] + self.v[1] * t
        yaw = math.atan2(self.v[1], self.v[0])
        pose.orientation.z, pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
        msg = PoseArray(poses=[pose])
        msg.header.stamp = now.to_msg()
        msg.header.frame_id = "map"
        self.pub.publish(msg)


def main() -> None:
    run(lambda: PeoplePublisher(*(float(a) for a in sys.argv[1:6])))


if __name__ == "__main__":
    main()

"""Map publisher: reads a ROS map YAML as map_server does and latches it on ``map``.

python map_publisher.py MAP_YAML
"""

from __future__ import annotations

import sys

from _spin import run
from nav_msgs.msg import OccupancyGrid
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from socialnav.world.mapio import load_map


class MapPublisher(Node):
    def __init__(self, path: str) -> None:
        super().__init__("map_server")
        omap = load_map(path)
        qos = QoSProfile(
            depth=1,
            durability=DurabilityPolicy.TRANSIENT_LOCAL,
            reliability=ReliabilityPolicy.RELIABLE,
        )
        self.pub = self.create_publisher(OccupancyGrid, "map", qos)
        msg = OccupancyGrid()
        msg.header.frame_id = "map"
        msg.header.stamp = self.get_clock().now().to_msg()
        g = omap.geometry
        msg.info.resolution = float(g.resolution)
        msg.info.height, msg.info.width = g.shape
        msg.info.origin.position.x, msg.info.origin.position.y = map(float, g.origin)
        msg.info.origin.orientation.w = 1.0
        msg.data = omap.to_ros_data().reshape(-1).tolist()
        self.pub.publish(msg)


def main() -> None:
    run(lambda: MapPublisher(sys.argv[1]))


if __name__ == "__main__":
    main()

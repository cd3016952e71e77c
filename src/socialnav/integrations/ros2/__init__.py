"""socialnav on a robot: a ROS 2 lifecycle node around ``build_navigator``.

- :mod:`.node` — the rclpy node (needs the extra: ``pip install 'socialnav[ros]'``); started with
  ``socialnav ros2 --params FILE``.
- :mod:`.params` — its parameters (types, ranges, descriptions) and the params-file reader.
- :mod:`.people` — people tracks (ids, velocities) from ``geometry_msgs/PoseArray`` detections.
- :mod:`.convert` — occupancy grids, quaternions, frames and the safety stop as plain arrays.

Only :mod:`.node` imports rclpy; the other modules are plain Python, tested without ROS.
"""

INSTALL_HINT = (
    "the ROS 2 node needs the optional extra 'ros' (ROS 2 Kilted client wheels from PyPI): "
    "pip install 'socialnav[ros]' — best in its own virtual environment, since the ROS wheels "
    "re-execute Python on import to set the library path"
)

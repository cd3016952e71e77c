"""ROS 2 tests: they run in their own environment (``pip install -e '.[ros]'``, see .ci/run).

Every process of a test run talks over loopback only, on a domain id of its own, so parallel
runs on one machine (and any other ROS graph) never see each other.
"""

from __future__ import annotations

import os

import pytest

# Before rclpy initializes anything, in this process and in the processes it starts.
os.environ.setdefault("ROS_DOMAIN_ID", str(10 + os.getpid() % 90))
os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
os.environ["ROS_LOCALHOST_ONLY"] = "1"
os.environ.setdefault("RMW_IMPLEMENTATION", "rmw_fastrtps_cpp")

rclpy = pytest.importorskip("rclpy")

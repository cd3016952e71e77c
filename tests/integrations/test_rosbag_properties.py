"""Bags as a property: the robot's poses read back from any exported episode."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("rosbags")

from test_rosbag import synthetic_record

from socialnav.integrations.rosbag import export_rosbag, read_rosbag_poses


@settings(max_examples=8, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    # Rooms-sized extents: the bag's map covers the trajectory at 5 cm (km would not fit).
    scale=st.sampled_from([1e-3, 1.0, 10.0]),
    storage=st.sampled_from(["mcap", "sqlite3"]),
)
def test_exported_poses_read_back(tmp_path_factory, seed, scale, storage):
    base = synthetic_record()
    rng = np.random.default_rng(seed)
    poses = base.robot_poses.copy()
    poses[:, :2] = rng.normal(size=(len(poses), 2)) * scale
    poses[:, 2] = rng.uniform(-10.0, 10.0, len(poses))  # unwrapped yaw, any turn count
    record = dataclasses.replace(base, robot_poses=poses)
    path = tmp_path_factory.mktemp("bag") / "episode"
    export_rosbag(record, path, storage=storage)
    times, back = read_rosbag_poses(path)
    np.testing.assert_allclose(times, record.times, rtol=0, atol=1e-9)
    np.testing.assert_allclose(back[:, :2], poses[:, :2], rtol=1e-12, atol=1e-9)
    dyaw = np.angle(np.exp(1j * (back[:, 2] - poses[:, 2])))
    np.testing.assert_allclose(dyaw, 0.0, atol=1e-9)

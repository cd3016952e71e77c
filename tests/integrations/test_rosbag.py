"""rosbag2 export: read the bags back with rosbags' own reader and compare with the record."""

from __future__ import annotations

import builtins
import dataclasses
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rosbags")

from rosbags.rosbag2 import Reader

from socialnav.core.episode import EpisodeRecord
from socialnav.integrations import rosbag as rb
from socialnav.integrations.rosbag import (
    DEFAULT_START_TIME_NS,
    TOPICS,
    export_rosbag,
    make_typestore,
    read_rosbag_poses,
)

T, K, DT = 50, 2, 0.1
STORAGES = ["mcap", "sqlite3"]


def synthetic_record() -> EpisodeRecord:
    """50 samples along an arc (yaw crosses ±π, so wrapping is exercised), 2 walking people."""
    times = np.arange(T) * DT
    yaw = np.linspace(2.5, 4.0, T)  # unwrapped, as recorders may store it
    poses = np.column_stack([1.0 + 0.3 * times, -0.7 + np.sin(times), yaw])
    twists = np.column_stack([np.full(T, 0.4), np.zeros(T), np.linspace(-0.5, 0.5, T)])
    people = np.stack(
        [
            np.column_stack([5.0 - 0.5 * times, np.full(T, 1.0)]),
            np.column_stack([np.full(T, 3.0), -2.0 + 0.25 * times]),
        ],
        axis=1,
    )
    vel = np.stack([np.tile([-0.5, 0.0], (T, 1)), np.tile([0.0, 0.25], (T, 1))], axis=1)
    walls = np.array([[[0.0, -1.5], [10.0, -1.5]], [[0.0, 1.5], [10.0, 1.5]]])
    status = np.array(["OK"] * (T - 1) + ["GOAL_REACHED"], dtype=object)
    return EpisodeRecord(
        dt=DT,
        times=times,
        robot_poses=poses,
        robot_twists=twists,
        robot_footprint=np.array([[0.3, 0.3], [-0.3, 0.3], [-0.3, -0.3], [0.3, -0.3]]),
        robot_radius=0.43,
        people_ids=np.array([7, 11]),
        people_positions=people,
        people_velocities=vel,
        people_radii=np.array([0.25, 0.3]),
        start=poses[0].copy(),
        goal=np.array([9.0, 0.0, 0.0]),
        target=np.array([8.0, 0.5, 1.2]),
        goal_tolerance=0.3,
        time_limit=60.0,
        family="hallway",
        scenario="synthetic",
        walls=walls,
        obstacles=(np.array([[4.0, 0.0], [4.5, 0.0], [4.5, 0.5]]),),
        status=status,
    )


@pytest.fixture(scope="module")
def record() -> EpisodeRecord:
    return synthetic_record()


@pytest.fixture(scope="module", params=STORAGES)
def bag(
    request: pytest.FixtureRequest, record: EpisodeRecord, tmp_path_factory: pytest.TempPathFactory
) -> tuple[str, Path]:
    path = tmp_path_factory.mktemp(request.param) / "missing" / "parents" / "episode"
    out = export_rosbag(record, path, storage=request.param)
    assert out == path
    return request.param, path


def messages(path: Path, topic: str) -> list[tuple[int, object]]:
    store = make_typestore()
    with Reader(path) as reader:
        conns = [c for c in reader.connections if c.topic == topic]
        return [
            (ts, store.deserialize_cdr(raw, c.msgtype))
            for c, ts, raw in reader.messages(connections=conns)
        ]


def test_storage_file_and_parents(bag: tuple[str, Path]) -> None:
    storage, path = bag
    assert (path / "metadata.yaml").is_file()
    suffix = ".mcap" if storage == "mcap" else ".db3"
    assert [p.suffix for p in path.iterdir() if p.name != "metadata.yaml"] == [suffix]


def test_topics_types_and_counts(bag: tuple[str, Path]) -> None:
    _, path = bag
    with Reader(path) as reader:
        topics = {name: (info.msgtype, info.msgcount) for name, info in reader.topics.items()}
        # 8 per sample, 4 latched once, a plan at t = 0, 2 and 4 s
        assert reader.message_count == 8 * T + 4 + 3
        assert reader.start_time == DEFAULT_START_TIME_NS
        assert reader.end_time == DEFAULT_START_TIME_NS + round((T - 1) * DT * 1e9) + 1
    once = {"/walls", "/social_goal", "/tf_static", "/map"}
    counts = {t: 1 if t in once else T for t in TOPICS} | {"/plan": 3}
    assert topics == {t: (ty, counts[t]) for t, ty in TOPICS.items()}


def test_robot_poses_round_trip(bag: tuple[str, Path], record: EpisodeRecord) -> None:
    times, poses = read_rosbag_poses(bag[1])
    np.testing.assert_allclose(times, record.times, rtol=0, atol=1e-9)
    np.testing.assert_allclose(poses[:, :2], record.robot_poses[:, :2], rtol=0, atol=1e-9)
    dyaw = np.angle(np.exp(1j * (poses[:, 2] - record.robot_poses[:, 2])))
    np.testing.assert_allclose(dyaw, 0.0, atol=1e-9)
    assert np.all(np.abs(poses[:, 2]) <= np.pi)


def test_odom_tf_and_cmd_vel(bag: tuple[str, Path], record: EpisodeRecord) -> None:
    path = bag[1]
    odom, tf, cmd = (messages(path, t) for t in ("/odom", "/tf", "/cmd_vel"))
    for k in (0, 17, T - 1):
        ts, o = odom[k]
        assert ts == DEFAULT_START_TIME_NS + round(record.times[k] * 1e9)
        assert o.header.stamp.sec * 10**9 + o.header.stamp.nanosec == ts
        assert (o.header.frame_id, o.child_frame_id) == ("odom", "base_link")
        assert o.twist.twist.linear.x == pytest.approx(record.robot_twists[k, 0], abs=1e-12)
        assert o.twist.twist.angular.z == pytest.approx(record.robot_twists[k, 2], abs=1e-12)
        (tr,) = tf[k][1].transforms
        assert (tr.header.frame_id, tr.child_frame_id) == ("odom", "base_link")
        assert tr.transform.translation.x == pytest.approx(o.pose.pose.position.x, abs=1e-12)
        q = tr.transform.rotation
        assert q.x**2 + q.y**2 + q.z**2 + q.w**2 == pytest.approx(1.0, abs=1e-12)
        assert cmd[k][1].angular.z == pytest.approx(record.robot_twists[k, 2], abs=1e-12)


def test_people_custom_type(bag: tuple[str, Path], record: EpisodeRecord) -> None:
    people = messages(bag[1], "/people")
    assert len(people) == T
    for k in (0, 25, T - 1):
        msg = people[k][1]
        assert type(msg).__msgtype__ == "people_msgs/msg/People"
        assert [p.name for p in msg.people] == ["7", "11"]
        got = np.array([[p.position.x, p.position.y] for p in msg.people])
        np.testing.assert_allclose(got, record.people_positions[k], rtol=0, atol=1e-12)
        vel = np.array([[p.velocity.x, p.velocity.y] for p in msg.people])
        np.testing.assert_allclose(vel, record.people_velocities[k], rtol=0, atol=1e-12)
        assert [float(p.tags[0]) for p in msg.people] == [0.25, 0.3]
        assert all(p.tagnames == ["radius", "yaw"] for p in msg.people)
        # they walk -x and +y: orientation is the heading of motion
        assert [float(p.tags[1]) for p in msg.people] == pytest.approx([np.pi, np.pi / 2])


def test_people_bag_definition_is_self_describing(bag: tuple[str, Path]) -> None:
    """A reader without our type store can rebuild People from the definition stored in the bag."""
    from rosbags.typesys import Stores, get_typestore
    from rosbags.typesys.msg import get_types_from_msg

    with Reader(bag[1]) as reader:
        (conn,) = [c for c in reader.connections if c.topic == "/people"]
        assert "people_msgs/Person" in conn.msgdef.data
        store = get_typestore(Stores.EMPTY)
        store.register(get_types_from_msg(conn.msgdef.data, conn.msgtype))
        _, _, raw = next(iter(reader.messages(connections=[conn])))
    msg = store.deserialize_cdr(raw, conn.msgtype)
    assert len(msg.people) == K


def test_markers_walls_goal_status(bag: tuple[str, Path], record: EpisodeRecord) -> None:
    path = bag[1]
    ((ts, walls),) = messages(path, "/walls")
    assert ts == DEFAULT_START_TIME_NS
    wall, obstacle = walls.markers
    pts = np.array([[p.x, p.y] for p in wall.points])
    np.testing.assert_array_equal(pts, record.walls.reshape(-1, 2))
    assert wall.type == wall.LINE_LIST
    assert len(obstacle.points) == 4  # the triangle outline, closed
    marks = messages(path, "/people_markers")
    last = marks[-1][1].markers
    assert [m.id for m in last] == [7, 11]
    assert all(m.type == m.CYLINDER for m in last)
    np.testing.assert_allclose([m.scale.x for m in last], 2 * record.people_radii)
    np.testing.assert_allclose(
        [[m.pose.position.x, m.pose.position.y] for m in last],
        record.people_positions[-1],
        atol=1e-12,
    )
    ((_, goal),) = messages(path, "/social_goal")
    assert goal.pose.position.x == 8.0
    assert 2 * np.arctan2(goal.pose.orientation.z, goal.pose.orientation.w) == pytest.approx(1.2)
    status = [m.data for _, m in messages(path, "/planner_status")]
    assert status == list(record.status)


def test_latched_topics_offer_transient_local(bag: tuple[str, Path]) -> None:
    from rosbags.interfaces import QosDurability

    with Reader(bag[1]) as reader:
        qos = {c.topic: c.ext.offered_qos_profiles for c in reader.connections}
    for topic in ("/walls", "/social_goal"):
        assert [q.durability for q in qos[topic]] == [QosDurability.TRANSIENT_LOCAL]
    assert qos["/odom"] == []


def test_deterministic(record: EpisodeRecord, tmp_path: Path) -> None:
    a = export_rosbag(record, tmp_path / "a", storage="sqlite3")
    b = export_rosbag(record, tmp_path / "b", storage="sqlite3")
    for topic in ("/odom", "/people", "/walls"):
        ra, rb_ = messages(a, topic), messages(b, topic)
        assert [t for t, _ in ra] == [t for t, _ in rb_]
        assert [repr(m) for _, m in ra] == [repr(m) for _, m in rb_]


def test_start_time_option(record: EpisodeRecord, tmp_path: Path) -> None:
    start = 1_700_000_000_123_456_789
    path = export_rosbag(record, tmp_path / "bag", start_time_ns=start)
    with Reader(path) as reader:
        assert reader.start_time == start
    times, _ = read_rosbag_poses(path)
    np.testing.assert_allclose(times, record.times, atol=1e-9)


def test_existing_bag_refused_unless_overwrite(record: EpisodeRecord, tmp_path: Path) -> None:
    path = export_rosbag(record, tmp_path / "bag", storage="mcap")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        export_rosbag(record, path, storage="mcap")
    export_rosbag(record, path, storage="sqlite3", overwrite=True)
    assert sorted(p.suffix for p in path.iterdir()) == [".db3", ".yaml"]
    _, poses = read_rosbag_poses(path)
    assert poses.shape == (T, 3)


def test_overwrite_refuses_non_bag_folder(record: EpisodeRecord, tmp_path: Path) -> None:
    folder = tmp_path / "notes"
    folder.mkdir()
    (folder / "thesis.tex").write_text("precious")
    with pytest.raises(FileExistsError, match="not a rosbag2 folder"):
        export_rosbag(record, folder, overwrite=True)
    assert (folder / "thesis.tex").read_text() == "precious"


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"storage": "bag"}, "storage"),
        ({"frame_id": "base_link"}, "distinct"),
        ({"start_time_ns": -(10**9)}, "negative"),
    ],
)
def test_bad_options(record: EpisodeRecord, tmp_path: Path, change: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        export_rosbag(record, tmp_path / "bag", **change)
    assert not (tmp_path / "bag").exists()


def test_bad_record(record: EpisodeRecord, tmp_path: Path) -> None:
    poses = record.robot_poses.copy()
    poses[3, 0] = np.nan
    bad = synthetic_record()
    bad.robot_poses = poses
    with pytest.raises(ValueError, match="robot_poses"):
        export_rosbag(bad, tmp_path / "bag")
    bad = synthetic_record()
    bad.times = bad.times[::-1].copy()
    with pytest.raises(ValueError, match="non-decreasing"):
        export_rosbag(bad, tmp_path / "bag")


def test_read_rejects_non_bag(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"metadata\.yaml"):
        read_rosbag_poses(tmp_path)


def test_missing_rosbags_names_the_extra(
    monkeypatch: pytest.MonkeyPatch, record: EpisodeRecord, tmp_path: Path
) -> None:
    real_import = builtins.__import__

    def fake_import(name: str, *args: object, **kwargs: object) -> object:
        if name.startswith("rosbags"):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", fake_import)
    with pytest.raises(ImportError, match=r"socialnav\[rosbag\]"):
        rb.export_rosbag(record, tmp_path / "bag")


def yaw_of(q) -> float:
    return float(np.arctan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y**2 + q.z**2)))


def test_odom_frame_chain_gives_the_map_pose(bag: tuple[str, Path], record: EpisodeRecord) -> None:
    path = bag[1]
    ((_, static),) = messages(path, "/tf_static")
    (tr,) = static.transforms
    assert (tr.header.frame_id, tr.child_frame_id) == ("map", "odom")
    origin = np.array([tr.transform.translation.x, tr.transform.translation.y, 0.0])
    origin[2] = yaw_of(tr.transform.rotation)
    np.testing.assert_allclose(origin[:2], record.robot_poses[0, :2], atol=1e-12)
    for k, (_, o) in enumerate(messages(path, "/odom")):
        p = o.pose.pose.position
        c, s = np.cos(origin[2]), np.sin(origin[2])
        xy = origin[:2] + np.array([c * p.x - s * p.y, s * p.x + c * p.y])
        np.testing.assert_allclose(xy, record.robot_poses[k, :2], atol=1e-9)


def test_map_plan_and_local_plan(bag: tuple[str, Path], record: EpisodeRecord) -> None:
    path = bag[1]
    ((_, grid),) = messages(path, "/map")
    info = grid.info
    data = np.asarray(grid.data).reshape(info.height, info.width)
    assert set(np.unique(data)) == {0, 100}

    def cell(x: float, y: float) -> int:
        col = int((x - info.origin.position.x) // info.resolution)
        row = int((y - info.origin.position.y) // info.resolution)
        return int(data[row, col])

    assert cell(5.0, -1.5) == 100 and cell(5.0, 1.5) == 100  # the walls
    assert cell(4.4, 0.1) == 100  # inside the triangle
    assert cell(2.0, 0.0) == 0
    plans = messages(path, "/plan")
    assert [ts for ts, _ in plans] == [DEFAULT_START_TIME_NS + s * 10**9 for s in (0, 2, 4)]
    # at t = 4 s the synthetic robot grazes the wall (y = -1.46): no plan, an empty path
    assert plans[2][1].poses == []
    for (_, plan), k in zip(plans[:2], (0, 20), strict=True):
        xy = np.array([[q.pose.position.x, q.pose.position.y] for q in plan.poses])
        assert np.hypot(*(xy[0] - record.robot_poses[k, :2])) < 0.05
        assert np.hypot(*(xy[-1] - record.target[:2])) < 0.05
        assert all(cell(x, y) == 0 for x, y in xy)
        assert plan.header.frame_id == "map"
    local = messages(path, "/local_plan")
    for k in (0, 30):
        xy = np.array([[q.pose.position.x, q.pose.position.y] for q in local[k][1].poses])
        np.testing.assert_allclose(xy[0], record.robot_poses[k, :2], atol=1e-9)
        length = np.sum(np.hypot(*np.diff(xy, axis=0).T))
        assert length == pytest.approx(0.4 * 1.7, rel=1e-6)  # vx 0.4 m/s for sim_time


def test_people_poses_carry_orientation(bag: tuple[str, Path], record: EpisodeRecord) -> None:
    poses = messages(bag[1], "/people_poses")
    msg = poses[10][1]
    xy = np.array([[p.position.x, p.position.y] for p in msg.poses])
    np.testing.assert_allclose(xy, record.people_positions[10], atol=1e-12)
    assert [yaw_of(p.orientation) for p in msg.poses] == pytest.approx([np.pi, np.pi / 2])
    marks = messages(bag[1], "/people_markers")[10][1].markers
    assert yaw_of(marks[1].pose.orientation) == pytest.approx(np.pi / 2)


def test_standing_person_keeps_the_scenario_orientation() -> None:
    from socialnav.core.scene import Person, SocialContext

    record = synthetic_record()
    record.people_velocities[:] = 0.0
    record.context = SocialContext((Person(7, (5.0, 1.0), yaw=-1.0),))
    yaws = rb.people_yaws(record)
    assert np.all(yaws[:, 0] == -1.0) and np.all(yaws[:, 1] == 0.0)


def test_export_bag_command_on_a_run_folder(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from socialnav.cli import app
    from socialnav.experiments.storage import load_episode

    run_dir = tmp_path / "run"
    runner = CliRunner()
    result = runner.invoke(app, ["run", "hallway_passing", "--out", str(run_dir)])
    assert result.exit_code == 0, result.output
    for storage in STORAGES:
        out = tmp_path / f"bag_{storage}"
        args = ["export-bag", str(run_dir), "--format", storage, "--out", str(out)]
        result = runner.invoke(app, args)
        assert result.exit_code == 0, result.output
        record = load_episode(run_dir)
        times, poses = read_rosbag_poses(out)
        np.testing.assert_allclose(poses[:, :2], record.robot_poses[:, :2], atol=1e-9)
        np.testing.assert_allclose(times, record.times, atol=1e-9)
        assert len(messages(out, "/plan")) >= 1
    result = runner.invoke(app, ["export-bag", str(run_dir), "--format", "rosbag"])
    assert result.exit_code == 2 and "mcap or sqlite3" in result.output
    result = runner.invoke(app, ["export-bag", str(tmp_path / "nothing")])
    assert result.exit_code == 2 and "episode.json" in result.output


def test_map_bounds_ignore_far_people_and_refuse_a_km_map(tmp_path: Path) -> None:
    """A replayed crowd can span a square; a wall kilometres off is a scale mistake.

    Before: the map covered every person (a pedestrian 3 km away gave a 60,000² grid and
    exhausted memory). The map now covers walls, obstacles, the robot and its target only, and a
    map past the cell limit is refused with the resolution that would fit.
    """
    near = synthetic_record()
    far_people = np.array(near.people_positions, copy=True)
    far_people[:, 0, 0] = 3000.0
    far_people[5:9, 1] = np.nan  # a replayed person absent for part of the episode
    record = dataclasses.replace(near, people_positions=far_people)
    assert rb.episode_map(record).geometry.shape == rb.episode_map(near).geometry.shape
    walls = np.array([[[0.0, -1.5], [5000.0, -1.5]], [[0.0, 1.5], [0.0, 3000.0]]])
    huge = dataclasses.replace(near, walls=walls)
    with pytest.raises(ValueError, match=r"map_resolution ≥ 0\.\d+"):
        export_rosbag(huge, tmp_path / "bag")
    assert not (tmp_path / "bag").exists()

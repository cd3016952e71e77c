"""Export a recorded episode as a rosbag2 (MCAP or SQLite3) for Foxglove, RViz or ``ros2 bag play``.

Written with the pure-Python ``rosbags`` package (optional extra ``socialnav[rosbag]``), so no
ROS installation is needed. Message definitions come from rosbags' ROS 2 Humble type store;
``people_msgs/Person`` and ``people_msgs/People`` (wg-perception/people) are not in it and are
registered from their ``.msg`` text.

Topics (one message per sample unless noted; ``T`` samples, ``K`` people):

==================  ==================================  =========================================
``/tf``             tf2_msgs/TFMessage                  ``frame_id`` → ``base_frame``
``/odom``           nav_msgs/Odometry                   pose in ``frame_id``; body twist (below)
``/cmd_vel``        geometry_msgs/Twist                 command issued at the sample
``/people``         people_msgs/People                  name = person id, tag ``radius`` (m)
``/people_markers`` visualization_msgs/MarkerArray      one cylinder per person (ns ``people``)
``/walls``          visualization_msgs/MarkerArray      once at the first sample, latched
``/social_goal``    geometry_msgs/PoseStamped           ``record.target``, once, latched
``/planner_status`` std_msgs/String                     planner status name
==================  ==================================  =========================================

Decisions:
- Time: a sample at ``record.times[k]`` seconds is stamped ``start_time_ns + round(times[k]·1e9)``
  nanoseconds (header stamp = bag log time), ``start_time_ns`` defaulting to
  :data:`DEFAULT_START_TIME_NS` (1 s after the Unix epoch: a zero stamp means "latest"/"unset" to
  tf2 and message filters). The start is stored in the bag's ``custom_data`` so readers can undo it.
- There is no odometry frame: ``/odom`` and ``/tf`` give the ground-truth pose in ``frame_id``.
- ``/odom`` twist is ``record.robot_twists[k]``, the body twist held over ``[t_k, t_k + dt)``
  (the simulator tracks commands exactly), so it equals ``/cmd_vel`` at the same stamp.
- Latched topics (``/walls``, ``/social_goal``) are offered with TRANSIENT_LOCAL durability so
  ``ros2 bag play`` republishes them to late subscribers such as RViz.
- rosbag2 metadata version 8 (the oldest rosbags writes) for the widest reader support.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Literal

import numpy as np
import yaml

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import FloatArray

__all__ = [
    "DEFAULT_START_TIME_NS",
    "PEOPLE_MSG",
    "PERSON_MSG",
    "TOPICS",
    "export_rosbag",
    "make_typestore",
    "read_rosbag_poses",
]

DEFAULT_START_TIME_NS = 1_000_000_000
"""Stamp (ns since the Unix epoch) of ``t = 0`` in exported bags."""

PERSON_MSG = """\
string name
geometry_msgs/Point position
geometry_msgs/Point velocity
float64 reliability
string[] tagnames
string[] tags
"""
PEOPLE_MSG = """\
std_msgs/Header header
people_msgs/Person[] people
"""

TOPICS: dict[str, str] = {
    "/tf": "tf2_msgs/msg/TFMessage",
    "/odom": "nav_msgs/msg/Odometry",
    "/cmd_vel": "geometry_msgs/msg/Twist",
    "/people": "people_msgs/msg/People",
    "/people_markers": "visualization_msgs/msg/MarkerArray",
    "/walls": "visualization_msgs/msg/MarkerArray",
    "/social_goal": "geometry_msgs/msg/PoseStamped",
    "/planner_status": "std_msgs/msg/String",
}
"""Every topic an exported bag contains, with its message type."""

_LATCHED = frozenset({"/walls", "/social_goal"})
_ROSBAG_VERSION = 8
_START_KEY = "socialnav.start_time_ns"
PERSON_HEIGHT = 1.7  # m, cylinder height of a person marker
WALL_WIDTH = 0.05  # m, LINE_LIST width of wall markers
# Files a rosbag2 folder may hold (incl. an aborted write); overwrite deletes nothing else.
_BAG_SUFFIXES = frozenset(
    {".mcap", ".db3", ".db3-shm", ".db3-wal", ".db3-journal", ".yaml", ".zstd"}
)


def _rosbags() -> SimpleNamespace:
    """Import rosbags lazily: it is an optional extra."""
    try:
        from rosbags.interfaces import (
            Qos,
            QosDurability,
            QosHistory,
            QosLiveliness,
            QosReliability,
            QosTime,
        )
        from rosbags.rosbag2 import Reader, StoragePlugin, Writer
        from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    except ImportError as exc:  # missing, or older than the Writer(version=, storage_plugin=) API
        raise ImportError(
            "rosbag export needs the optional dependency 'rosbags>=0.10': "
            "pip install 'socialnav[rosbag]'"
        ) from exc
    return SimpleNamespace(
        Qos=Qos,
        QosDurability=QosDurability,
        QosHistory=QosHistory,
        QosLiveliness=QosLiveliness,
        QosReliability=QosReliability,
        QosTime=QosTime,
        Reader=Reader,
        StoragePlugin=StoragePlugin,
        Writer=Writer,
        Stores=Stores,
        get_types_from_msg=get_types_from_msg,
        get_typestore=get_typestore,
    )


def make_typestore() -> Any:
    """A fresh ROS 2 Humble ``rosbags`` type store with ``people_msgs/msg/{Person,People}`` added.

    Use it to deserialize the ``/people`` topic of an exported bag
    (``store.deserialize_cdr(raw, "people_msgs/msg/People")``).
    """
    rb = _rosbags()
    store = rb.get_typestore(rb.Stores.ROS2_HUMBLE)  # a new instance: registering is local
    types = {}
    types.update(rb.get_types_from_msg(PERSON_MSG, "people_msgs/msg/Person"))
    types.update(rb.get_types_from_msg(PEOPLE_MSG, "people_msgs/msg/People"))
    store.register(types)
    return store


def _stamps_ns(times: FloatArray, start_time_ns: int) -> np.ndarray:
    return int(start_time_ns) + np.rint(np.asarray(times, dtype=float) * 1e9).astype(np.int64)


def _validate(
    record: EpisodeRecord, storage: str, frame_id: str, base_frame: str, start_time_ns: int
) -> np.ndarray:
    """Check the record and options; return the ``(T,)`` int64 stamps (ns)."""
    if storage not in ("mcap", "sqlite3"):
        raise ValueError(f"storage must be 'mcap' or 'sqlite3', got {storage!r}")
    if not frame_id or not base_frame or frame_id == base_frame:
        raise ValueError(
            f"frame ids must be non-empty and distinct, got {frame_id!r}, {base_frame!r}"
        )
    times = np.asarray(record.times, dtype=float)
    if times.ndim != 1 or times.size == 0:
        raise ValueError(f"record.times must be a non-empty 1-D array, got shape {times.shape}")
    arrays = {
        "times": times,
        "robot_poses": record.robot_poses,
        "robot_twists": record.robot_twists,
        "people_positions": record.people_positions,
        "people_velocities": record.people_velocities,
        "people_radii": record.people_radii,
        "target": record.target,
        "walls": record.walls,
    }
    for name, arr in arrays.items():
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"record.{name} contains NaN or infinite values")
    if np.any(np.diff(times) < 0):
        raise ValueError("record.times must be non-decreasing")
    stamps = _stamps_ns(times, start_time_ns)
    if stamps[0] < 0:
        raise ValueError(f"first stamp {stamps[0]} ns is negative: raise start_time_ns")
    return stamps


def _prepare_path(path: Path, overwrite: bool) -> None:
    if path.exists() or path.is_symlink():
        if not overwrite:
            raise FileExistsError(
                f"{path} exists; rosbag2 writers only create new bags "
                "(pass overwrite=True to replace an existing bag)"
            )
        entries = list(path.iterdir()) if path.is_dir() and not path.is_symlink() else None
        if entries is None or any(
            not e.is_file() or e.suffix not in _BAG_SUFFIXES for e in entries
        ):
            raise FileExistsError(
                f"refusing to overwrite {path}: it is not a rosbag2 folder "
                "(only .mcap/.db3/.yaml files are deleted)"
            )
        shutil.rmtree(path)
    path.parent.mkdir(parents=True, exist_ok=True)


def _yaw_quaternions(yaw: FloatArray) -> FloatArray:
    """``(N, 4)`` quaternions ``(x, y, z, w)`` of rotations by ``yaw (N,)`` about +z."""
    half = 0.5 * np.asarray(yaw, dtype=float)
    q = np.zeros((half.size, 4))
    q[:, 2], q[:, 3] = np.sin(half), np.cos(half)
    return q


class _Messages:
    """Builds the message objects of one type store (keeps export_rosbag readable)."""

    def __init__(self, store: Any) -> None:
        self.t = store.types
        self.zero_duration = self.t["builtin_interfaces/msg/Duration"](sec=0, nanosec=0)

    def header(self, ns: int, frame: str) -> Any:
        sec, nanosec = divmod(int(ns), 1_000_000_000)
        stamp = self.t["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec)
        return self.t["std_msgs/msg/Header"](stamp=stamp, frame_id=frame)

    def point(self, x: float, y: float, z: float = 0.0) -> Any:
        return self.t["geometry_msgs/msg/Point"](x=float(x), y=float(y), z=float(z))

    def vector3(self, x: float, y: float, z: float) -> Any:
        return self.t["geometry_msgs/msg/Vector3"](x=float(x), y=float(y), z=float(z))

    def quaternion(self, q: FloatArray) -> Any:
        return self.t["geometry_msgs/msg/Quaternion"](
            x=float(q[0]), y=float(q[1]), z=float(q[2]), w=float(q[3])
        )

    def pose(self, x: float, y: float, q: FloatArray, z: float = 0.0) -> Any:
        return self.t["geometry_msgs/msg/Pose"](
            position=self.point(x, y, z), orientation=self.quaternion(q)
        )

    def twist(self, cmd: FloatArray) -> Any:
        return self.t["geometry_msgs/msg/Twist"](
            linear=self.vector3(cmd[0], cmd[1], 0.0), angular=self.vector3(0.0, 0.0, cmd[2])
        )

    def color(self, r: float, g: float, b: float, a: float) -> Any:
        return self.t["std_msgs/msg/ColorRGBA"](r=r, g=g, b=b, a=a)

    def marker(
        self,
        header: Any,
        ns: str,
        mid: int,
        kind: str,
        pose: Any,
        scale: Any,
        color: Any,
        points: list[Any] | None = None,
    ) -> Any:
        marker_cls = self.t["visualization_msgs/msg/Marker"]
        return marker_cls(
            header=header,
            ns=ns,
            id=int(mid),
            type=getattr(marker_cls, kind),
            action=marker_cls.ADD,
            pose=pose,
            scale=scale,
            color=color,
            lifetime=self.zero_duration,
            frame_locked=False,
            points=points or [],
            colors=[],
            texture_resource="",
            texture=self.t["sensor_msgs/msg/CompressedImage"](
                header=header, format="", data=np.zeros(0, dtype=np.uint8)
            ),
            uv_coordinates=[],
            text="",
            mesh_resource="",
            mesh_file=self.t["visualization_msgs/msg/MeshFile"](
                filename="", data=np.zeros(0, dtype=np.uint8)
            ),
            mesh_use_embedded_materials=False,
        )


def export_rosbag(
    record: EpisodeRecord,
    path: Path | str,
    storage: Literal["sqlite3", "mcap"] = "mcap",
    frame_id: str = "map",
    *,
    base_frame: str = "base_link",
    overwrite: bool = False,
    start_time_ns: int = DEFAULT_START_TIME_NS,
) -> Path:
    """Write ``record`` as a rosbag2 folder at ``path`` and return ``path``.

    ``path`` is the bag *folder* (rosbag2 layout: ``metadata.yaml`` plus one ``.mcap`` or
    ``.db3`` file); missing parents are created. An existing ``path`` raises
    :class:`FileExistsError` unless ``overwrite`` is true, in which case an existing rosbag2
    folder is replaced (anything else is refused). Topics, stamps and frames: see the module
    docstring. Deterministic: the same record gives the same messages and stamps.
    """
    rb = _rosbags()
    path = Path(path)
    stamps = _validate(record, storage, frame_id, base_frame, start_time_ns)
    _prepare_path(path, overwrite)

    store = make_typestore()
    m = _Messages(store)
    poses = np.asarray(record.robot_poses, dtype=float)
    twists = np.asarray(record.robot_twists, dtype=float)
    quats = _yaw_quaternions(poses[:, 2])
    people_xy = np.asarray(record.people_positions, dtype=float)
    people_v = np.asarray(record.people_velocities, dtype=float)
    radii = np.asarray(record.people_radii, dtype=float)
    pids = np.asarray(record.people_ids)
    ids = [str(i) for i in pids.tolist()]
    # Marker ids must be ints: use the person ids when they are, else their index.
    marker_ids = pids.tolist() if np.issubdtype(pids.dtype, np.integer) else list(range(pids.size))
    status = [str(s) for s in np.asarray(record.status).tolist()]
    zero_cov = np.zeros(36)
    latched = [
        rb.Qos(
            rb.QosHistory.KEEP_LAST,
            1,
            rb.QosReliability.RELIABLE,
            rb.QosDurability.TRANSIENT_LOCAL,
            rb.QosTime(0, 0),
            rb.QosTime(0, 0),
            rb.QosLiveliness.AUTOMATIC,
            rb.QosTime(0, 0),
            False,
        )
    ]
    plugin = rb.StoragePlugin.MCAP if storage == "mcap" else rb.StoragePlugin.SQLITE3
    t = m.t

    writer = rb.Writer(path, version=_ROSBAG_VERSION, storage_plugin=plugin)
    writer.set_custom_data(_START_KEY, str(int(start_time_ns)))
    writer.set_custom_data("socialnav.scenario", str(record.scenario))
    writer.set_custom_data("socialnav.family", str(record.family))
    writer.set_custom_data("socialnav.dt", repr(float(record.dt)))
    with writer:
        conns = {
            topic: writer.add_connection(
                topic,
                msgtype,
                typestore=store,
                offered_qos_profiles=latched if topic in _LATCHED else (),
            )
            for topic, msgtype in TOPICS.items()
        }

        def write(topic: str, ns: int, msg: Any) -> None:
            writer.write(conns[topic], int(ns), store.serialize_cdr(msg, TOPICS[topic]))

        # Static world and task, once at the first stamp.
        t0 = int(stamps[0])
        h0 = m.header(t0, frame_id)
        identity = m.pose(0.0, 0.0, np.array([0.0, 0.0, 0.0, 1.0]))
        wall_markers = []
        walls = np.asarray(record.walls, dtype=float).reshape(-1, 2, 2)
        if walls.shape[0]:
            wall_markers.append(
                m.marker(
                    h0,
                    "walls",
                    0,
                    "LINE_LIST",
                    identity,
                    m.vector3(WALL_WIDTH, 0.0, 0.0),
                    m.color(0.3, 0.3, 0.3, 1.0),
                    [m.point(x, y) for x, y in walls.reshape(-1, 2)],
                )
            )
        for i, poly in enumerate(record.obstacles):
            ring = np.vstack([poly, poly[:1]])  # close the outline
            wall_markers.append(
                m.marker(
                    h0,
                    "obstacles",
                    i,
                    "LINE_STRIP",
                    identity,
                    m.vector3(WALL_WIDTH, 0.0, 0.0),
                    m.color(0.3, 0.3, 0.3, 1.0),
                    [m.point(x, y) for x, y in ring],
                )
            )
        write("/walls", t0, t["visualization_msgs/msg/MarkerArray"](markers=wall_markers))
        target = np.asarray(record.target, dtype=float)
        write(
            "/social_goal",
            t0,
            t["geometry_msgs/msg/PoseStamped"](
                header=h0, pose=m.pose(target[0], target[1], _yaw_quaternions(target[2:3])[0])
            ),
        )

        for k, ns in enumerate(stamps.tolist()):
            header = m.header(ns, frame_id)
            x, y = poses[k, 0], poses[k, 1]
            transform = t["geometry_msgs/msg/Transform"](
                translation=m.vector3(x, y, 0.0), rotation=m.quaternion(quats[k])
            )
            write(
                "/tf",
                ns,
                t["tf2_msgs/msg/TFMessage"](
                    transforms=[
                        t["geometry_msgs/msg/TransformStamped"](
                            header=header, child_frame_id=base_frame, transform=transform
                        )
                    ]
                ),
            )
            write(
                "/odom",
                ns,
                t["nav_msgs/msg/Odometry"](
                    header=header,
                    child_frame_id=base_frame,
                    pose=t["geometry_msgs/msg/PoseWithCovariance"](
                        pose=m.pose(x, y, quats[k]), covariance=zero_cov
                    ),
                    twist=t["geometry_msgs/msg/TwistWithCovariance"](
                        twist=m.twist(twists[k]), covariance=zero_cov
                    ),
                ),
            )
            write("/cmd_vel", ns, m.twist(twists[k]))
            write(
                "/people",
                ns,
                t["people_msgs/msg/People"](
                    header=header,
                    people=[
                        t["people_msgs/msg/Person"](
                            name=ids[j],
                            position=m.point(*people_xy[k, j]),
                            velocity=m.point(*people_v[k, j]),
                            reliability=1.0,
                            tagnames=["radius"],
                            tags=[repr(float(radii[j]))],
                        )
                        for j in range(len(ids))
                    ],
                ),
            )
            write(
                "/people_markers",
                ns,
                t["visualization_msgs/msg/MarkerArray"](
                    markers=[
                        m.marker(
                            header,
                            "people",
                            marker_ids[j],
                            "CYLINDER",
                            m.pose(
                                float(people_xy[k, j, 0]),
                                float(people_xy[k, j, 1]),
                                np.array([0.0, 0.0, 0.0, 1.0]),
                                z=0.5 * PERSON_HEIGHT,
                            ),
                            m.vector3(2 * radii[j], 2 * radii[j], PERSON_HEIGHT),
                            m.color(0.2, 0.4, 0.9, 0.7),
                        )
                        for j in range(len(ids))
                    ]
                ),
            )
            write("/planner_status", ns, t["std_msgs/msg/String"](data=status[k]))
    return path


def read_rosbag_poses(path: Path | str) -> tuple[FloatArray, FloatArray]:
    """Robot poses from the ``/odom`` topic of a rosbag2 folder.

    Returns ``times (T,)`` in seconds — relative to the export's ``start_time_ns`` when the bag
    was written by :func:`export_rosbag`, else absolute header stamps — and ``poses (T, 3)``
    ``[x, y, yaw]`` (m, m, rad in ``(-π, π]``), in bag order.
    """
    rb = _rosbags()
    path = Path(path)
    meta_file = path / "metadata.yaml"
    if not meta_file.is_file():
        raise FileNotFoundError(f"{path} is not a rosbag2 folder (no metadata.yaml)")
    info = yaml.safe_load(meta_file.read_text()).get("rosbag2_bagfile_information", {})
    start_ns = int((info.get("custom_data") or {}).get(_START_KEY, 0))
    store = make_typestore()
    stamps: list[int] = []
    rows: list[tuple[float, float, float]] = []
    with rb.Reader(path) as reader:
        conns = [c for c in reader.connections if c.topic == "/odom"]
        if not conns:
            raise ValueError(f"{path} has no /odom topic")
        for conn, _, raw in reader.messages(connections=conns):
            msg = store.deserialize_cdr(raw, conn.msgtype)
            stamp = msg.header.stamp
            stamps.append(stamp.sec * 1_000_000_000 + stamp.nanosec)
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
            rows.append((p.x, p.y, yaw))
    times = (np.asarray(stamps, dtype=np.int64) - start_ns) / 1e9
    return times, np.asarray(rows, dtype=float).reshape(-1, 3)

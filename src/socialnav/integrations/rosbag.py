"""Export a recorded episode as a rosbag2 (MCAP or SQLite3) for Foxglove, RViz or ``ros2 bag play``.

Written with the pure-Python ``rosbags`` package (optional extra ``socialnav[rosbag]``), so no
ROS installation is needed. Message definitions come from rosbags' ROS 2 Humble type store;
``people_msgs/Person`` and ``people_msgs/People`` (wg-perception/people) are not in it and are
registered from their ``.msg`` text.

Topics (one message per sample unless noted; ``T`` samples, ``K`` people):

==================  ==================================  =========================================
``/tf_static``      tf2_msgs/TFMessage                  ``frame_id`` → ``odom_frame``, once, latched
``/tf``             tf2_msgs/TFMessage                  ``odom_frame`` → ``base_frame``
``/odom``           nav_msgs/Odometry                   pose in ``odom_frame``; body twist (below)
``/cmd_vel``        geometry_msgs/Twist                 command issued at the sample
``/map``            nav_msgs/OccupancyGrid              walls and obstacles, once, latched
``/plan``           nav_msgs/Path                       global plan, every ``replan_period`` s
``/local_plan``     nav_msgs/Path                       the command's rollout over ``sim_time`` s
``/people``         people_msgs/People                  name = person id, tags ``radius`` (m),
                                                        ``yaw`` (rad)
``/people_poses``   geometry_msgs/PoseArray             people with orientation (the ROS node's
                                                        input), in person-id order
``/people_markers`` visualization_msgs/MarkerArray      one cylinder per person (ns ``people``),
                                                        oriented
``/walls``          visualization_msgs/MarkerArray      once at the first sample, latched
``/social_goal``    geometry_msgs/PoseStamped           ``record.target``, once, latched
``/planner_status`` std_msgs/String                     planner status name
==================  ==================================  =========================================

Decisions:
- Time: a sample at ``record.times[k]`` seconds is stamped ``start_time_ns + round(times[k]·1e9)``
  nanoseconds (header stamp = bag log time), ``start_time_ns`` defaulting to
  :data:`DEFAULT_START_TIME_NS` (1 s after the Unix epoch: a zero stamp means "latest"/"unset" to
  tf2 and message filters). The start is stored in the bag's ``custom_data`` so readers can undo it.
- Frames as REP 105: ``frame_id`` (map) → ``odom_frame`` is the start pose (static: the
  simulator's odometry does not drift), ``odom_frame`` → ``base_frame`` the pose since the start;
  :func:`read_rosbag_poses` composes them back into ``frame_id``.
- ``/map`` is the walls and obstacles rasterized at ``map_resolution`` (m/cell) over their bounds,
  the robot's positions and its target, plus 1 m (trinary: 0 free, 100 occupied). People are not
  in the bounds: a recorded crowd may span a whole square, and RViz draws markers off the map.
  A map over :data:`MAX_MAP_CELLS` cells raises ``ValueError`` naming a resolution that fits.
- ``/plan`` is the global planner (:func:`~socialnav.planner.global_planner.plan_path`, navfn
  costs) rerun on that map, inflated for the robot's inscribed radius, from the recorded pose to
  ``record.target`` every ``replan_period`` s: the plan a Nav2 global planner makes there (people
  are not in it; the planners that add a personal-space cost plan around them too). An empty
  path when no plan exists. ``/local_plan`` is the recorded command rolled out for ``sim_time``
  s from the pose (DWB publishes the chosen trajectory the same way).
- People's orientation (``yaw``): the heading of their velocity while they move faster than
  0.05 m/s, else the last one, starting from the scenario's ``yaw`` (the record's context).
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
from socialnav.core.geometry import FloatArray, point_segment_distance, polygon_edges, wrap_angle
from socialnav.core.robot import PR2
from socialnav.planner.global_planner import plan_path
from socialnav.planner.rollout import RolloutParams, rollout
from socialnav.world.grid import GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.mapio import OccupancyMap
from socialnav.world.raster import rasterize

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
    "/tf_static": "tf2_msgs/msg/TFMessage",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/odom": "nav_msgs/msg/Odometry",
    "/cmd_vel": "geometry_msgs/msg/Twist",
    "/map": "nav_msgs/msg/OccupancyGrid",
    "/plan": "nav_msgs/msg/Path",
    "/local_plan": "nav_msgs/msg/Path",
    "/people": "people_msgs/msg/People",
    "/people_poses": "geometry_msgs/msg/PoseArray",
    "/people_markers": "visualization_msgs/msg/MarkerArray",
    "/walls": "visualization_msgs/msg/MarkerArray",
    "/social_goal": "geometry_msgs/msg/PoseStamped",
    "/planner_status": "std_msgs/msg/String",
}
"""Every topic an exported bag contains, with its message type."""

_LATCHED = frozenset({"/walls", "/social_goal", "/tf_static", "/map"})
MOVING_SPEED = 0.05  # m/s: slower people keep their orientation
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


def people_yaws(record: EpisodeRecord) -> FloatArray:
    """``(T, K)`` people's orientation (rad): heading of motion above :data:`MOVING_SPEED`,
    else held, starting from the context's ``yaw`` (0 for a person the context lacks)."""
    v = np.asarray(record.people_velocities, dtype=float)
    ids = np.asarray(record.people_ids).tolist()
    known = {p.id: p.yaw for p in record.context.people}
    current = np.array([float(known.get(i, 0.0)) for i in ids])
    moving = np.hypot(v[..., 0], v[..., 1]) > MOVING_SPEED
    heading = np.arctan2(v[..., 1], v[..., 0])
    out = np.zeros(moving.shape)
    for k in range(moving.shape[0]):
        current = np.where(moving[k], heading[k], current)
        out[k] = current
    return out


def relative_poses(origin: FloatArray, poses: FloatArray) -> FloatArray:
    """``poses (T, 3)`` expressed in the frame whose pose is ``origin (3,)`` (both planar)."""
    d = np.asarray(poses, dtype=float)[:, :2] - origin[:2]
    c, s = math.cos(origin[2]), math.sin(origin[2])
    return np.column_stack(
        [c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1], wrap_angle(poses[:, 2] - origin[2])]
    )


def _compose(frame: FloatArray, pose: FloatArray) -> FloatArray:
    c, s = math.cos(frame[2]), math.sin(frame[2])
    return np.array(
        [
            frame[0] + c * pose[0] - s * pose[1],
            frame[1] + s * pose[0] + c * pose[1],
            float(wrap_angle(frame[2] + pose[2])),
        ]
    )


# 25 M cells is a 250 m × 250 m map at 0.05 m (25 MB as int8): beyond it a bag's map is a mistake
# of scale (a wall kilometres away), not a map anyone views, and would exhaust memory.
MAX_MAP_CELLS = 25_000_000


def episode_map(record: EpisodeRecord, resolution: float = 0.05) -> OccupancyMap:
    """The walls and obstacles of ``record`` as a trinary occupancy map over their bounds, the
    robot's recorded positions and its target, plus 1 m.

    Raises ``ValueError`` when the map would exceed :data:`MAX_MAP_CELLS` cells at
    ``resolution`` (m/cell), naming the coarsest resolution that fits."""
    walls = np.asarray(record.walls, dtype=float).reshape(-1, 2, 2)
    pts = np.concatenate(
        [
            walls.reshape(-1, 2),
            *[np.asarray(o, dtype=float).reshape(-1, 2) for o in record.obstacles],
            np.asarray(record.robot_poses, dtype=float)[:, :2],
            np.asarray(record.target, dtype=float)[None, :2],
        ]
    )
    pts = pts[np.isfinite(pts).all(axis=1)]
    lo, hi = pts.min(axis=0) - 1.0, pts.max(axis=0) + 1.0
    extent = hi - lo
    cells = math.ceil(extent[1] / resolution) * math.ceil(extent[0] / resolution)
    if cells > MAX_MAP_CELLS:
        fits = 1.01 * math.sqrt(float(extent[0] * extent[1]) / MAX_MAP_CELLS)
        raise ValueError(
            f"map_resolution {resolution} m gives a {extent[0]:.0f} m × {extent[1]:.0f} m map of "
            f"{cells} cells (limit {MAX_MAP_CELLS}); use map_resolution ≥ {fits:.3g}"
        )
    shape = (math.ceil(extent[1] / resolution), math.ceil(extent[0] / resolution))
    geometry = GridGeometry(shape, resolution, (float(lo[0]), float(lo[1])))
    occupied = rasterize(
        geometry, segments=walls, polygons=[np.asarray(o, dtype=float) for o in record.obstacles]
    )
    return OccupancyMap.from_masks(occupied, geometry)


def global_plans(
    record: EpisodeRecord, omap: OccupancyMap, replan_period: float
) -> list[tuple[int, FloatArray]]:
    """``(sample index, path (P, 2))`` every ``replan_period`` s: the global planner on ``omap``
    inflated for the footprint's inscribed radius, from the recorded pose to ``record.target``
    (``(0, 2)`` when no plan exists)."""
    a, b = polygon_edges(np.asarray(record.robot_footprint, dtype=float))
    inscribed = float(point_segment_distance(np.zeros(2), a, b).min())
    costmap = inflate(omap.occupied_mask(), omap.geometry, inscribed)
    out, last = [], -math.inf
    for k, t in enumerate(np.asarray(record.times, dtype=float).tolist()):
        if t - last >= replan_period - 1e-9:
            plan = plan_path(costmap, record.robot_poses[k, :2], record.target[:2])
            out.append((k, np.zeros((0, 2)) if plan.path is None else plan.path))
            last = t
    return out


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

    def transform(self, header: Any, child: str, pose: FloatArray) -> Any:
        q = _yaw_quaternions(np.asarray(pose[2:3], dtype=float))[0]
        return self.t["geometry_msgs/msg/TransformStamped"](
            header=header,
            child_frame_id=child,
            transform=self.t["geometry_msgs/msg/Transform"](
                translation=self.vector3(pose[0], pose[1], 0.0), rotation=self.quaternion(q)
            ),
        )

    def path(self, header: Any, xy: FloatArray, yaw: FloatArray | None = None) -> Any:
        """``nav_msgs/Path`` through ``xy (P, 2)``; orientation ``yaw (P,)`` or along the path."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        if yaw is None:
            d = np.diff(xy, axis=0)
            yaw = np.arctan2(d[:, 1], d[:, 0]) if len(d) else np.zeros(len(xy))
            if len(d):
                yaw = np.append(yaw, yaw[-1])
        quats = _yaw_quaternions(np.asarray(yaw, dtype=float))
        stamped = self.t["geometry_msgs/msg/PoseStamped"]
        return self.t["nav_msgs/msg/Path"](
            header=header,
            poses=[
                stamped(header=header, pose=self.pose(x, y, q))
                for (x, y), q in zip(xy, quats, strict=True)
            ],
        )

    def occupancy_grid(self, header: Any, omap: OccupancyMap) -> Any:
        g = omap.geometry
        info = self.t["nav_msgs/msg/MapMetaData"](
            map_load_time=header.stamp,
            resolution=float(g.resolution),
            width=int(g.shape[1]),
            height=int(g.shape[0]),
            origin=self.pose(g.origin[0], g.origin[1], np.array([0.0, 0.0, 0.0, 1.0])),
        )
        data = omap.to_ros_data().reshape(-1).astype(np.int8)
        return self.t["nav_msgs/msg/OccupancyGrid"](header=header, info=info, data=data)

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
    odom_frame: str = "odom",
    overwrite: bool = False,
    start_time_ns: int = DEFAULT_START_TIME_NS,
    map_resolution: float = 0.05,
    replan_period: float = 2.0,
    sim_time: float = 1.7,
) -> Path:
    """Write ``record`` as a rosbag2 folder at ``path`` and return ``path``.

    ``path`` is the bag *folder* (rosbag2 layout: ``metadata.yaml`` plus one ``.mcap`` or
    ``.db3`` file); missing parents are created. An existing ``path`` raises
    :class:`FileExistsError` unless ``overwrite`` is true, in which case an existing rosbag2
    folder is replaced (anything else is refused). Topics, stamps and frames: see the module
    docstring; ``map_resolution`` (m/cell), ``replan_period`` (s) and ``sim_time`` (s) shape
    ``/map``, ``/plan`` and ``/local_plan``. Deterministic: the same record gives the same
    messages and stamps.
    """
    rb = _rosbags()
    path = Path(path)
    stamps = _validate(record, storage, frame_id, base_frame, start_time_ns)
    if odom_frame in ("", frame_id, base_frame):
        raise ValueError(f"odom_frame {odom_frame!r} must be non-empty and distinct")
    for name, value in (
        ("map_resolution", map_resolution),
        ("replan_period", replan_period),
        ("sim_time", sim_time),
    ):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be positive, got {value}")
    omap = episode_map(record, map_resolution)  # before the folder exists: a refusal leaves none
    _prepare_path(path, overwrite)

    store = make_typestore()
    m = _Messages(store)
    poses = np.asarray(record.robot_poses, dtype=float)
    twists = np.asarray(record.robot_twists, dtype=float)
    odom_origin = poses[0].copy()
    odom_poses = relative_poses(odom_origin, poses)
    quats = _yaw_quaternions(odom_poses[:, 2])
    plans = dict(global_plans(record, omap, replan_period))
    rollout_params = RolloutParams(sim_time=sim_time)
    yaws = people_yaws(record)
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
        write(
            "/tf_static",
            t0,
            t["tf2_msgs/msg/TFMessage"](transforms=[m.transform(h0, odom_frame, odom_origin)]),
        )
        write("/map", t0, m.occupancy_grid(h0, omap))
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
            odom_header = m.header(ns, odom_frame)
            x, y = odom_poses[k, 0], odom_poses[k, 1]
            write(
                "/tf",
                ns,
                t["tf2_msgs/msg/TFMessage"](
                    transforms=[m.transform(odom_header, base_frame, odom_poses[k])]
                ),
            )
            write(
                "/odom",
                ns,
                t["nav_msgs/msg/Odometry"](
                    header=odom_header,
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
            if k in plans:
                write("/plan", ns, m.path(header, plans[k]))
            # DWA rollout of the command held for sim_time (the robot model is not used by it)
            local = rollout(poses[k], twists[k], twists[k : k + 1], PR2, rollout_params).poses[0]
            write("/local_plan", ns, m.path(header, local[:, :2], local[:, 2]))
            people_q = _yaw_quaternions(yaws[k])
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
                            tagnames=["radius", "yaw"],
                            tags=[repr(float(radii[j])), repr(float(yaws[k, j]))],
                        )
                        for j in range(len(ids))
                    ],
                ),
            )
            write(
                "/people_poses",
                ns,
                t["geometry_msgs/msg/PoseArray"](
                    header=header,
                    poses=[
                        m.pose(people_xy[k, j, 0], people_xy[k, j, 1], people_q[j])
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
                                people_xy[k, j, 0],
                                people_xy[k, j, 1],
                                people_q[j],
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
    """Robot poses from the ``/odom`` topic of a rosbag2 folder, in the frame above the
    odometry frame in ``/tf_static`` (the map, for bags of :func:`export_rosbag`; the odometry
    frame itself when the bag has no such transform).

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
    parents: dict[str, FloatArray] = {}
    with rb.Reader(path) as reader:
        static = [c for c in reader.connections if c.topic == "/tf_static"]
        for conn, _, raw in reader.messages(connections=static):
            for tr in store.deserialize_cdr(raw, conn.msgtype).transforms:
                v, q = tr.transform.translation, tr.transform.rotation
                parents[tr.child_frame_id] = np.array([v.x, v.y, _yaw(q)])
        conns = [c for c in reader.connections if c.topic == "/odom"]
        if not conns:
            raise ValueError(f"{path} has no /odom topic")
        for conn, _, raw in reader.messages(connections=conns):
            msg = store.deserialize_cdr(raw, conn.msgtype)
            stamp = msg.header.stamp
            stamps.append(stamp.sec * 1_000_000_000 + stamp.nanosec)
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            pose = np.array([p.x, p.y, _yaw(q)])
            frame = parents.get(msg.header.frame_id)
            rows.append(tuple(pose if frame is None else _compose(frame, pose)))
    times = (np.asarray(stamps, dtype=np.int64) - start_ns) / 1e9
    return times, np.asarray(rows, dtype=float).reshape(-1, 3)


def _yaw(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))

"""Episode files: a long step table (one row per agent and step) plus a JSON of what does not
change.

``save_episode`` writes ``trajectory.parquet`` (or ``.csv``) with the columns

- ``step`` (int), ``t`` (s), ``agent`` (``robot`` or ``person``), ``agent_id`` (the person's id;
  0 for the robot), ``x``, ``y`` (m, world frame), ``heading`` (rad, world frame: the robot's yaw,
  the direction a person faces), ``vx``, ``vy`` (m/s, world frame), ``wz`` (rad/s; the robot's
  command, null for people);
- on robot rows only (null on person rows): ``status`` (planner status), ``collision_person``,
  ``collision_obstacle``;

sorted by step, then robot first, then person id. A person absent at a step (NaN in the record's
``(T, K, …)`` arrays) has no row there. The robot's velocity is its body-frame command rotated
into the world frame. ``episode.json`` holds the rest; ``load_episode`` rebuilds the
:class:`EpisodeRecord` that metrics and pictures read (NaN where a person was absent).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import InvalidInputError
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.core.success import ConditionSpec
from socialnav.social.structures import make_structure, structure_to_dict

TRAJECTORY_FILE = "trajectory.parquet"
EPISODE_FILE = "episode.json"
ROBOT = "robot"
PERSON = "person"
TRAJECTORY_SCHEMA = pa.schema(
    [
        pa.field("step", pa.int64()),
        pa.field("t", pa.float64(), metadata={"unit": "s"}),
        pa.field("agent", pa.string()),
        pa.field("agent_id", pa.int64()),
        pa.field("x", pa.float64(), metadata={"unit": "m", "frame": "world"}),
        pa.field("y", pa.float64(), metadata={"unit": "m", "frame": "world"}),
        pa.field("heading", pa.float64(), metadata={"unit": "rad", "frame": "world"}),
        pa.field("vx", pa.float64(), metadata={"unit": "m/s", "frame": "world"}),
        pa.field("vy", pa.float64(), metadata={"unit": "m/s", "frame": "world"}),
        pa.field("wz", pa.float64(), metadata={"unit": "rad/s"}),
        pa.field("status", pa.string()),
        pa.field("collision_person", pa.bool_()),
        pa.field("collision_obstacle", pa.bool_()),
    ]
)


def trajectory_table(record: EpisodeRecord) -> pa.Table:
    """The long step table of every agent (see the module docstring for its columns)."""
    steps = record.num_steps
    yaw = record.robot_poses[:, 2]
    body = record.robot_twists
    robot = {
        "step": np.arange(steps),
        "t": record.times,
        "agent": np.full(steps, ROBOT, dtype=object),
        "agent_id": np.zeros(steps, dtype=np.int64),
        "x": record.robot_poses[:, 0],
        "y": record.robot_poses[:, 1],
        "heading": yaw,
        "vx": np.cos(yaw) * body[:, 0] - np.sin(yaw) * body[:, 1],
        "vy": np.sin(yaw) * body[:, 0] + np.cos(yaw) * body[:, 1],
        "wz": body[:, 2],
    }
    pos, vel = record.people_positions, record.people_velocities
    headings = np.asarray(record.people_headings, dtype=float)
    t_idx, k_idx = np.nonzero(np.isfinite(pos).all(axis=2))  # rows only where present
    ids = np.asarray(record.people_ids, dtype=np.int64)
    people = {
        "step": t_idx,
        "t": record.times[t_idx],
        "agent": np.full(len(t_idx), PERSON, dtype=object),
        "agent_id": ids[k_idx],
        "x": pos[t_idx, k_idx, 0],
        "y": pos[t_idx, k_idx, 1],
        "heading": headings[t_idx, k_idx],
        "vx": vel[t_idx, k_idx, 0],
        "vy": vel[t_idx, k_idx, 1],
        "wz": np.full(len(t_idx), np.nan),
    }
    merged = {k: np.concatenate([robot[k], people[k]]) for k in robot}
    order = np.lexsort((merged["agent_id"], merged["agent"] != ROBOT, merged["step"]))
    columns: dict[str, Any] = {k: v[order] for k, v in merged.items()}
    is_robot = columns["agent"] == ROBOT
    step = columns["step"]
    columns["wz"] = pa.array(columns["wz"], mask=~is_robot)
    status = np.array([str(s) for s in np.asarray(record.status)], dtype=object)
    for name, values in (
        ("status", status),
        ("collision_person", np.asarray(record.collision_person, dtype=bool)),
        ("collision_obstacle", np.asarray(record.collision_obstacle, dtype=bool)),
    ):
        columns[name] = pa.array(values[step], mask=~is_robot)
    return pa.table(columns, schema=TRAJECTORY_SCHEMA)


def _context_to_json(context: SocialContext) -> dict[str, Any]:
    return {
        "people": [asdict(p) for p in context.people],
        "groups": [asdict(g) for g in context.groups],
        "queues": [asdict(q) for q in context.queues],
        "artworks": [asdict(a) for a in context.artworks],
        "structures": [structure_to_dict(s) for s in context.structures],
    }


def _context_from_json(data: dict[str, Any]) -> SocialContext:
    def tup(d: dict[str, Any]) -> dict[str, Any]:
        return {k: tuple(v) if isinstance(v, list) else v for k, v in d.items()}

    return SocialContext(
        people=tuple(Person(**tup(p)) for p in data["people"]),
        groups=tuple(Group(**tup(g)) for g in data["groups"]),
        queues=tuple(Queue(**tup(q)) for q in data["queues"]),
        artworks=tuple(Artwork(**tup(a)) for a in data["artworks"]),
        structures=tuple(
            make_structure(s, f"context.structures.{i}")
            for i, s in enumerate(data.get("structures", []))
        ),
    )


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    return value


def save_episode(record: EpisodeRecord, folder: Path, fmt: str = "parquet") -> Path:
    """Write the episode into ``folder``; ``fmt`` is ``parquet`` or ``csv`` for the step table."""
    folder.mkdir(parents=True, exist_ok=True)
    table = trajectory_table(record)
    if fmt == "parquet":
        pq.write_table(table, folder / TRAJECTORY_FILE)
    elif fmt == "csv":
        pacsv.write_csv(table, folder / "trajectory.csv")
    else:
        raise ValueError(f"unknown trajectory format {fmt!r}; use parquet or csv")
    static = {
        "dt": record.dt,
        "robot_footprint": record.robot_footprint,
        "robot_radius": record.robot_radius,
        "people_ids": record.people_ids,
        "people_radii": record.people_radii,
        "start": record.start,
        "goal": record.goal,
        "target": record.target,
        "waypoint": record.waypoint,
        "goal_tolerance": record.goal_tolerance,
        "time_limit": record.time_limit,
        "family": record.family,
        "scenario": record.scenario,
        "walls": record.walls,
        "obstacles": list(record.obstacles),
        "context": _context_to_json(record.context),
        "meta": record.meta,
        "success": [asdict(s) for s in record.success],
        "trajectory_format": fmt,
    }
    (folder / EPISODE_FILE).write_text(json.dumps(_jsonable(static), indent=1))
    return folder


#: the fields of ``episode.json`` that :func:`load_episode` needs (``success`` and
#: ``trajectory_format`` have defaults)
EPISODE_FIELDS = (
    "dt",
    "robot_footprint",
    "robot_radius",
    "people_ids",
    "people_radii",
    "start",
    "goal",
    "target",
    "waypoint",
    "goal_tolerance",
    "time_limit",
    "family",
    "scenario",
    "walls",
    "obstacles",
    "context",
    "meta",
)


def _episode_json(path: Path) -> dict[str, Any]:
    """``episode.json`` as a dict; ``InvalidInputError`` naming ``path`` (and the fields) when it
    is not a JSON object holding every one of :data:`EPISODE_FIELDS`."""
    try:
        static = json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise InvalidInputError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(static, dict):
        raise InvalidInputError(f"{path}: expected a JSON object, got {type(static).__name__}")
    missing = [name for name in EPISODE_FIELDS if name not in static]
    if missing:
        raise InvalidInputError(
            f"{path}: missing field(s) {', '.join(map(repr, missing))}; not an episode that "
            "save_episode wrote"
        )
    return static


def _check_fields(path: Path, static: dict[str, Any]) -> None:
    """The fields a record would take but fail on later (``InvalidInputError`` naming them)."""
    dt = static["dt"]
    if (
        isinstance(dt, bool)
        or not isinstance(dt, int | float)
        or not (math.isfinite(dt) and dt > 0)
    ):
        raise InvalidInputError(
            f"{path}: field 'dt' must be a positive number of seconds, got {dt!r}"
        )
    try:
        footprint = np.asarray(static["robot_footprint"], dtype=float)
    except (TypeError, ValueError):
        footprint = np.zeros((0, 0))
    if footprint.ndim != 2 or footprint.shape[1:] != (2,) or len(footprint) < 3:
        raise InvalidInputError(
            f"{path}: field 'robot_footprint' must be a polygon of at least 3 (x, y) vertices, "
            f"got {static['robot_footprint']!r}"
        )
    if not isinstance(static["meta"], dict):
        raise InvalidInputError(f"{path}: field 'meta' must be an object, got {static['meta']!r}")
    ids, radii = static["people_ids"], static["people_radii"]
    if not isinstance(ids, list) or not all(type(i) is int for i in ids):
        raise InvalidInputError(f"{path}: field 'people_ids' must be a list of integers")
    if not isinstance(radii, list) or len(radii) != len(ids):
        raise InvalidInputError(
            f"{path}: field 'people_radii' must list one radius per id of 'people_ids' ({len(ids)})"
        )


def load_episode(folder: Path | str) -> EpisodeRecord:
    """Rebuild the :class:`EpisodeRecord` written by :func:`save_episode` in ``folder``.

    Raises ``FileNotFoundError`` naming the file when ``episode.json`` or the step table is
    missing, and ``InvalidInputError`` naming the file (and the field) when ``episode.json`` is
    not valid JSON, lacks a field or holds one of the wrong type or shape, or when the step table
    has rows of someone the episode does not list."""
    folder = Path(folder)
    path = folder / EPISODE_FILE
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file (not an episode folder of save_episode)")
    static = _episode_json(path)
    _check_fields(path, static)
    csv = static.get("trajectory_format", "parquet") == "csv"
    table_path = folder / ("trajectory.csv" if csv else TRAJECTORY_FILE)
    if not table_path.is_file():
        raise FileNotFoundError(f"{table_path}: no such file (the episode's step table)")
    try:
        return _record_from(folder, static, table_path)
    except InvalidInputError:
        raise
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(
            f"{folder}: {EPISODE_FILE} and its step table do not make an episode "
            f"({type(exc).__name__}: {exc})"
        ) from None


def _record_from(folder: Path, static: dict[str, Any], table_path: Path) -> EpisodeRecord:
    """:func:`load_episode` once the files are there and ``episode.json`` is checked."""
    if table_path.suffix == ".csv":
        table = pacsv.read_csv(
            table_path, convert_options=pacsv.ConvertOptions(column_types=TRAJECTORY_SCHEMA)
        )
    else:
        table = pq.read_table(table_path)
    missing = set(TRAJECTORY_SCHEMA.names) - set(table.column_names)
    if missing:
        raise InvalidInputError(
            f"{folder}: the step table lacks {sorted(missing)}; it is not a long table as "
            "save_episode writes (one row per agent and step)"
        )
    col = {n: table.column(n).to_numpy(zero_copy_only=False) for n in TRAJECTORY_SCHEMA.names}
    ids = np.asarray(static["people_ids"], dtype=int)
    robot = col["agent"] == ROBOT
    steps = int(robot.sum())
    yaw = col["heading"][robot].astype(float)
    vx, vy = col["vx"][robot].astype(float), col["vy"][robot].astype(float)
    # back to the body frame of the command (the inverse rotation of trajectory_table)
    twists = np.stack(
        [
            np.cos(yaw) * vx + np.sin(yaw) * vy,
            -np.sin(yaw) * vx + np.cos(yaw) * vy,
            col["wz"][robot],
        ],
        axis=1,
    ).astype(float)
    positions = np.full((steps, len(ids), 2), np.nan)
    velocities = np.full((steps, len(ids), 2), np.nan)
    headings = np.full((steps, len(ids)), np.nan)
    person = ~robot
    slot = {int(pid): k for k, pid in enumerate(ids)}
    t_idx = col["step"][person].astype(int)
    unknown = sorted({int(i) for i in col["agent_id"][person]} - set(slot))
    if unknown:
        raise InvalidInputError(
            f"{table_path}: rows of person {', '.join(map(str, unknown))}, whom "
            f"{EPISODE_FILE}'s people_ids do not list"
        )
    k_idx = np.array([slot[int(i)] for i in col["agent_id"][person]], dtype=int)
    positions[t_idx, k_idx] = np.stack([col["x"][person], col["y"][person]], axis=1)
    velocities[t_idx, k_idx] = np.stack([col["vx"][person], col["vy"][person]], axis=1)
    headings[t_idx, k_idx] = col["heading"][person]
    arr = np.asarray
    return EpisodeRecord(
        dt=static["dt"],
        times=arr(col["t"][robot], dtype=float),
        robot_poses=np.stack([col["x"][robot], col["y"][robot], yaw], 1).astype(float),
        robot_twists=twists,
        robot_footprint=arr(static["robot_footprint"], dtype=float),
        robot_radius=static["robot_radius"],
        people_ids=ids,
        people_positions=positions,
        people_velocities=velocities,
        people_headings=headings,
        people_radii=arr(static["people_radii"], dtype=float).reshape(len(ids)),
        start=arr(static["start"], dtype=float),
        goal=arr(static["goal"], dtype=float),
        target=arr(static["target"], dtype=float),
        waypoint=None if static["waypoint"] is None else arr(static["waypoint"], dtype=float),
        goal_tolerance=static["goal_tolerance"],
        time_limit=static["time_limit"],
        family=static["family"],
        scenario=static["scenario"],
        walls=arr(static["walls"], dtype=float).reshape(-1, 2, 2),
        obstacles=tuple(arr(o, dtype=float) for o in static["obstacles"]),
        context=_context_from_json(static["context"]),
        collision_person=arr(col["collision_person"][robot], dtype=bool),
        collision_obstacle=arr(col["collision_obstacle"][robot], dtype=bool),
        status=arr(col["status"][robot], dtype=object),
        meta=static["meta"],
        success=tuple(ConditionSpec(**s) for s in static.get("success", [])),
    )

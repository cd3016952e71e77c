"""Episode files: one row per step (Parquet or CSV) plus a JSON of what does not change.

``save_episode`` writes ``trajectory.parquet`` (columns ``t, robot_x, robot_y, robot_yaw, robot_vx,
robot_vy, robot_wz, status, collision_person, collision_obstacle, person_<id>_x, …``) and
``episode.json``; ``load_episode`` rebuilds the :class:`EpisodeRecord` that metrics and
pictures read.
"""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from socialnav.core.episode import EpisodeRecord
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.core.success import ConditionSpec
from socialnav.social.structures import make_structure, structure_to_dict

TRAJECTORY_FILE = "trajectory.parquet"
EPISODE_FILE = "episode.json"


def trajectory_table(record: EpisodeRecord) -> pa.Table:
    """The per-step table of every agent: one row per step, wide columns per person."""
    columns: dict[str, Any] = {
        "t": record.times,
        "robot_x": record.robot_poses[:, 0],
        "robot_y": record.robot_poses[:, 1],
        "robot_yaw": record.robot_poses[:, 2],
        "robot_vx": record.robot_twists[:, 0],
        "robot_vy": record.robot_twists[:, 1],
        "robot_wz": record.robot_twists[:, 2],
        "status": [str(s) for s in np.asarray(record.status)],
        "collision_person": record.collision_person,
        "collision_obstacle": record.collision_obstacle,
    }
    for k, pid in enumerate(record.people_ids):
        columns[f"person_{pid}_x"] = record.people_positions[:, k, 0]
        columns[f"person_{pid}_y"] = record.people_positions[:, k, 1]
        columns[f"person_{pid}_vx"] = record.people_velocities[:, k, 0]
        columns[f"person_{pid}_vy"] = record.people_velocities[:, k, 1]
    return pa.table(columns)


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


def load_episode(folder: Path) -> EpisodeRecord:
    """Rebuild the :class:`EpisodeRecord` written by :func:`save_episode`."""
    static = json.loads((folder / EPISODE_FILE).read_text())
    if static.get("trajectory_format", "parquet") == "csv":
        table = pacsv.read_csv(folder / "trajectory.csv")
    else:
        table = pq.read_table(folder / TRAJECTORY_FILE)
    col = {name: table.column(name).to_numpy(zero_copy_only=False) for name in table.column_names}
    ids = np.asarray(static["people_ids"], dtype=int)
    steps = len(col["t"])
    positions = np.zeros((steps, len(ids), 2))
    velocities = np.zeros((steps, len(ids), 2))
    for k, pid in enumerate(ids):
        positions[:, k] = np.stack([col[f"person_{pid}_x"], col[f"person_{pid}_y"]], axis=1)
        velocities[:, k] = np.stack([col[f"person_{pid}_vx"], col[f"person_{pid}_vy"]], axis=1)
    arr = np.asarray
    return EpisodeRecord(
        dt=static["dt"],
        times=arr(col["t"], dtype=float),
        # dtype=float: CSV reads an all-integer column (a robot that never moved) as int64
        robot_poses=np.stack([col["robot_x"], col["robot_y"], col["robot_yaw"]], 1, dtype=float),
        robot_twists=np.stack([col["robot_vx"], col["robot_vy"], col["robot_wz"]], 1, dtype=float),
        robot_footprint=arr(static["robot_footprint"], dtype=float),
        robot_radius=static["robot_radius"],
        people_ids=ids,
        people_positions=positions,
        people_velocities=velocities,
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
        collision_person=arr(col["collision_person"], dtype=bool),
        collision_obstacle=arr(col["collision_obstacle"], dtype=bool),
        status=arr(col["status"], dtype=object),
        meta=static["meta"],
        success=tuple(ConditionSpec(**s) for s in static.get("success", [])),
    )

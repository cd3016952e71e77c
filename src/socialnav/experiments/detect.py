"""``socialnav detect FILE``: the social-context estimator over a recording or a scenario.

FILE is an episode folder written by ``socialnav run`` / ``compare`` (``episode.json`` and the
step table), a crowd recording (ETH/UCY obsmat, four-column ``frame id x y`` or Trajnet++
``.ndjson``, read by :func:`socialnav.crowds.load_recording` and taken at its own frames), or a
scenario (a built-in name or a YAML file; it is simulated with the ``traditional`` planner,
people as the scenario scripts them). Every sample's people pass
through the perception model (``noise``: ``default`` = DEFAULT_PERCEPTION, ``none`` = exact
tracks), then the estimator, with the map knowledge of the record (artworks, queue service
points). Writes ``structures.parquet`` (one row per frame and structure: ``t`` (s), ``kind``,
``track_id``, ``members`` (list of ids), ``confidence``, ``center_x``/``center_y`` (m, o-space
centre or queue service point, else null)) and ``context.png`` (:func:`plot_context`).
Headings of people are not in the record: a moving person faces their velocity, a standing one
keeps their last heading (initially the scenario's).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import ConfigurationError
from socialnav.core.scene import Artwork
from socialnav.crowds import Recording
from socialnav.social.perception import ContextEstimator, Estimate, EstimatorParams, MapKnowledge
from socialnav.social.perception.base import STANDING_SPEED

STRUCTURES_FILE = "structures.parquet"


def _check_noise(noise: str) -> None:
    if noise not in ("default", "none"):
        raise ConfigurationError(f"unknown noise {noise!r}; use default or none")


def _record_of(source: str) -> EpisodeRecord:
    path = Path(source)
    if path.is_dir():
        from socialnav.experiments.storage import EPISODE_FILE, load_episode

        if not (path / EPISODE_FILE).exists():
            raise ConfigurationError(f"{path}: not an episode folder (no {EPISODE_FILE})")
        return load_episode(path)
    from socialnav.experiments.planners import run_planner_episode
    from socialnav.experiments.suite import EpisodeSpec
    from socialnav.sim.scenario import load_scenario

    load_scenario(source)  # names the file and field on bad input
    return run_planner_episode(EpisodeSpec(source, "traditional", "pr2")).record


#: a file with one of these suffixes is a scenario; any other file is read as a recording,
#: its format told by its content (``socialnav.crowds.load_recording``), as the crowd suite does
SCENARIO_SUFFIXES = (".yaml", ".yml")


def _recording_of(source: str) -> Recording | None:
    """The crowd recording at ``source``, or ``None`` when it is no recording (a folder, a
    scenario name or YAML). Any other file is read as a recording, whatever its suffix; a
    malformed one raises naming the file and line."""
    from socialnav.crowds import RecordingFormatError, load_recording

    path = Path(source)
    if not path.is_file() or path.suffix.lower() in SCENARIO_SUFFIXES:
        return None
    try:
        return load_recording(path)
    except (RecordingFormatError, ValueError) as exc:
        raise ConfigurationError(str(exc)) from None


def detect_recording(
    recording: Recording,
    noise: str = "default",
    seed: int = 0,
    params: EstimatorParams | None = None,
) -> tuple[list[Estimate], pa.Table]:
    """Estimates at every frame of ``recording`` (its own frame period) and the structures
    table (module docstring); no map knowledge (an open space has no desk or artwork).
    ``params``: the estimator's (default :class:`EstimatorParams`; its ``group_mode`` is set
    here)."""
    from socialnav.core.scene import HUMAN_RADIUS

    period = recording.frame_period * _frame_step(recording)
    n = int(np.floor((recording.end_time - recording.start_time) / period + 1e-9)) + 1
    times = np.asarray(recording.start_time + period * np.arange(n), dtype=np.float64)
    state = recording.states(times)
    p = state.ids.shape[0]
    return _detect_frames(
        MapKnowledge(),
        "join",
        times,
        state.ids,
        state.positions,
        state.velocities,
        state.headings,
        np.zeros(p),
        np.full(p, HUMAN_RADIUS),
        noise,
        seed,
        params,
    )


def _frame_step(recording: Recording) -> int:
    """Frame numbers between annotations (ETH/UCY annotate every 10th video frame)."""
    steps = [np.diff(tr.times) for tr in recording.tracks if len(tr.times) > 1]
    if not steps:
        return 1
    smallest = float(np.min(np.concatenate(steps)))
    return max(1, round(smallest / recording.frame_period))


def detect_record(
    record: EpisodeRecord,
    noise: str = "default",
    seed: int = 0,
    params: EstimatorParams | None = None,
) -> tuple[list[Estimate], pa.Table]:
    """Estimates per sample of ``record`` and the structures table (module docstring);
    ``params`` as :func:`detect_recording`."""
    ctx = record.context
    knowledge = MapKnowledge(
        artworks=tuple(Artwork(a.center, a.width, a.facing) for a in ctx.artworks),
        service_points=np.array([q.service_point for q in ctx.queues], dtype=float),
    )
    mode = "lead" if any(g.mode == "lead" for g in ctx.groups) else "join"
    initial = {p.id: p.yaw for p in ctx.people}
    yaw0 = np.array([initial.get(int(i), 0.0) for i in record.people_ids], dtype=float)
    return _detect_frames(
        knowledge,
        mode,
        record.times,
        record.people_ids,
        record.people_positions,
        record.people_velocities,
        None,
        yaw0,
        record.people_radii,
        noise,
        seed,
        params,
    )


def _detect_frames(
    knowledge: MapKnowledge,
    mode: str,
    times: np.ndarray,
    ids: np.ndarray,
    positions: np.ndarray,
    velocities: np.ndarray,
    headings: np.ndarray | None,
    yaw0: np.ndarray,
    radii: np.ndarray,
    noise: str,
    seed: int,
    params: EstimatorParams | None = None,
) -> tuple[list[Estimate], pa.Table]:
    """The estimator over frames ``times (T,)`` of people ``ids (P,)``: ``positions`` and
    ``velocities (T, P, 2)`` (NaN where absent), ``headings (T, P)`` or ``None`` (a moving
    person faces their velocity, a standing one keeps the last heading, from ``yaw0 (P,)``)."""
    from socialnav.sim.perception import DEFAULT_PERCEPTION, EXACT_PERCEPTION, PerceptionModel

    _check_noise(noise)
    estimator = ContextEstimator(
        knowledge, dataclasses.replace(params or EstimatorParams(), group_mode=mode)
    )
    pts = positions.reshape(-1, 2)
    pts = pts[np.all(np.isfinite(pts), axis=1)]  # absent people are NaN
    bounds = (
        (
            float(pts[:, 0].min()),
            float(pts[:, 1].min()),
            float(pts[:, 0].max()),
            float(pts[:, 1].max()),
        )
        if pts.size
        else (0.0, 0.0, 1.0, 1.0)
    )
    model = PerceptionModel(
        DEFAULT_PERCEPTION if noise == "default" else EXACT_PERCEPTION, bounds, seed
    )
    yaw = np.asarray(yaw0, dtype=float)
    estimates: list[Estimate] = []
    rows: dict[str, list[Any]] = {
        k: [] for k in ("t", "kind", "track_id", "members", "confidence", "center_x", "center_y")
    }
    for k, t in enumerate(times):
        pos, vel = positions[k], velocities[k]
        present = np.all(np.isfinite(pos), axis=1)
        if headings is not None:
            yaw = np.where(np.isfinite(headings[k]), headings[k], yaw)
        else:
            with np.errstate(invalid="ignore"):
                moving = np.hypot(vel[:, 0], vel[:, 1]) >= STANDING_SPEED
            yaw = np.where(moving, np.arctan2(vel[:, 1], vel[:, 0]), yaw)
        tracks = model.observe(
            ids[present],
            pos[present],
            vel[present],
            yaw[present],
            radii[present],
        )
        est = estimator.update(float(t), tracks)
        estimates.append(est)
        queues = {q.member_ids: q.service_point for q in est.context.queues}
        for s in est.structures:
            center: Any = s.geometry.get("ospace_center")
            if s.kind == "queue":
                center = queues.get(s.members)
            rows["t"].append(float(t))
            rows["kind"].append(s.kind)
            rows["track_id"].append(int(s.track_id))
            rows["members"].append([int(m) for m in s.members])
            rows["confidence"].append(float(s.confidence))
            rows["center_x"].append(None if center is None else float(center[0]))
            rows["center_y"].append(None if center is None else float(center[1]))
    schema = pa.schema(
        [
            pa.field(name, kind, metadata={"description": text})
            for name, kind, text in STRUCTURE_COLUMNS
        ],
        metadata={"description": "one row per structure found per estimated frame"},
    )
    return estimates, pa.table(rows, schema=schema)


#: The columns of ``structures.parquet`` (name, Arrow type, description with unit and frame),
#: also stored as each field's ``description`` metadata.
STRUCTURE_COLUMNS = (
    ("t", pa.float64(), "s, time of the frame since the start of the recording or episode"),
    ("kind", pa.string(), "fformation, walking_group, queue or viewers"),
    ("track_id", pa.int64(), "the structure's id, kept while it persists over frames"),
    ("members", pa.list_(pa.int64()), "ids of the people in it (queues: head first)"),
    ("confidence", pa.float64(), "0..1, the estimator's confidence"),
    ("center_x", pa.float64(), "m, map frame: o-space centre or queue service point; null else"),
    ("center_y", pa.float64(), "m, map frame: as center_x"),
)


def detect_file(
    source: str,
    out: Path,
    noise: str = "default",
    seed: int = 0,
    params: EstimatorParams | None = None,
) -> dict[str, Any]:
    """Run :func:`detect_record` (or :func:`detect_recording`) on ``source`` with the
    estimator's ``params`` and write the table and picture into ``out``."""
    from socialnav.viz.context import plot_context
    from socialnav.viz.topdown import save_figure

    _check_noise(noise)  # before a scenario's episode is simulated, not after
    recording = _recording_of(source)
    if recording is not None:
        estimates, table = detect_recording(recording, noise, seed, params)
        from socialnav.crowds.space import area_walls

        walls, title = area_walls(recording.area), recording.name
        robot = None
    else:
        record = _record_of(source)
        estimates, table = detect_record(record, noise, seed, params)
        walls, title, robot = record.walls, record.scenario, record.robot_poses
    out.mkdir(parents=True, exist_ok=True)
    pq.write_table(table, out / STRUCTURES_FILE)
    save_figure(
        plot_context(estimates, walls=walls, title=title, robot_poses=robot), out / "context.png"
    )
    kinds = table.column("kind").to_pylist()
    return {
        "source": source,
        "frames": len(estimates),
        "structure_rows": table.num_rows,  # one per structure per frame
        "structures": {
            k: len(
                {
                    (tid)
                    for tid, kk in zip(table.column("track_id").to_pylist(), kinds, strict=True)
                    if kk == k
                }
            )
            for k in sorted(set(kinds))
        },
        "out": str(out),
    }

"""The crowd suite: planners among replayed recorded pedestrians (``--suite crowds``).

Every run is one :class:`CrowdSpec` — recording file × planner × robot × seed; the seed selects
the episode (``socialnav.crowds.episodes``). The ``straight_line`` reference runs beside the
planners in every suite, so each episode shows how crowded it is. The row's metrics follow
SocNavBench / Francis et al. (``socialnav.metrics.crowd``).
"""

from __future__ import annotations

import hashlib
import math
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from socialnav.core.errors import ConfigurationError

#: the reference controller of every crowd run (no planner: the straight line at full speed)
REFERENCE = "straight_line"
#: the reporting seeds (tune on seeds below 10,000)
REPORT_SEEDS = "10000:10050"
#: metrics of a crowd row (column ``metric_column(name)``: ``time_within_1_2``)
CROWD_METRICS = (
    "success",
    "collisions_active",
    "collisions_passive",
    "min_distance_footprint",
    "time_within_0.45",
    "time_within_1.2",
    "path_length_ratio",
    "time_to_goal",
    "mean_jerk",
)


@dataclass(frozen=True)
class CrowdSpec:
    """One crowd run. ``data``: a recording file (any format of ``socialnav.crowds``);
    ``switch_distance`` (m): replayed people within it of the robot switch to navground HL
    (``None``: they never react); ``context``: what the planner sees, ``given`` (the people,
    exactly) or ``detected`` (noisy tracks and the context estimator's structures;
    ``socialnav.sim.replay.run_crowd_episode``)."""

    data: str
    planner: str
    robot: str
    seed: int
    switch_distance: float | None = None
    context: str = "given"

    @property
    def scenario(self) -> str:
        """The recording's name (:func:`recording_name`)."""
        return recording_name(self.data)

    @property
    def run_id(self) -> str:
        react = "" if self.switch_distance is None else f"_hl{self.switch_distance:g}"
        # the given context keeps the ids runs had before contexts, so their results resume
        seen = "" if self.context == "given" else f"__{self.context}"
        return f"{self.scenario}__{self.planner}__{self.robot}__crowd{react}{seen}__s{self.seed}"


def parse_seeds(text: str) -> range:
    """``A:B`` → ``range(A, B)``; a bare ``N`` → ``range(0, N)``. Raises ConfigurationError."""
    try:
        if ":" in text:
            a, b = (int(v) for v in text.split(":", 1))
        else:
            a, b = 0, int(text)
    except ValueError as exc:
        raise ConfigurationError(f"--seeds must be N or A:B, got {text!r}") from exc
    from socialnav.sim.engine import MAX_SEED

    if b <= a or a < 0:
        raise ConfigurationError(f"--seeds {text!r}: need 0 <= A < B")
    if b - 1 > MAX_SEED:
        raise ConfigurationError(f"--seeds {text!r}: seeds go up to {MAX_SEED}")
    return range(a, b)


def crowd_specs(
    data: list[str],
    planners: list[str],
    robots: list[str],
    seeds: range,
    switch_distance: float | None = None,
    contexts: Sequence[str] = ("given",),
) -> list[CrowdSpec]:
    """Every planner (the first one, then the straight-line reference, then the others) × file
    × robot × seed × context, in that order: an interrupted suite has the first planner
    complete. A file
    given twice runs once. Raises ConfigurationError when two different files share a
    recording name (:attr:`CrowdSpec.scenario`): runs, results and report sections are keyed
    on it."""
    check_switch_distance(switch_distance)
    files = unique_recordings(data)
    names = list(dict.fromkeys([*planners[:1], REFERENCE, *planners[1:]]))
    return [
        CrowdSpec(d, p, r, s, switch_distance, c)
        for p in names
        for d in files
        for r in robots
        for s in seeds
        for c in contexts
    ]


def recording_name(path: str | Path) -> str:
    """The name a recording's runs, rows and report section go by: the file's stem without
    ``_obsmat`` (``eth_hotel_obsmat.txt`` → ``eth_hotel``)."""
    return Path(path).stem.removesuffix("_obsmat")


def unique_recordings(data: list[str]) -> list[str]:
    """``data`` without repeats of one recording (the same resolved path, or the same bytes
    under the same name). Raises ConfigurationError when two different files have one
    :func:`recording_name`, letter case aside (a case-insensitive file system would put their
    runs in one folder)."""
    seen: dict[str, tuple[str, Path]] = {}  # by case-folded name: run folders may share it
    out: list[str] = []
    for d in data:
        name, where = recording_name(d), Path(d).resolve()
        key = name.casefold()
        if key in seen:
            first, place = seen[key]
            same = place == where or (
                first == name
                and where.is_file()
                and place.is_file()
                and recording_fingerprint(str(place)) == recording_fingerprint(str(where))
            )
            if not same:
                raise ConfigurationError(
                    f"{d}: another recording given, {place}, has the same name {first!r} (case "
                    "aside); runs and report sections are named after the file, so rename one"
                )
            continue
        seen[key] = (name, where)
        out.append(str(d))
    return out


@lru_cache(maxsize=32)
def recording_fingerprint(path: str) -> str:
    """The first 16 hex digits of the SHA-256 of the file's bytes: which recording a stored
    row was run on, whatever path it was given by."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()[:16]


def check_stored_recordings(stored: list[dict[str, Any]], data: list[str]) -> None:
    """Refuse to add runs of a recording to a results folder that holds runs of a *different*
    recording of the same name (``stored``: the folder's crowd rows; ``data``: the files about
    to run): their run ids would coincide, so resuming would skip the new file and the report
    would pool the two. Rows stored before fingerprints were kept (no ``data_sha256``) are
    compared by resolved path. Raises ConfigurationError naming both files."""
    mine = {recording_name(d): (d, recording_fingerprint(str(d))) for d in data}
    for row in stored:
        name = recording_name(str(row.get("data", "")))
        if name not in mine:
            continue
        given, fingerprint = mine[name]
        theirs = row.get("data_sha256")
        same = (
            theirs == fingerprint
            if isinstance(theirs, str) and theirs
            else Path(str(row["data"])).resolve() == Path(given).resolve()
        )
        if not same:
            raise ConfigurationError(
                f"{given}: the results folder already holds runs of another recording named "
                f"{name!r} ({row['data']}); use another --out, or rename the file"
            )


@lru_cache(maxsize=8)
def cached_recording(path: str) -> Any:
    """A recording loaded once per process (workers run many episodes of one file); its
    loader's warnings were said once when the call checked the file (:func:`load_noting`)."""
    return load_noting(path)[0]


def load_noting(path: str | Path) -> tuple[Any, list[str]]:
    """``(load_recording(path), the texts of its warnings)``: what the loader warns about (a
    group list only partly matching the recording) goes where the caller's other warnings go,
    once, instead of Python's stderr line from inside the library."""
    import warnings as py_warnings

    from socialnav.crowds import load_recording

    with py_warnings.catch_warnings(record=True) as caught:
        py_warnings.simplefilter("always")
        recording = load_recording(path)
    return recording, [str(w.message) for w in caught]


def crowd_controller(planner: str, record: bool = False) -> Any:
    """The controller of a crowd run: the planner's (``experiments.planners``), or the
    ``straight_line`` reference controller. Raises ConfigurationError for an unknown name."""
    from socialnav.sim.controller import make_controller

    return make_controller(planner, record=record)


def run_crowd_planner(spec: CrowdSpec, record_diagnostics: bool = False) -> Any:
    """Run one crowd episode with its planner; the episode generator's task is in the meta."""
    from socialnav.crowds.episodes import generate_episode
    from socialnav.sim.replay import CrowdTask, run_crowd_episode

    recording = cached_recording(spec.data)
    episode = generate_episode(recording, spec.seed)
    task = CrowdTask(episode.t0, episode.start, episode.goal, episode.time_limit)
    controller = crowd_controller(spec.planner, record_diagnostics)
    result = run_crowd_episode(
        recording,
        task,
        controller,
        spec.robot,
        seed=spec.seed,
        record_diagnostics=record_diagnostics,
        switch_distance=spec.switch_distance,
        context=spec.context,
    )
    meta = result.record.meta
    meta.update({"planner": spec.planner, "flow": episode.flow, "people_near": episode.people_near})
    meta.update(planner_timing(spec.planner, result.step_seconds))
    return result


def planner_timing(planner: str, step_seconds: list[float]) -> dict[str, Any]:
    """The planner's step time (ms): ``planner_ms_median``, ``planner_ms_p95`` and every step's
    ``planner_ms_steps``; empty for a controller that is not a planner stack (its step time
    would be navground's, not a planner's) or an episode without steps."""
    from socialnav.sim.controller import CONTROLLERS

    if CONTROLLERS.get(planner).kind != "stack" or not step_seconds:
        return {}
    ms = np.asarray(step_seconds) * 1e3
    return {
        "planner_ms_median": float(np.median(ms)),
        "planner_ms_p95": float(np.percentile(ms, 95)),
        "planner_ms_steps": [round(float(v), 3) for v in ms],
    }


def check_crowd_task(
    recording: Any,
    t0: float,
    start: tuple[float, float],
    goal: tuple[float, float],
    switch_distance: float | None = None,
    margin: float = 0.0,
) -> None:
    """Raise a :class:`ConfigurationError` naming the file for a task the recording cannot
    hold: an area of zero width or height (every position on one line), ``t0`` (s) outside
    the recording's time span (its first to its last sample), ``start``/``goal`` (m) outside its
    annotated area (:attr:`Recording.area`, the border of the crowd's open space) shrunk by
    ``margin`` (m: the robot's circumscribed radius, so its footprint starts and ends clear of
    the border at any heading), a ``goal`` within the goal tolerance of ``start`` (nothing to
    drive), or a negative ``switch_distance`` (m)."""
    where = str(recording.source) if recording.source is not None else recording.name
    area = recording.area
    width, height = area.size
    if not (width > 0 and height > 0):
        flat = "width (every x" if not width > 0 else "height (every y"
        value = area.xmin if not width > 0 else area.ymin
        raise ConfigurationError(
            f"{where}: the recorded area has zero {flat} is {value:g}); a robot task needs "
            "people recorded over an area"
        )
    if not (math.isfinite(t0) and recording.start_time <= t0 <= recording.end_time):
        raise ConfigurationError(
            f"--t0 {t0:g}: outside the recording's time span {recording.start_time:g} to "
            f"{recording.end_time:g} s ({where})"
        )
    for flag, xy in (("--start", start), ("--goal", goal)):
        if not bool(area.contains(np.asarray(xy, dtype=float), margin)):
            inside = (
                "outside"
                if not bool(area.contains(np.asarray(xy, dtype=float)))
                else f"not {margin:.2f} m (the robot's radius) inside"
            )
            raise ConfigurationError(
                f"{flag} {xy[0]:g} {xy[1]:g}: {inside} the annotated area of {where}: "
                f"x {area.xmin:.2f} to {area.xmax:.2f} m, y {area.ymin:.2f} to {area.ymax:.2f} m"
            )
    from socialnav.sim.replay import CrowdTask

    if math.dist(start, goal) <= CrowdTask.goal_tolerance:
        raise ConfigurationError(
            f"--start and --goal are {math.dist(start, goal):.2f} m apart: the robot would "
            f"arrive at once (the goal tolerance is {CrowdTask.goal_tolerance:g} m)"
        )
    check_switch_distance(switch_distance)


def check_switch_distance(switch_distance: float | None) -> None:
    """Raise ConfigurationError unless ``switch_distance`` is None or a finite distance >= 0
    m (a NaN would read as "never react" in stored rows, an infinite one switches everyone)."""
    if switch_distance is not None and not (
        math.isfinite(switch_distance) and switch_distance >= 0
    ):
        raise ConfigurationError(
            f"--switch-distance must be a finite distance >= 0 m, got {switch_distance:g}"
        )


def run_crowd_spec(
    spec: CrowdSpec, out_dir: Path | None = None, figure: bool = False
) -> dict[str, Any]:
    """One crowd run's result row (metrics, success conditions, timing, error)."""
    from socialnav.sim.replay import humans_label

    row: dict[str, Any] = {
        **asdict(spec),
        "scenario": spec.scenario,
        "humans": humans_label(spec.switch_distance),
        "run_id": spec.run_id,
        "error": None,
    }
    started = time.perf_counter()
    try:
        row["data_sha256"] = recording_fingerprint(spec.data)
        from socialnav.experiments.results import condition_column, metric_column
        from socialnav.metrics import compute_metrics, evaluate_success

        result = run_crowd_planner(spec)
        record = result.record
        metrics = compute_metrics(record, CROWD_METRICS)
        row.update({metric_column(k): float(v) for k, v in metrics.items()})
        # overall success is the metric ``success``: stored once
        conditions = {k: v for k, v in evaluate_success(record).items() if k != "success"}
        row.update({condition_column(k): bool(v) for k, v in conditions.items()})
        row.update(
            family=record.family,
            steps=record.num_steps,
            t0=record.meta["t0"],
            flow=record.meta["flow"],
            people_near=record.meta["people_near"],
            people_total=int(record.people_ids.shape[0]),
            planner_ms_median=float(record.meta.get("planner_ms_median", np.nan)),
            planner_ms_p95=float(record.meta.get("planner_ms_p95", np.nan)),
            estimator_ms_median=float(record.meta.get("estimator_ms_median", np.nan)),
            # every step's time, so the report pools percentiles over steps, not episodes
            planner_ms_steps=record.meta.get("planner_ms_steps", []),
        )
        if out_dir is not None:
            from socialnav.experiments.storage import save_episode

            save_episode(record, out_dir / "runs" / spec.run_id)
    except Exception as exc:  # an episode failure is data, not the end of the suite
        row["error"] = f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=4)}"
    row["wall_time_s"] = time.perf_counter() - started
    return row


def crowd_task_warnings(
    recording: Any, t0: float, start: tuple[float, float], time_limit: float
) -> list[str]:
    """What makes a hand-given task (``socialnav run --crowd``) unlike the suite's episodes
    (:mod:`socialnav.crowds.episodes`), one line each: someone within ``CLEARANCE`` (1 m) of
    ``start`` (m) at ``t0`` (s), who may stand on the robot; a recording that ends before
    ``t0 + time_limit``, after which the robot drives among nobody."""
    from socialnav.crowds.episodes import CLEARANCE

    out = []
    state = recording.state_at(float(t0))
    here, ids = state.positions[0][state.present[0]], state.ids[state.present[0]]
    if here.size:
        gaps = np.hypot(*(here - np.asarray(start, dtype=float)).T)
        k = int(np.argmin(gaps))
        if gaps[k] < CLEARANCE:
            out.append(
                f"person {int(ids[k])} is {gaps[k]:.2f} m from --start at --t0 {t0:g} s (the "
                f"suite's episodes keep everyone {CLEARANCE:g} m away at the start)"
            )
    left = recording.end_time - float(t0)
    if left < time_limit:
        out.append(
            f"the recording ends {left:.1f} s after --t0 (the run may last {time_limit:g} s): "
            "nobody is in the scene after that"
        )
    return out


def run_crowd_single(
    data: Path,
    t0: float | None,
    start: tuple[float, float],
    goal: tuple[float, float],
    planner: str,
    robot: str,
    *,
    out: Path = Path("out"),
    switch_distance: float | None = None,
    time_limit: float = 60.0,
    fmt: str = "parquet",
    video: str = "none",
    progress: Callable[[str], None] | None = None,
    warn: Callable[[str], None] | None = None,
    context: str = "given",
    seed: int = 0,
) -> dict[str, Any]:
    """``socialnav run --crowd``: one task in a recording, written to ``out`` with the files of
    a scenario run (:func:`socialnav.experiments.run.write_run`); ``metrics.json`` holds the
    crowd metrics (:data:`CROWD_METRICS`) and ``topdown.png`` draws the crowd's tracks. The robot
    starts facing the goal; ``t0`` and ``time_limit`` are seconds, ``start``/``goal`` and
    ``switch_distance`` metres. ``context``: ``given`` or ``detected`` (the planner sees noisy
    tracks and the context estimator's output, see
    :func:`socialnav.sim.replay.run_crowd_episode`; ``seed`` seeds the perception noise and is
    stored in ``episode.json``). With the context given a crowd run has no seed: the task is
    given, not drawn, and ``episode.json`` stores none.
    ``progress`` receives a line per stage, ``warn`` each of :func:`crowd_task_warnings`
    (also in the summary's ``warnings``). Raises :class:`ConfigurationError` for an unknown
    planner, robot or format, an ``out`` that is a file, ``mp4`` without the ``video`` extra,
    a bad file or a task the recording cannot hold (:func:`check_crowd_task`), all before the
    episode runs."""
    from socialnav.core.robot import ROBOT_MODELS
    from socialnav.experiments.run import check_outputs, check_robot, write_run
    from socialnav.metrics import compute_metrics, evaluate_success
    from socialnav.sim.replay import CrowdTask, run_crowd_episode
    from socialnav.sim.runner import check_context
    from socialnav.viz.crowd import plot_crowd_episodes

    check_context(context)
    # the evaluation records feed diagnostics.parquet and decision.png, as in a scenario run
    controller = crowd_controller(planner, record=True)
    check_robot(robot)
    check_outputs(fmt, video, out)
    recording, warnings = load_noting(data)
    if t0 is None:
        t0 = recording.start_time  # the first annotated instant (ETH hotel: 0.04 s, not 0)
    radius = ROBOT_MODELS[robot].circumscribed_radius
    check_crowd_task(recording, t0, start, goal, switch_distance, margin=radius)
    warnings += crowd_task_warnings(recording, t0, start, time_limit)
    for line in warnings:
        (warn or (lambda line: None))(line)
    say = progress or (lambda line: None)
    seen = "" if context == "given" else f", context {context} (seed {seed})"
    say(f"running {recording.name} from t0 = {t0:g} s with {planner} on {robot}{seen} …")
    yaw = math.atan2(goal[1] - start[1], goal[0] - start[0])
    task = CrowdTask(float(t0), (*start, yaw), (*goal, yaw), time_limit)
    result = run_crowd_episode(
        recording,
        task,
        controller,
        robot,
        seed=seed,
        record_diagnostics=True,
        switch_distance=switch_distance,
        context=context,
    )
    record = result.record
    record.meta["planner"] = planner
    if context == "given":
        record.meta.pop("seed", None)  # the task is given, not drawn: no seed to report
    timing = planner_timing(planner, result.step_seconds)
    success = evaluate_success(record)
    metrics = compute_metrics(record, CROWD_METRICS)
    for key in ("planner_ms_median", "planner_ms_p95"):  # the suite's columns, NaN off-stack
        metrics[key] = float(timing.get(key, np.nan))
    write_run(
        result,
        out,
        metrics,
        success,
        lambda: plot_crowd_episodes([record], title=record.scenario),
        fmt=fmt,
        video=video,
        say=say,
    )
    return {
        "recording": str(data),
        "t0": t0,
        "planner": planner,
        "robot": robot,
        "switch_distance": switch_distance,
        "context": context,
        **({"seed": seed} if context == "detected" else {}),
        "steps": record.num_steps,
        "people": int(record.people_ids.shape[0]),
        "success": success["success"],
        "wall_time_s": round(result.wall_time, 2),
        "warnings": warnings,
        "out": str(out),
    }

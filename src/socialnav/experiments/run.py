"""``socialnav run``: one scenario with one planner, every output file written to one folder."""

from __future__ import annotations

import difflib
import importlib.util
import json
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import ROBOT_MODELS
from socialnav.core.success import not_required_text
from socialnav.experiments.planners import CONTROLLERS, run_planner_episode
from socialnav.experiments.storage import EPISODE_FILE, TRAJECTORY_FILE, save_episode
from socialnav.experiments.suite import EpisodeSpec
from socialnav.planner.record import EvaluationRecord
from socialnav.sim.runner import EpisodeResult
from socialnav.viz.animation import FanFrame


def check_robot(robot: str) -> None:
    """Raise a :class:`ConfigurationError` with a "did you mean" for an unknown robot model."""
    if robot not in ROBOT_MODELS:
        close = difflib.get_close_matches(robot, ROBOT_MODELS, n=1)
        hint = f" Did you mean {close[0]!r}?" if close else ""
        known = ", ".join(ROBOT_MODELS)
        raise ConfigurationError(f"unknown robot {robot!r}.{hint} Known: {known}.")


def diagnostics_table(diagnostics: Sequence[EvaluationRecord | None]) -> dict[str, list[Any]]:
    """Per-step planner diagnostics as columns: status, chosen twist, candidates, rejections.

    One row per sample with an evaluation record (``None`` entries are skipped)."""
    columns: dict[str, list[Any]] = {
        "step": [],
        "status": [],
        "n_candidates": [],
        "n_legal": [],
        "chosen_index": [],
        "chosen_vx": [],
        "chosen_vy": [],
        "chosen_wz": [],
        "rejections": [],
        "objectives": [],
        "plan_ms": [],
    }
    for step, record in enumerate(diagnostics):
        if record is None:
            continue
        chosen = record.chosen
        columns["step"].append(step)
        columns["status"].append(record.status)
        columns["n_candidates"].append(record.num_samples)
        columns["n_legal"].append(record.num_legal)
        columns["chosen_index"].append(-1 if chosen is None else int(chosen))
        cmd = record.twists[chosen] if chosen is not None else np.full(3, np.nan)
        columns["chosen_vx"].append(float(cmd[0]))
        columns["chosen_vy"].append(float(cmd[1]))
        columns["chosen_wz"].append(float(cmd[2]))
        rejected = {f"{c}:{r}": int(k) for (c, r), k in record.rejected.items()}
        columns["rejections"].append(json.dumps(rejected))
        columns["objectives"].append(",".join(record.objective_names))
        timing = record.timing
        columns["plan_ms"].append(float(timing.get("total", np.nan)) * 1e3)
    return columns


def run_single(
    scenario: str,
    planner: str,
    robot: str,
    *,
    seed: int = 0,
    humans: str = "scripted",
    out: Path = Path("out"),
    fmt: str = "parquet",
    video: str = "none",
    context: str = "given",
    progress: Callable[[str], None] | None = None,
    warn: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Run, measure and draw one episode into ``out``; returns a summary dict. ``context``:
    ``given`` or ``detected`` (see :func:`socialnav.sim.runner.run_episode`).

    ``progress`` receives one line as each stage starts and ends (the episode, the files, the
    figures, the video), so a person sees what the command is doing; ``warn`` each of the
    scenario's :meth:`~socialnav.sim.scenario.Scenario.group_warnings` (a group the planner
    plans around as people).
    """
    from socialnav.experiments.suite import GENERATED_PREFIX
    from socialnav.metrics import measure_episode
    from socialnav.sim.generate import GENERATORS
    from socialnav.sim.runner import check_context
    from socialnav.sim.scenario import load_scenario
    from socialnav.viz.topdown import plot_episode

    CONTROLLERS.get(planner)
    check_robot(robot)
    check_outputs(fmt, video, out)  # before the episode runs, not after
    if humans not in ("scripted", "reactive"):
        raise ConfigurationError(f"unknown human model {humans!r}; use scripted or reactive")
    check_context(context)
    spec = EpisodeSpec(
        scenario=scenario, planner=planner, robot=robot, seed=seed, humans=humans, context=context
    )
    # an unknown name or a bad file fails before "running …" is said
    if scenario.startswith(GENERATED_PREFIX):
        GENERATORS.get(scenario.removeprefix(GENERATED_PREFIX))
    else:
        for line in load_scenario(scenario).group_warnings():
            (warn or (lambda line: None))(line)
    say = progress or (lambda line: None)
    say(f"running {spec.scenario} with {planner} on {robot} (seed {seed}) …")
    result = run_planner_episode(spec, record_diagnostics=True)
    record = result.record
    measured = measure_episode(record)
    success = measured.passed()
    write_run(
        result,
        out,
        measured.metrics,
        success,
        lambda: plot_episode(record, label=planner),
        fmt=fmt,
        video=video,
        say=say,
    )
    return {
        "scenario": record.scenario,
        "planner": planner,
        "robot": robot,
        "seed": seed,
        "steps": record.num_steps,
        "success": success.get("success"),
        "wall_time_s": round(result.wall_time, 2),
        "out": str(out),
    }


#: every file :func:`write_run` may write; a new run into the folder removes these, no others
RUN_FILES = (
    TRAJECTORY_FILE,
    "trajectory.csv",
    EPISODE_FILE,
    "metrics.json",
    "topdown.png",
    "diagnostics.parquet",
    "decision.png",
    "episode.gif",
    "episode.mp4",
)


def check_outputs(fmt: str, video: str, out: Path | None = None) -> None:
    """Raise a :class:`ConfigurationError` for an unknown step-table or video format, for
    ``mp4`` without the optional ``video`` extra (imageio-ffmpeg), or for an output folder
    ``out`` that is (or lies inside) an existing file: checked before an episode runs, so a
    bad option does not cost the episode."""
    if fmt not in ("parquet", "csv"):
        raise ConfigurationError(f"unknown trajectory format {fmt!r}; use parquet or csv")
    if video not in ("none", "gif", "mp4"):
        raise ConfigurationError(f"unknown video format {video!r}; use none, gif or mp4")
    if video == "mp4" and importlib.util.find_spec("imageio_ffmpeg") is None:
        raise ConfigurationError(
            "--video mp4 needs imageio-ffmpeg: pip install 'socialnav[video]', or use --video gif"
        )
    if out is not None:
        # the nearest existing ancestor decides whether the folder can be made
        existing = next((p for p in (out, *out.parents) if p.exists()), None)
        if existing is not None and not existing.is_dir():
            why = "is a file" if existing == out else f"lies inside {existing}, a file"
            raise ConfigurationError(f"--out {out}: {why}, not a folder")


def write_run(
    result: EpisodeResult,
    out: Path,
    metrics: Mapping[str, float],
    success: Mapping[str, bool],
    topdown: Callable[[], Figure | Axes],
    *,
    fmt: str = "parquet",
    video: str = "none",
    say: Callable[[str], None] = lambda line: None,
) -> None:
    """Write every file of ``socialnav run`` (a scenario or a recorded crowd) into ``out``.

    The step table (``fmt``) and ``episode.json``; ``metrics.json`` (``metrics``, NaN as null,
    ``success_conditions``, and ``not_required``: the conditions measured but not counted, as
    ``"name: reason; …"``, the suite row's column); ``topdown.png`` (drawn by ``topdown``);
    where the episode was run with ``record_diagnostics`` and the planner evaluates candidates,
    ``diagnostics.parquet`` and, where a cycle weighed two or more objectives,
    ``decision.png``; ``episode.gif`` or ``.mp4`` unless ``video`` is ``none``. The files of
    :data:`RUN_FILES` already in ``out`` (an earlier run's) are removed first; other files are
    kept. ``say`` receives a progress line per stage.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    from socialnav.metrics.success import success_spec
    from socialnav.viz.topdown import save_figure

    record = result.record
    say(
        f"episode: {record.num_steps} steps, {record.times[-1]:.1f} s simulated in "
        f"{result.wall_time:.1f} s; writing {out}/ …"
    )
    out.mkdir(parents=True, exist_ok=True)
    stale = [out / name for name in RUN_FILES if (out / name).is_file()]
    for path in stale:  # an earlier run's files would mix with this run's
        path.unlink()
    if stale:
        say(f"removed {len(stale)} files of an earlier run from {out}/")
    save_episode(record, out, fmt=fmt)
    columns = diagnostics_table(result.diagnostics)
    if columns["step"]:
        pq.write_table(pa.table(columns), out / "diagnostics.parquet")
    values = {k: (None if np.isnan(v) else float(v)) for k, v in metrics.items()}
    # conditions measured but not counted toward success, with why (a reader of this file
    # would otherwise take a false `facing_centre` for a failure)
    spared = not_required_text(success_spec(record))
    (out / "metrics.json").write_text(
        json.dumps(
            {**values, "success_conditions": dict(success), "not_required": spared}, indent=1
        )
    )
    cycle = decision_cycle(result.diagnostics, record)
    say("drawing topdown.png …" if cycle is None else "drawing topdown.png and decision.png …")
    save_figure(topdown(), out / "topdown.png")
    if cycle is not None:
        save_figure(decision_figure(result.diagnostics, record, cycle), out / "decision.png")
    if video != "none":
        from socialnav.viz.animation import animate_episode

        frames = fan_frames(result.diagnostics)
        kind: Literal["gif", "mp4"] = "gif" if video == "gif" else "mp4"
        say(f"rendering episode.{video} ({record.num_steps} frames) …")
        animate_episode(record, frames or None, out / f"episode.{video}", fmt=kind)
    say("done")


def decision_cycle(
    diagnostics: Sequence[EvaluationRecord | None], record: EpisodeRecord
) -> tuple[int, float] | None:
    """The step of the multi-objective cycle (a choice among two or more objective columns)
    closest to a person, and that distance (m, ``inf`` with nobody present); ``None`` where no
    cycle weighed two objectives (``traditional``, ``proxemic_layer``, nobody in view)."""
    best, best_distance = None, np.inf
    for step, rec in enumerate(diagnostics):
        if rec is None or rec.chosen is None or rec.F.ndim != 2 or rec.F.shape[1] < 2:
            continue
        gaps = record.people_positions[step] - record.robot_poses[step, :2]
        near = np.hypot(gaps[:, 0], gaps[:, 1])  # NaN for people absent at this step
        distance = float(np.nanmin(near)) if np.isfinite(near).any() else np.inf
        if best is None or distance < best_distance:
            best, best_distance = step, distance
    return None if best is None else (best, best_distance)


def decision_figure(
    diagnostics: Sequence[EvaluationRecord | None],
    record: EpisodeRecord,
    cycle: tuple[int, float],
) -> Figure:
    """Why a trajectory won at ``cycle``, the ``(step, distance)`` of :func:`decision_cycle`."""
    from socialnav.viz.pareto import plot_decision

    step, best_distance = cycle
    rec = diagnostics[step]
    assert rec is not None and rec.chosen is not None  # decision_cycle picks such cycles
    details = rec.selection or {}
    where = f"{best_distance:.2f} m from a person" if np.isfinite(best_distance) else "nobody near"
    return plot_decision(
        rec.F,
        rec.legal,
        details.get("nondominated"),
        details.get("transformed"),
        rec.chosen,
        rec.objective_names,
        fitness=rec.fitness,
        title=f"cycle at t = {record.times[step]:.1f} s ({where})",
    )


def fan_frames(diagnostics: Sequence[EvaluationRecord | None]) -> list[FanFrame | None]:
    """Per-sample candidate fans for the animation, from the planner's evaluation records."""
    from socialnav.viz.animation import fan_frame

    return [fan_frame(record) for record in diagnostics]

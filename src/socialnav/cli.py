"""The ``socialnav`` command line: run one scenario, compare planners, validate scenario files."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated, Any, cast

import typer
from typer.core import TyperCommand

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Socially-aware navigation with PaCcET: run scenarios, compare planners, make reports.",
)

ROBOT_HELP = "Robot model: pr2 (holonomic) or pioneer (differential drive)."
# socialnav.sim.engine.MAX_SEED, spelled out for the same reason; a test keeps them equal
MAX_SEED = 2**32 - 1
# Spelled out rather than imported so that ``--help`` does not load the simulator; a test keeps it
# equal to the generator registry.
GENERATED_FAMILIES = (
    "crowdnav, crowdnav_visible, gallery_pass, gallery_present, group_join, group_lead, hallway, "
    "mixed, queue"
)


def _version(value: bool) -> None:
    if value:
        from socialnav import __version__

        typer.echo(f"socialnav {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    version: Annotated[
        bool,
        typer.Option("--version", callback=_version, is_eager=True, help="Print the version."),
    ] = False,
) -> None:
    """Socially-aware navigation with PaCcET: run scenarios, compare planners, make reports."""


def _warn(message: str) -> None:
    typer.secho(f"warning: {message}", fg=typer.colors.YELLOW, err=True)


def _fail(message: str) -> None:
    typer.secho(f"error: {message}", fg=typer.colors.RED, err=True)
    raise typer.Exit(code=2)


def _split(value: str) -> list[str]:
    return [v.strip() for v in value.split(",") if v.strip()]


#: the options of each ``run`` mode (parameter names), refused in the other one
CROWD_ONLY = ("t0", "start", "goal", "switch_distance")
SCENARIO_ONLY = ("humans",)
XY_OPTIONS = ("--start", "--goal")


def _is_number(word: str) -> bool:
    try:
        return math.isfinite(float(word))
    except ValueError:
        return False


class RunCommand(TyperCommand):
    """``run``, checking that --start and --goal are each followed by exactly two numbers.

    Click takes the next two words whatever they are, so a missing number surfaced as a
    confusing error elsewhere (``--start -4 --goal 1 2`` read "--goal" as a number) and a third
    number became the scenario argument.
    """

    # ctx: a Context of the Click that typer bundles (typer does not export that class)
    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        for i, word in enumerate(args):
            if word == "--":
                break
            if word in XY_OPTIONS:
                count = 0
                while i + 1 + count < len(args) and _is_number(args[i + 1 + count]):
                    count += 1
                if count != 2:
                    got = " ".join(args[i + 1 : i + 1 + max(count, 2)]) or "nothing"
                    raise typer.BadParameter(
                        f"needs two numbers X Y (e.g. {word} -1.9 6.41); got {got}",
                        ctx,
                        param_hint=f"'{word}'",
                    )
        return super().parse_args(ctx, args)


def _given(ctx: typer.Context, names: tuple[str, ...]) -> list[str]:
    """The flags of the parameters ``names`` that the command line set."""
    # compared by name: typer bundles its own Click and does not export ParameterSource
    return [
        param.opts[0]
        for param in ctx.command.params
        if param.name in names
        and getattr(ctx.get_parameter_source(param.name), "name", None) == "COMMANDLINE"
    ]


def _applies(flags: list[str]) -> str:
    return ", ".join(flags) + (" only applies" if len(flags) == 1 else " only apply")


@app.command(cls=RunCommand)
def run(
    ctx: typer.Context,
    scenario: Annotated[
        str | None,
        typer.Argument(
            help="Built-in scenario name, generated:FAMILY (a generated scene, --seed picks "
            "it) or path to a YAML file."
        ),
    ] = None,
    planner: Annotated[str, typer.Option(help="Planner name (see `socialnav list`).")] = "paccet",
    robot: Annotated[str, typer.Option(help=ROBOT_HELP)] = "pr2",
    seed: Annotated[
        int,
        typer.Option(
            min=0,
            max=MAX_SEED,
            help="Seed for a scenario's jitter (a generated scene: which one); with --crowd, "
            "of the perception noise, and only with --context detected.",
        ),
    ] = 0,
    humans: Annotated[
        str, typer.Option(help="Scenario only: scripted (the paper) or reactive (navground HL).")
    ] = ("scripted"),
    out: Annotated[
        Path,
        typer.Option(
            help="Output folder; an earlier run's files there (trajectory.*, episode.*, "
            "metrics.json, topdown.png, diagnostics.parquet, decision.png) are replaced, "
            "other files are kept."
        ),
    ] = Path("out"),
    fmt: Annotated[str, typer.Option("--format", help="Step table format: parquet or csv.")] = (
        "parquet"
    ),
    video: Annotated[
        str,
        typer.Option(
            help="none, gif or mp4 (candidate fan by score); mp4 needs the optional video "
            "extra (imageio-ffmpeg)."
        ),
    ] = "none",
    crowd: Annotated[
        Path | None, typer.Option(help="A recorded crowd (obsmat, frame-id-x-y, ndjson).")
    ] = None,
    t0: Annotated[
        float | None,
        typer.Option(help="--crowd only: start time in the recording (s); default its start."),
    ] = None,
    start: Annotated[
        tuple[float, float] | None,
        typer.Option(metavar="X Y", help="--crowd only: robot start X Y (m)."),
    ] = None,
    goal: Annotated[
        tuple[float, float] | None,
        typer.Option(metavar="X Y", help="--crowd only: goal X Y (m)."),
    ] = None,
    switch_distance: Annotated[
        float | None,
        typer.Option(help="--crowd only: people this close (m) switch to navground HL."),
    ] = None,
    context: Annotated[
        str,
        typer.Option(
            help="given (the scenario's structures; with --crowd the people, exactly) or "
            "detected (noisy tracks and the context estimator)."
        ),
    ] = "given",
) -> None:
    """Run one scenario (or a recorded crowd) with one planner.

    Writes the trajectories, the metrics and the figures. With --crowd FILE,
    the task is --t0, --start X Y and --goal X Y and the files are the same.
    Options marked "--crowd only" or "Scenario only" fail in the other mode.
    """
    from socialnav.core.errors import ConfigurationError
    from socialnav.experiments.run import run_single

    if crowd is not None:
        if scenario is not None:
            _fail(f"give a scenario or --crowd FILE, not both (got scenario {scenario!r})")
        misplaced = _given(ctx, SCENARIO_ONLY)
        if misplaced:
            _fail(f"{_applies(misplaced)} to a scenario, not with --crowd")
        if context != "detected" and _given(ctx, ("seed",)):
            # a crowd task is given, not drawn: the only random choice is perception's
            _fail("--seed with --crowd only applies to --context detected (the perception noise)")
        _run_crowd(
            crowd, t0, start, goal, planner, robot, out, switch_distance, fmt, video, context, seed
        )
        return
    misplaced = _given(ctx, CROWD_ONLY)
    if misplaced:
        _fail(f"{_applies(misplaced)} with --crowd, not with a scenario")
    if scenario is None:
        _fail("give a scenario, or --crowd FILE [--t0 T] --start X Y --goal X Y")
        return
    try:
        summary = run_single(
            scenario,
            planner,
            robot,
            seed=seed,
            humans=humans,
            out=out,
            fmt=fmt,
            video=video,
            progress=_progress,
            warn=_warn,
            context=context,
        )
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    typer.echo(json.dumps(summary, indent=1))


def _progress(line: str) -> None:
    typer.echo(line, err=True)


def _run_crowd(
    data: Path,
    t0: float | None,
    start: tuple[float, float] | None,
    goal: tuple[float, float] | None,
    planner: str,
    robot: str,
    out: Path,
    switch_distance: float | None,
    fmt: str,
    video: str,
    context: str = "given",
    seed: int = 0,
) -> None:
    from socialnav.core.errors import ConfigurationError
    from socialnav.experiments.crowd import run_crowd_single

    if start is None or goal is None:
        _fail("--crowd needs --start X Y and --goal X Y")
        return
    try:
        summary = run_crowd_single(
            data,
            t0,
            start,
            goal,
            planner,
            robot,
            out=out,
            switch_distance=switch_distance,
            fmt=fmt,
            video=video,
            progress=_progress,
            warn=_warn,
            context=context,
            seed=seed,
        )
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    typer.echo(json.dumps(summary, indent=1))


def _compare_crowds(
    data: list[Path],
    planners: list[str],
    robots: list[str],
    seeds: str,
    out: Path,
    jobs: int,
    resume: bool,
    switch_distance: float | None,
    backend: str = "local",
    address: str | None = None,
    contexts: tuple[str, ...] = ("given",),
) -> None:
    """``compare --suite crowds``: every --data file × planners (+ straight_line) × robots,
    once per social context."""
    from socialnav.core.errors import ConfigurationError
    from socialnav.crowds.episodes import generate_episode
    from socialnav.experiments.crowd import (
        REPORT_SEEDS,
        check_stored_recordings,
        crowd_specs,
        load_noting,
        parse_seeds,
        unique_recordings,
    )
    from socialnav.experiments.results import ResultStore
    from socialnav.report.crowd import build_crowd_report

    if not data:
        _fail("--suite crowds needs --data FILE (a recorded crowd; repeat for several)")
    try:
        files = unique_recordings([str(p) for p in data])
        first = parse_seeds(seeds or REPORT_SEEDS).start
        for path in files:
            # a bad file, or one that yields no episode, fails here, not as a row per run
            recording, said = load_noting(path)
            for line in said:
                _warn(line)
            generate_episode(recording, first)
        stored = [r for r in ResultStore(out, notify=_warn).load() if r.get("suite") == "crowds"]
        check_stored_recordings(stored, files)
        specs = crowd_specs(
            files,
            planners,
            robots,
            parse_seeds(seeds or REPORT_SEEDS),
            switch_distance,
            contexts,
        )
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    rows = _run_with_progress(specs, out, jobs, resume, "crowds", backend, address)
    report = build_crowd_report(rows, out)
    failed = sum(1 for r in rows if r.get("error"))
    typer.echo(f"{len(rows)} runs ({failed} errors) → {report}")


def _run_with_progress(
    specs: list[Any],
    out: Path,
    jobs: int,
    resume: bool,
    suite: str,
    backend: str = "local",
    address: str | None = None,
) -> list[dict[str, Any]]:
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

    from socialnav.experiments.suite import run_suite

    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
    ) as bar:
        task = bar.add_task(f"{suite} suite", total=len(specs))

        def advance(done: int, total: int) -> None:
            if done == 0 and total < len(specs):
                bar.console.print(
                    f"{len(specs) - total} of {len(specs)} episodes already stored in {out}; "
                    f"running the other {total}"
                )
            bar.update(task, completed=done, total=total)

        return run_suite(
            specs,
            out,
            n_jobs=jobs,
            resume=resume,
            progress=advance,
            suite=suite,
            backend=backend,
            address=address,
            notify=_warn,
        )


def _compare_generated(
    families: str,
    planners: list[str],
    robots: list[str],
    seeds: str | None,
    out: Path,
    jobs: int,
    resume: bool,
    backend: str = "local",
    address: str | None = None,
    contexts: tuple[str, ...] = ("given",),
) -> None:
    """``compare --suite generated``: family × planner × robot × seed (socialnav.sim.generate),
    once per social context."""
    from socialnav.experiments.crowd import parse_seeds
    from socialnav.experiments.suite import generated_specs
    from socialnav.report.generated import build_generated_report
    from socialnav.sim.generate import GENERATORS

    names = _split(families) or GENERATORS.names()
    for name in names:
        GENERATORS.get(name)  # an unknown family fails here (ConfigurationError)
    specs = generated_specs(
        names, planners, robots, parse_seeds(seeds or "10000:10020"), contexts=contexts
    )
    rows = _run_with_progress(specs, out, jobs, resume, "generated", backend, address)
    report = build_generated_report(rows, out)
    failed = sum(1 for r in rows if r.get("error"))
    typer.echo(f"{len(rows)} runs ({failed} errors) → {report}")


@app.command()
def compare(
    out: Annotated[Path, typer.Option(help="Report folder.")] = Path("report"),
    suite: Annotated[
        str, typer.Option(help="paper, reactive, randomized, crowds or generated.")
    ] = "paper",
    planners: Annotated[str, typer.Option(help="Comma-separated planner names; default all.")] = "",
    robots: Annotated[str, typer.Option(help="Comma-separated robot models.")] = "pr2,pioneer",
    scenarios: Annotated[str, typer.Option(help="Comma-separated scenarios; default all.")] = "",
    seeds: Annotated[
        str | None,
        typer.Option(
            help="Seeds A:B, or N for 0:N (randomized: 20; crowds: 10000:10050 reports; "
            "generated: below 10000 development, 10000 and up reporting, default 10000:10020)."
        ),
    ] = None,
    families: Annotated[
        str,
        typer.Option(
            help="--suite generated: comma-separated families (" + GENERATED_FAMILIES + "); "
            "default all."
        ),
    ] = "",
    jobs: Annotated[int, typer.Option(help="Parallel workers; -1 = all cores.")] = -1,
    resume: Annotated[bool, typer.Option(help="Skip runs already in the report folder.")] = True,
    data: Annotated[
        list[Path] | None, typer.Option(help="--suite crowds: a recorded crowd file (repeat).")
    ] = None,
    switch_distance: Annotated[
        float | None,
        typer.Option(help="--suite crowds: replayed people this close (m) switch to HL."),
    ] = None,
    backend: Annotated[
        str, typer.Option(help="Where episodes run: local (process pool), dask or ray.")
    ] = "local",
    address: Annotated[
        str | None,
        typer.Option(help="Join a running cluster: Dask scheduler tcp://HOST:8786, Ray auto."),
    ] = None,
    context: Annotated[
        str,
        typer.Option(
            help="given (the scenario's groups, queues, viewers), detected (noisy tracks and "
            "the context estimator), or both (side by side in the report)."
        ),
    ] = "given",
) -> None:
    """The main job: every scenario × planner × robot, into a report with figures.

    The report is written as Markdown and HTML in the --out folder.
    """
    from socialnav.core.errors import ConfigurationError
    from socialnav.experiments.backends import check_backend
    from socialnav.experiments.crowd import parse_seeds
    from socialnav.experiments.planners import CONTROLLERS, compared_planners
    from socialnav.experiments.run import check_robot
    from socialnav.experiments.suite import suite_specs
    from socialnav.report.build import build_report
    from socialnav.sim.scenario import builtin_scenarios, load_scenario

    if suite not in ("paper", "reactive", "randomized", "crowds", "generated"):
        _fail(f"unknown suite {suite!r}; use paper, reactive, randomized, crowds or generated")
    contexts = {"given": ("given",), "detected": ("detected",), "both": ("given", "detected")}
    if context not in contexts:
        _fail(f"unknown context {context!r}; use given, detected or both")
    if jobs == 0:
        _fail("--jobs must be a number of workers >= 1, or negative (-1: every core)")
    # an option another suite reads would be ignored silently: refuse it, as `run` does
    misplaced = (  # (option, set on the command line, the suites that read it)
        ("--data", bool(data), ("crowds",)),
        ("--switch-distance", switch_distance is not None, ("crowds",)),
        ("--families", bool(families), ("generated",)),
        ("--scenarios", bool(scenarios), ("paper", "reactive", "randomized")),
    )
    for option, given, readers in misplaced:
        if given and suite not in readers:
            where = ", ".join(readers[:-1]) + (" or " if len(readers) > 1 else "") + readers[-1]
            _fail(f"{option} applies only with --suite {where}, not --suite {suite}")
    try:
        check_backend(backend, address)
        planner_names = _split(planners) or compared_planners()
        for name in planner_names:
            CONTROLLERS.get(name)
        for name in _split(robots):
            check_robot(name)
        if suite == "crowds":
            _compare_crowds(
                data or [],
                planner_names,
                _split(robots),
                seeds or "",
                out,
                jobs,
                resume,
                switch_distance,
                backend,
                address,
                contexts=contexts[context],
            )
            return
        if suite == "generated":
            _compare_generated(
                families,
                planner_names,
                _split(robots),
                seeds,
                out,
                jobs,
                resume,
                backend,
                address,
                contexts=contexts[context],
            )
            return
        for name in _split(scenarios):
            load_scenario(name)  # an unknown name fails here, not as one error row per run
        specs = suite_specs(
            suite,
            _split(scenarios) or builtin_scenarios(),
            planner_names,
            _split(robots),
            None if seeds is None else parse_seeds(seeds),
            contexts=contexts[context],
        )
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    rows = _run_with_progress(specs, out, jobs, resume, suite, backend, address)
    report = build_report(rows, out, suite=suite)
    failed = sum(1 for r in rows if r.get("error"))
    typer.echo(f"{len(rows)} runs ({failed} errors) → {report}")


@app.command()
def report(
    results_dir: Annotated[Path, typer.Argument(help="A folder `socialnav compare` wrote.")],
    suite: Annotated[
        str | None, typer.Option(help="Which suite's rows (default: the only one stored).")
    ] = None,
) -> None:
    """Rebuild report.md and report.html from the results already stored in RESULTS_DIR."""
    from socialnav.experiments.results import load_results, suites_in
    from socialnav.report.build import build_report
    from socialnav.report.crowd import build_crowd_report

    rows = load_results(results_dir, notify=_warn)
    present = suites_in(rows)
    if not present:
        _fail(f"{results_dir}: no results found (expected {results_dir / 'results'})")
    if suite is None:
        if len(present) > 1:
            _fail(f"{results_dir} holds suites {', '.join(present)}; choose one with --suite")
        suite = present[0]
    elif suite not in present:
        _fail(f"{results_dir} has no rows of suite {suite!r}; it has {', '.join(present)}")
    selected = [r for r in rows if r["suite"] == suite]
    if suite == "crowds":
        path = build_crowd_report(selected, results_dir)
    elif suite == "generated":
        from socialnav.report.generated import build_generated_report

        path = build_generated_report(selected, results_dir)
    else:
        path = build_report(selected, results_dir, suite=suite)
    failed = sum(1 for r in selected if r.get("error"))
    typer.echo(f"{len(selected)} runs ({failed} errors) → {path}")


@app.command()
def detect(
    source: Annotated[
        str,
        typer.Argument(
            help="Crowd recording (obsmat, frame-id-x-y text, Trajnet++ ndjson), episode folder "
            "(from run/compare), built-in scenario or YAML."
        ),
    ],
    out: Annotated[Path, typer.Option(help="Output folder.")] = Path("detect"),
    noise: Annotated[str, typer.Option(help="Perception noise: default or none.")] = "default",
    seed: Annotated[
        int, typer.Option(min=0, max=MAX_SEED, help="Seed of the perception noise.")
    ] = 0,
    velocity_source: Annotated[
        str,
        typer.Option(
            help="Standing or walking from the tracks' velocities (measured) or from each "
            "track's position history (positions: for tracks without velocities or with "
            "velocities differenced from noisy positions)."
        ),
    ] = "measured",
    fformations: Annotated[
        str,
        typer.Option(
            help="F-formation detector: fformation (o-space voting and graph cuts, GCFF) or "
            "dominant_sets (Hung & Kröse 2011)."
        ),
    ] = "fformation",
) -> None:
    """Estimate the social context over a recording or a scenario.

    Writes the structures found per frame (structures.parquet) and a picture.
    """
    from socialnav.core.errors import ConfigurationError
    from socialnav.experiments.detect import detect_file
    from socialnav.social.perception import EstimatorParams
    from socialnav.social.perception.estimator import VelocitySource

    if fformations not in ("fformation", "dominant_sets"):
        _fail(f"--fformations must be fformation or dominant_sets, got {fformations!r}")
        return
    try:
        base = EstimatorParams()
        pipeline = tuple(fformations if n == "fformation" else n for n in base.pipeline)
        params = EstimatorParams(
            velocity_source=cast("VelocitySource", velocity_source), pipeline=pipeline
        )
        summary = detect_file(source, out, noise=noise, seed=seed, params=params)
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    typer.echo(json.dumps(summary, indent=1))


@app.command()
def validate(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or path to a YAML file.")],
) -> None:
    """Check a scenario file, its geometry and its ROS map.

    Geometry: start, goal and people outside walls and obstacles, start and goal on the map.
    Errors name the file and the field.
    """
    from socialnav.core.errors import ConfigurationError
    from socialnav.sim.scenario import load_scenario

    try:
        loaded = load_scenario(scenario)
        problems = loaded.geometry_problems()
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    if problems:
        _fail("\n".join(f"{scenario}: {p}" for p in problems))
        return
    for warning in loaded.group_warnings():
        _warn(f"{scenario}: {warning}")
    typer.echo(f"{scenario}: ok ({loaded.name}, family {loaded.family})")


@app.command()
def schema(
    out: Annotated[Path | None, typer.Option(help="Write the JSON Schema here.")] = None,
) -> None:
    """Print (or write) the JSON Schema of scenario files, for editors."""
    from socialnav.sim.scenario import scenario_json_schema

    text = json.dumps(scenario_json_schema(), indent=2)
    if out is None:
        typer.echo(text)
    else:
        out.write_text(text + "\n")
        typer.echo(f"wrote {out}")


@app.command("list")
def list_components() -> None:
    """List built-in scenarios, generated families and planners (planners in display order)."""
    from socialnav.experiments.planners import CONTROLLERS, planner_names
    from socialnav.sim.generate import GENERATORS
    from socialnav.sim.scenario import builtin_scenarios

    typer.echo("scenarios: " + ", ".join(builtin_scenarios()))
    typer.echo("generated families (--suite generated): " + ", ".join(sorted(GENERATORS)))
    for name in planner_names():
        entry = CONTROLLERS.get(name)
        default = "" if entry.compared else " (not compared by default)"
        typer.echo(f"planner {name}: {entry.description}{default}")


@app.command("export-bag")
def export_bag(
    run_dir: Annotated[Path, typer.Argument(help="Folder written by `socialnav run`.")],
    fmt: Annotated[str, typer.Option("--format", help="rosbag2 storage: mcap or sqlite3.")] = (
        "mcap"
    ),
    out: Annotated[Path | None, typer.Option(help="Bag folder; default RUN_DIR/bag.")] = None,
    overwrite: Annotated[bool, typer.Option(help="Replace an existing bag folder.")] = False,
) -> None:
    """Export a run as a rosbag2 (map, odom frame, plans, people) for RViz, Foxglove, ros2 bag."""
    from socialnav.experiments.storage import EPISODE_FILE, load_episode
    from socialnav.integrations.rosbag import export_rosbag

    if fmt not in ("mcap", "sqlite3"):
        _fail(f"unknown bag format {fmt!r}; use mcap or sqlite3")
    if not (run_dir / EPISODE_FILE).is_file():
        _fail(f"{run_dir}: not a run folder (no {EPISODE_FILE}); write one with `socialnav run`")
    record = load_episode(run_dir)
    target = out if out is not None else run_dir / "bag"
    try:
        path = export_rosbag(record, target, storage=fmt, overwrite=overwrite)  # type: ignore[arg-type]
    except (FileExistsError, ImportError, ValueError) as exc:
        _fail(str(exc))
        return
    typer.echo(f"wrote {path}")


# --- ROS 2 --------------------------------------------------------------------------------


@app.command("ros2", context_settings={"allow_extra_args": True, "ignore_unknown_options": True})
def ros2(
    ctx: typer.Context,
    params: Annotated[
        Path | None, typer.Option(help="Nav2-style params file (socialnav: ros__parameters: ...).")
    ] = None,
    list_params: Annotated[
        bool,
        typer.Option(
            "--list-params",
            help="Print every node parameter (default, range, run-time changeable) and exit; "
            "needs no ROS.",
        ),
    ] = False,
    robot_model: Annotated[
        str, typer.Option(help="With --list-params: the model whose limits are the defaults.")
    ] = "pioneer",
    planner: Annotated[
        str,
        typer.Option(
            help="With --list-params: the preset whose local-planner parameters are the "
            "defaults (a --params file's robot_model and planner take precedence)."
        ),
    ] = "paccet",
) -> None:
    """Run the socialnav ROS 2 lifecycle node; arguments after --ros-args go to ROS."""
    import importlib.util

    from socialnav.core.errors import ConfigurationError
    from socialnav.integrations.ros2 import INSTALL_HINT
    from socialnav.integrations.ros2.params import load_params_file, param_specs

    if list_params:
        if params is not None:
            try:
                given = load_params_file(params)
            except ConfigurationError as exc:
                _fail(str(exc))
                return
            robot_model = str(given.get("robot_model", robot_model))
            planner = str(given.get("planner", planner))
        else:
            given = {}
        typer.echo("| parameter | default | range or choices | changeable at run time | meaning |")
        typer.echo("|---|---|---|---|---|")
        for spec in param_specs(robot_model, planner):
            default = given.get(spec.name, spec.default)
            if spec.choices:
                bounds = ", ".join(spec.choices)
            elif spec.min is not None or spec.max is not None:
                lo = "-inf" if spec.min is None else f"{spec.min:g}"
                hi = "inf" if spec.max is None else f"{spec.max:g}"
                bounds = f"[{lo}, {hi}]"
            else:
                bounds = ""
            dynamic = "yes" if spec.dynamic else "no"
            typer.echo(f"| `{spec.name}` | {default} | {bounds} | {dynamic} | {spec.description} |")
        return

    # the params file is checked even without ROS, and a missing extra is always named
    problems = []
    if params is not None:
        try:
            load_params_file(params)
            typer.echo(f"{params}: parameters OK", err=True)
        except ConfigurationError as exc:
            problems.append(str(exc))
    if importlib.util.find_spec("rclpy") is None:
        problems.append(INSTALL_HINT)
    if problems:
        _fail("\n".join(problems))
    from socialnav.integrations.ros2.node import main

    extra = [a for a in ctx.args if a != "--ros-args"]
    raise typer.Exit(code=main(None if params is None else str(params), extra))


if __name__ == "__main__":
    app()

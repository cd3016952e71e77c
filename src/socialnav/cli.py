"""The ``socialnav`` command line: run one scenario, compare planners, validate scenario files."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Socially-aware navigation with PaCcET: run scenarios, compare planners, make reports.",
)

ROBOT_HELP = "Robot model: pr2 (holonomic) or pioneer (differential drive)."


def _fail(message: str) -> None:
    typer.secho(f"error: {message}", fg=typer.colors.RED, err=True)
    raise typer.Exit(code=2)


def _split(value: str) -> list[str]:
    return [v.strip() for v in value.split(",") if v.strip()]


@app.command()
def run(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or path to a YAML file.")],
    planner: Annotated[str, typer.Option(help="Planner name (see `socialnav list`).")] = "paccet",
    robot: Annotated[str, typer.Option(help=ROBOT_HELP)] = "pr2",
    seed: Annotated[int, typer.Option(help="Seed for the scenario's jitter.")] = 0,
    humans: Annotated[
        str, typer.Option(help="scripted (the paper) or reactive (navground HL).")
    ] = ("scripted"),
    out: Annotated[Path, typer.Option(help="Output folder.")] = Path("out"),
    fmt: Annotated[str, typer.Option("--format", help="Step table format: parquet or csv.")] = (
        "parquet"
    ),
    video: Annotated[str, typer.Option(help="none, gif or mp4 (candidate fan by score).")] = "none",
) -> None:
    """Run one scenario with one planner; write trajectories, diagnostics, metrics and a figure."""
    from socialnav.core.errors import ConfigurationError
    from socialnav.experiments.run import run_single

    try:
        summary = run_single(
            scenario, planner, robot, seed=seed, humans=humans, out=out, fmt=fmt, video=video
        )
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    typer.echo(json.dumps(summary, indent=1))


@app.command()
def compare(
    out: Annotated[Path, typer.Option(help="Report folder.")] = Path("report"),
    suite: Annotated[str, typer.Option(help="paper, reactive, randomized or generated.")] = "paper",
    planners: Annotated[str, typer.Option(help="Comma-separated planner names; default all.")] = "",
    robots: Annotated[str, typer.Option(help="Comma-separated robot models.")] = "pr2,pioneer",
    scenarios: Annotated[str, typer.Option(help="Comma-separated scenarios; default all.")] = "",
    seeds: Annotated[
        str | None,
        typer.Option(
            help="Seeds: N (= 0:N) or A:B. Paper/randomized: N per scenario (randomized: 20). "
            "Generated: below 10000 development, 10000 and up reporting (default 10000:10020)."
        ),
    ] = None,
    families: Annotated[
        str, typer.Option(help="Generated suite: comma-separated families; default all.")
    ] = "",
    jobs: Annotated[int, typer.Option(help="Parallel workers; -1 = all cores.")] = -1,
    resume: Annotated[bool, typer.Option(help="Skip runs already in the report folder.")] = True,
) -> None:
    """The main job: every scenario × planner × robot, into a Markdown/HTML report with figures."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

    from socialnav.core.errors import ConfigurationError
    from socialnav.experiments.planners import CONTROLLERS, compared_planners
    from socialnav.experiments.run import check_robot
    from socialnav.experiments.suite import run_suite, suite_specs
    from socialnav.report.build import build_report
    from socialnav.sim.scenario import builtin_scenarios, load_scenario

    if suite not in ("paper", "reactive", "randomized", "generated"):
        _fail(f"unknown suite {suite!r}; use paper, reactive, randomized or generated")
    try:
        planner_names = _split(planners) or compared_planners()
        for name in planner_names:
            CONTROLLERS.get(name)
        for name in _split(robots):
            check_robot(name)
        if suite == "generated":
            specs = _generated_specs(families, planner_names, _split(robots), seeds)
        else:
            for name in _split(scenarios):
                load_scenario(name)  # an unknown name fails here, not as one error row per run
            n_seeds = None if seeds is None else len(_seed_range(seeds))
            specs = suite_specs(
                suite,
                _split(scenarios) or builtin_scenarios(),
                planner_names,
                _split(robots),
                n_seeds,
            )
    except ConfigurationError as exc:
        _fail(str(exc))
        return
    with Progress(
        "[progress.description]{task.description}",
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
    ) as bar:
        task = bar.add_task(f"{suite} suite", total=len(specs))

        def advance(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)

        rows = run_suite(specs, out, n_jobs=jobs, resume=resume, progress=advance)
    if suite == "generated":
        from socialnav.report.generated import build_generated_report

        report = build_generated_report(rows, out)
    else:
        report = build_report(rows, out, suite=suite)
    failed = sum(1 for r in rows if r.get("error"))
    typer.echo(f"{len(rows)} runs ({failed} errors) → {report}")


def _seed_range(text: str) -> range:
    from socialnav.core.errors import ConfigurationError
    from socialnav.experiments.suite import parse_seeds

    try:
        return parse_seeds(text)
    except ValueError as exc:
        raise ConfigurationError(str(exc)) from None


def _generated_specs(
    families: str, planners: list[str], robots: list[str], seeds: str | None
) -> list:
    """The generated suite's runs (``socialnav.sim.generate``)."""
    from socialnav.experiments.suite import generated_specs
    from socialnav.sim.generate import GENERATORS

    names = _split(families) or GENERATORS.names()
    for name in names:
        GENERATORS.get(name)
    return generated_specs(names, planners, robots, _seed_range(seeds or "10000:10020"))


@app.command()
def validate(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or path to a YAML file.")],
) -> None:
    """Check a scenario file; errors name the file and the field."""
    from socialnav.core.errors import ConfigurationError
    from socialnav.sim.scenario import load_scenario

    try:
        loaded = load_scenario(scenario)
    except ConfigurationError as exc:
        _fail(str(exc))
        return
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
    """List built-in scenarios and planners (planners in display order)."""
    from socialnav.experiments.planners import CONTROLLERS, planner_names
    from socialnav.sim.scenario import builtin_scenarios

    typer.echo("scenarios: " + ", ".join(builtin_scenarios()))
    for name in planner_names():
        entry = CONTROLLERS.get(name)
        default = "" if entry.compared else " (not compared by default)"
        typer.echo(f"planner {name}: {entry.description}{default}")


if __name__ == "__main__":
    app()

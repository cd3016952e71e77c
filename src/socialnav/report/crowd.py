"""The crowd suite's report: one section per recording, a table for every planner and robot,
and a figure of a few episodes' paths over the crowd's tracks.

Columns follow SocNavBench / Francis et al. (``socialnav.metrics.crowd``): success (goal
reached, no active contact, no obstacle); the share of episodes with an active and with a
passive contact; mean minimum body gap; mean time with the body gap under 0.45 m and 1.2 m;
mean path length ratio and time to goal (over successful episodes); mean jerk; planner step
time p50 and p95 pooled over every step of every episode (our planners only). The
``straight_line`` reference shows how crowded the episodes are: its contact share is the bar
that passive contacts are held against.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from socialnav.report.document import (
    Document,
    Heading,
    Image,
    Paragraph,
    Table,
    to_html,
    to_markdown,
)

REFERENCE = "straight_line"
#: episodes drawn per dataset figure
FIGURE_EPISODES = 3
HEADER = [
    "planner",
    "robot",
    "n",
    "success %",
    "active %",
    "passive %",
    "contact %",
    "min gap m",
    "t<0.45 s",
    "t<1.2 s",
    "path ratio",
    "time s",
    "jerk m/s³",
    "ms p50",
    "ms p95",
]


def _m(name: str) -> str:
    """The results column of metric ``name`` (``socialnav.experiments.results``)."""
    from socialnav.experiments.results import metric_column

    return metric_column(name)


def _values(rows: Sequence[dict[str, Any]], key: str) -> np.ndarray:
    return np.array([float(r.get(key, math.nan)) for r in rows], dtype=float)


def _nanmean(values: np.ndarray) -> float:
    finite = values[np.isfinite(values)]
    return float(finite.mean()) if finite.size else math.nan


def summary(rows: Sequence[dict[str, Any]]) -> dict[str, float]:
    """Aggregates of one planner × robot × dataset (see the module docstring)."""
    ok = [r for r in rows if not r.get("error")]
    n = len(ok)
    success = _values(ok, _m("success"))
    done = success > 0.5
    steps = [v for r in ok for v in (r.get("planner_ms_steps") or [])]
    return {
        "n": n,
        "success": 100.0 * float(success.mean()) if n else math.nan,
        "active": 100.0 * float((_values(ok, _m("collisions_active")) > 0).mean())
        if n
        else math.nan,
        "passive": 100.0 * float((_values(ok, _m("collisions_passive")) > 0).mean())
        if n
        else math.nan,
        "any_contact": 100.0
        * float(
            (
                (_values(ok, _m("collisions_active")) + _values(ok, _m("collisions_passive"))) > 0
            ).mean()
        )
        if n
        else math.nan,
        "min_gap": _nanmean(_values(ok, _m("min_distance_footprint"))),
        "t045": _nanmean(_values(ok, _m("time_within_0.45"))),
        "t12": _nanmean(_values(ok, _m("time_within_1.2"))),
        "path_ratio": _nanmean(_values(ok, _m("path_length_ratio"))[done]),
        "time": _nanmean(_values(ok, _m("time_to_goal"))[done]),
        "jerk": _nanmean(_values(ok, _m("mean_jerk"))),
        "ms_p50": float(np.percentile(steps, 50)) if steps else math.nan,
        "ms_p95": float(np.percentile(steps, 95)) if steps else math.nan,
    }


def _order(planners: set[str]) -> list[str]:
    try:
        from socialnav.experiments.planners import planner_names

        known = [p for p in planner_names() if p in planners and p != REFERENCE]
    except ImportError:  # pragma: no cover - the experiments layer is always there
        known = []
    rest = sorted(planners - set(known) - {REFERENCE})
    return known + rest + ([REFERENCE] if REFERENCE in planners else [])


def switch_distance(row: dict[str, Any]) -> float | None:
    """The row's ``switch_distance`` (m), or None when its people never react."""
    value = row.get("switch_distance")
    if value is None:
        return None
    value = float(value)
    return None if math.isnan(value) else value


def reproduce(rows: Sequence[dict[str, Any]]) -> str:
    """The ``socialnav compare`` command(s) that run ``rows`` again, as Markdown code: files,
    seed range, planners (the straight-line reference runs anyway), robots, context, and one
    command per switch distance."""
    files = list(dict.fromkeys(str(r["data"]) for r in rows if r.get("data")))
    seeds = sorted({int(r["seed"]) for r in rows})
    planners = [p for p in _order({r["planner"] for r in rows}) if p != REFERENCE] or [REFERENCE]
    robots = sorted({r["robot"] for r in rows})
    parts = ["socialnav compare --suite crowds", *(f"--data {f}" for f in files)]
    if seeds:
        parts.append(f"--seeds {seeds[0]}:{seeds[-1] + 1}")
    parts += [f"--planners {','.join(planners)}", f"--robots {','.join(robots)}"]
    seen = {r.get("context") or "given" for r in rows}
    if seen != {"given"}:
        parts.append("--context " + ("both" if len(seen) > 1 else next(iter(seen))))
    base = " ".join(parts)
    reacts = sorted({switch_distance(r) for r in rows}, key=lambda d: -1.0 if d is None else d)
    commands = [base if d is None else f"{base} --switch-distance {d:g}" for d in reacts]
    return ", and ".join(f"`{c}`" for c in commands)


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" if n == 1 else f"{n} {noun}s"


def _seed_span(seeds: Sequence[int]) -> str:
    if not seeds:
        return "no seeds"
    if len(seeds) == 1:
        return f"seed {seeds[0]}"
    return f"seeds {seeds[0]}–{seeds[-1]}"


def dataset_table(
    rows: Sequence[dict[str, Any]],
) -> tuple[list[list[Any]], dict[tuple[str, str], dict[str, float]]]:
    """Table rows and the summaries by ``(planner, robot)`` of one dataset."""
    table, by_key = [], {}
    for robot in sorted({r["robot"] for r in rows}):
        for planner in _order({r["planner"] for r in rows}):
            sel = [r for r in rows if r["planner"] == planner and r["robot"] == robot]
            if not sel:
                continue
            s = summary(sel)
            by_key[(planner, robot)] = s
            table.append(
                [
                    planner,
                    robot,
                    int(s["n"]),
                    s["success"],
                    s["active"],
                    s["passive"],
                    s["any_contact"],
                    s["min_gap"],
                    s["t045"],
                    s["t12"],
                    s["path_ratio"],
                    s["time"],
                    s["jerk"],
                    s["ms_p50"],
                    s["ms_p95"],
                ]
            )
    return table, by_key


def targets(by_key: dict[tuple[str, str], dict[str, float]], planner: str = "paccet") -> list[str]:
    """The issue's targets for ``planner`` on one dataset, one line per robot: met, missed, or
    not evaluated (a target that compares against runs that are not there: the straight-line
    reference, or any other planner)."""
    lines = []
    for (name, robot), s in sorted(by_key.items()):
        if name != planner:
            continue
        ref = by_key.get((REFERENCE, robot))
        others = [v for (p, r), v in by_key.items() if r == robot and p not in (planner, REFERENCE)]
        checks: dict[str, bool | None] = {
            "success ≥ 95 %": s["success"] >= 95.0,
            "active contacts 0": s["active"] == 0.0,
            "passive ≤ ⅓ of straight-line contacts": None
            if ref is None
            else s["passive"] <= ref["any_contact"] / 3.0,
            "time within 1.2 m below every baseline": all(s["t12"] < o["t12"] for o in others)
            if others
            else None,
            "path ratio ≤ 1.25": s["path_ratio"] <= 1.25,
            "step p95 ≤ 50 ms": s["ms_p95"] <= 50.0,
        }
        met = [k for k, v in checks.items() if v is True]
        missed = [k for k, v in checks.items() if v is False]
        unset = [k for k, v in checks.items() if v is None]
        line = (
            f"`{planner}` on {robot}: met — {', '.join(met) or 'none'}; "
            f"missed — {', '.join(missed) or 'none'}"
        )
        if unset:
            line += f"; not evaluated (no run to compare with) — {', '.join(unset)}"
        lines.append(line + ".")
    return lines


def _figure(
    rows: Sequence[dict[str, Any]], out_dir: Path, name: str, title: str = ""
) -> str | None:
    """A few episodes of paccet (else the first planner) on the first robot, with the
    straight-line reference of the same episodes: ``figures/crowd_<name>.png``, headed
    ``title`` (default ``name``)."""
    from socialnav.experiments.storage import load_episode
    from socialnav.viz.crowd import plot_crowd_episodes
    from socialnav.viz.topdown import save_figure

    ok = [r for r in rows if not r.get("error")]
    if not ok:
        return None
    planners = _order({r["planner"] for r in ok})
    main = "paccet" if "paccet" in planners else planners[0]
    robot = sorted({r["robot"] for r in ok})[0]
    seeds = sorted({r["seed"] for r in ok if r["planner"] == main and r["robot"] == robot})
    records = []
    for seed in seeds[:FIGURE_EPISODES]:
        for planner in dict.fromkeys([main, REFERENCE]):
            match = [
                r for r in ok if (r["planner"], r["robot"], r["seed"]) == (planner, robot, seed)
            ]
            folder = out_dir / "runs" / match[0]["run_id"] if match else None
            if folder is not None and folder.is_dir():
                records.append(load_episode(folder))
    if not records:
        return None
    path = out_dir / "figures" / f"crowd_{name}.png"
    save_figure(
        plot_crowd_episodes(records, title=f"{title or name}: {main} and {REFERENCE}", columns=2),
        path,
    )
    return str(path.relative_to(out_dir))


def build_crowd_report(rows: Sequence[dict[str, Any]], out_dir: Path) -> Path:
    """Write ``report.md`` and ``report.html`` of a crowd suite into ``out_dir``."""
    doc = Document("socialnav: planners in recorded crowds")
    datasets = sorted({r["scenario"] for r in rows})
    # runs whose people switch to HL are another experiment: a section of their own
    sections = sorted(
        {(r["scenario"], switch_distance(r), r.get("context") or "given") for r in rows},
        key=lambda k: (k[0], -1.0 if k[1] is None else k[1], k[2] != "given"),
    )
    seeds = sorted({int(r["seed"]) for r in rows})
    reacting = sorted({d for _, d, _ in sections if d is not None})
    people = "people replayed from the recordings (they do not react to the robot)"
    if reacting:
        people += (
            "; in the sections that say so, each replayed person switches to navground's HL "
            "toward their recorded destination once the robot is within the switch distance "
            f"({', '.join(f'{d:g} m' for d in reacting)}; `--switch-distance`)"
        )
    if any(c == "detected" for _, _, c in sections):
        people += (
            '; in the sections marked "context detected" the planner sees noisy tracks '
            "(the default perception noise) and the context estimator's structures, never "
            "the recording itself (`--context detected`); contacts and distances are measured "
            "on the true people"
        )
    doc.add(
        Paragraph(
            f"{len(rows)} runs over {_count(len(datasets), 'recording')} "
            f"({', '.join(datasets)}), {_seed_span(seeds)}; {people}, 0.1 s control period. "
            f"Reproduce with {reproduce(rows)}. Seeds below 10,000 are for tuning; report "
            "seeds 10,000 and up."
        )
    )
    for name, react, seen in sections:
        sel = [
            r
            for r in rows
            if r["scenario"] == name
            and switch_distance(r) == react
            and (r.get("context") or "given") == seen
        ]
        title, tag = f"Recording {name}", name
        if react is not None:
            title += f", people switching to HL within {react:g} m"
            tag += f"_hl{react:g}"
        if seen != "given":
            title += f", context {seen}"
            tag += f"_{seen}"
        doc.add(Heading(title))
        flows = {r["seed"]: r["flow"] for r in sel if r.get("flow")}
        along = sum(1 for f in flows.values() if f == "along")
        across = sum(1 for f in flows.values() if f == "across")
        doc.add(
            Paragraph(
                f"{_count(len(flows), 'episode')} (each run with every robot): {along} along "
                f"the main flow, {across} across it. A contact is the robot's footprint touching a "
                "person: active when the footprint was closing on them (turning included) "
                "faster than 0.05 m/s, except in steps where the robot brakes at its "
                "acceleration limits right after they appear in the recording, passive "
                "otherwise (stopped, or moving away while they walk into it). Success % = "
                "episodes that reach the goal in time with no "
                "active contact; active / passive / contact % = episodes with such a contact "
                "(contact: either kind). Min gap and t<0.45 s / t<1.2 s use the body-to-body "
                "gap (footprint to the person's disc): its episode minimum (the table gives the "
                "mean of those minima; the worst is in the results' "
                "`min_distance_footprint`), and the time it stays under Hall's intimate and "
                "personal distances, over every episode; path "
                "ratio (path length over the start-goal distance; straight lines end inside "
                "the goal tolerance, so slightly under 1) and time over successful episodes; "
                "ms = planner step time pooled over every step (our planners only). The lines "
                "under the table check `paccet` against the targets of the recorded-crowds "
                "benchmark (success ≥ 95 %, no active contact, passive contacts at most a "
                "third of the straight-line reference's contact episodes, less time within "
                "1.2 m than every other planner at a path ratio ≤ 1.25, step p95 ≤ 50 ms)."
            )
        )
        table, by_key = dataset_table(sel)
        doc.add(Table(HEADER, table, caption=f"{name}: means over episodes"))
        for line in targets(by_key):
            doc.add(Paragraph(line))
        figure = _figure(sel, out_dir, tag, title.removeprefix("Recording "))
        if figure:
            doc.add(Image(figure, f"{name} paths"))
    errors = [r for r in rows if r.get("error")]
    if errors:
        doc.add(Heading("Errors"))
        doc.add(
            Table(
                ["run", "error"], [[r["run_id"], str(r["error"]).splitlines()[0]] for r in errors]
            )
        )
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "report.md").write_text(to_markdown(doc))
    (out_dir / "report.html").write_text(to_html(doc, embed_from=out_dir))
    return out_dir / "report.md"

"""The generated suite's report: pass rate per family and robot with Wilson intervals, time
against every baseline over the scenes both pass, CrowdNav's own terms, and the worst failures
with their picture, failed condition and seed.

Families are the generators' names (``gallery_present`` and ``gallery_pass`` count apart, as do
``group_join`` and ``group_lead``). Every number comes from the rows given.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from socialnav.report.build import _planner_order, context_section, wilson_interval
from socialnav.report.document import (
    Document,
    Heading,
    Image,
    Paragraph,
    Table,
    to_html,
    to_markdown,
)

OURS = "paccet"
WORST_FAILURES = 12
WORST_BASELINE_FAILURES = 4


def family_of(row: dict[str, Any]) -> str:
    """The generator name of a generated row (``generated:<family>``)."""
    return str(row["scenario"]).removeprefix("generated:")


def _rate_cell(sel: Sequence[dict[str, Any]]) -> str:
    n, k = len(sel), sum((r.get("success") == 1.0) for r in sel)
    if not n:
        return "–"
    lo, hi = wilson_interval(k, n)
    return f"{k}/{n} ({k / n:.0%}) [{lo:.2f}, {hi:.2f}]"


def _time(row: dict[str, Any]) -> float:
    v = row.get("time_to_goal")
    return math.nan if v is None else float(v)


def pass_rate_section(doc: Document, rows: Sequence[dict[str, Any]], planners: list[str]) -> None:
    families = sorted({family_of(r) for r in rows})
    robots = sorted({r["robot"] for r in rows})
    doc.add(Heading("Pass rate per family and robot"))
    doc.add(
        Paragraph(
            "passed/runs (rate) [95% Wilson interval]. A run passes when every *required* "
            "condition holds; conditions a scene's geometry makes impossible for a robot are "
            "marked not required by the generator, with the reason"
            + (" (listed below)." if any(r.get("not_required") for r in rows) else ": none here.")
        )
    )
    body = []
    for fam in families:
        for robot in robots:
            line: list[Any] = [fam, robot]
            for p in planners:
                line.append(
                    _rate_cell(
                        [
                            r
                            for r in rows
                            if family_of(r) == fam and r["robot"] == robot and r["planner"] == p
                        ]
                    )
                )
            body.append(line)
    doc.add(Table(["family", "robot", *planners], body))
    collisions = {
        p: sum(1 for r in rows if r["planner"] == p and (r.get("collisions") or 0) > 0)
        for p in planners
    }
    doc.add(
        Paragraph(
            "Runs with a collision: " + ", ".join(f"{p} {n}" for p, n in collisions.items()) + "."
        )
    )
    waived: dict[str, list[str]] = {}
    for r in rows:
        if r.get("not_required"):
            waived.setdefault(r["not_required"], []).append(
                f"{family_of(r)} {r['robot']} {r['planner']} seed {r['seed']}"
            )
    if waived:
        doc.add(
            Table(
                ["not required, and why", "runs", "where"],
                [
                    [
                        note,
                        len(where),
                        ", ".join(sorted(where)[:6]) + (" …" if len(where) > 6 else ""),
                    ]
                    for note, where in sorted(waived.items())
                ],
            )
        )


def efficiency_section(doc: Document, rows: Sequence[dict[str, Any]], planners: list[str]) -> None:
    """Median and mean ratio of our time to goal over each baseline's, scenes both pass."""
    if OURS not in planners:
        return
    doc.add(Heading(f"Time to goal: {OURS} against every baseline (scenes both pass)"))
    if all(p == OURS for p in planners):
        doc.add(Paragraph(f"No baseline ran beside {OURS} (add some with `--planners`)."))
        return
    index = {(r["scenario"], r["robot"], r["seed"], r["planner"]): r for r in rows}
    body = []
    for other in planners:
        if other == OURS:
            continue
        for robot in sorted({r["robot"] for r in rows}):
            ratios = []
            for (scn, rb, seed, p), r in index.items():
                if p != OURS or rb != robot or r.get("success") != 1.0:
                    continue
                o = index.get((scn, rb, seed, other))
                if o is None or o.get("success") != 1.0:
                    continue
                a, b = _time(r), _time(o)
                if a > 0 and b > 0:
                    ratios.append(a / b)
            if ratios:
                body.append(
                    [other, robot, len(ratios), float(np.median(ratios)), float(np.mean(ratios))]
                )
            else:
                body.append([other, robot, 0, math.nan, math.nan])
    doc.add(
        Paragraph(
            f"Ratio = {OURS}'s time to goal / the baseline's on the same scene: below 1, "
            f"{OURS} is faster (the target is at most 1.25 against hl)."
        )
    )
    doc.add(Table(["baseline", "robot", "scenes both pass", "median ratio", "mean ratio"], body))


def crowdnav_section(doc: Document, rows: Sequence[dict[str, Any]], planners: list[str]) -> None:
    sel = [r for r in rows if family_of(r).startswith("crowdnav")]
    if not sel:
        return
    doc.add(Heading("CrowdNav test bank in CrowdNav's terms"))
    doc.add(
        Paragraph(
            "success = reached the goal without collision in time; collision / timeout shares; "
            "time = mean time to goal of successes (s); discomfort = share of steps with a body "
            "gap below 0.2 m (Chen et al. 2019)."
        )
    )
    body = []
    for fam in sorted({family_of(r) for r in sel}):
        for robot in sorted({r["robot"] for r in sel}):
            for p in planners:
                runs = [
                    r
                    for r in sel
                    if family_of(r) == fam and r["robot"] == robot and r["planner"] == p
                ]
                if not runs:
                    continue
                n = len(runs)
                coll = sum((r.get("collisions_person") or 0) > 0 for r in runs) / n
                succ = [r for r in runs if r.get("ok_reached_goal") and r.get("ok_no_collision")]
                timeout = sum(not r.get("ok_reached_goal") for r in runs) / n
                times = [_time(r) for r in succ]
                disc = [float(r.get("discomfort") or 0.0) for r in runs]
                body.append(
                    [
                        fam,
                        robot,
                        p,
                        n,
                        len(succ) / n,
                        coll,
                        timeout,
                        float(np.nanmean(times)) if times else math.nan,
                        float(np.mean(disc)),
                    ]
                )
    doc.add(
        Table(
            [
                "variant",
                "robot",
                "planner",
                "n",
                "success",
                "collision",
                "timeout",
                "time",
                "discomfort",
            ],
            body,
        )
    )


def _badness(row: dict[str, Any]) -> tuple[int, int, float]:
    """Sort key, worst first: a collision, then more failed conditions, then the closer
    approach to a person (centre to centre; a run without one sorts last among its peers)."""
    collided = (row.get("collisions") or 0) > 0
    failed = [c for c in str(row.get("failed_required") or "").split(",") if c]
    closest = row.get("min_distance_center")
    closest = float(closest) if closest is not None and math.isfinite(closest) else math.inf
    return (0 if collided else 1, -len(failed), closest)


def worst_failures_section(
    doc: Document,
    rows: Sequence[dict[str, Any]],
    out_dir: Path,
    planner: str = OURS,
    context: str = "",
    limit: int = WORST_FAILURES,
) -> None:
    """The ``limit`` worst failed runs of ``planner`` (:func:`_badness`: collisions, then the
    most failed conditions, then the closest approach to a person), each with its picture,
    failed conditions and the command that reruns it. ``context``: the social context the
    rows share, named in the heading ("given" beside detected runs compared in their own
    section, or "detected"); empty when there is nothing to tell apart."""
    failed = [r for r in rows if r["planner"] == planner and r.get("success") != 1.0]
    which = f" with the context {context}" if context else ""
    doc.add(Heading(f"Worst failures of {planner}{which}"))
    if not failed:
        doc.add(Paragraph(f"{planner} failed no run{which}."))
        return
    failed.sort(key=_badness)
    shown = failed[:limit]
    if len(failed) > len(shown):
        doc.add(Paragraph(f"The {len(shown)} worst of {len(failed)} failed runs."))
    fig_dir = out_dir / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    body = []
    for r in shown:
        why = r.get("failed_required") or r.get("error", "")[:60]
        rerun = _rerun_command([r], _context_of(r), _rerun_folder(r))
        body.append([family_of(r), r["robot"], r["seed"], why, rerun])
    doc.add(Table(["family", "robot", "seed", "failed condition", "rerun"], body))
    for r in shown:
        path = fig_dir / f"fail__{r['run_id']}.png"
        try:
            from socialnav.experiments.storage import load_episode
            from socialnav.viz.topdown import plot_episode, save_figure

            save_figure(
                plot_episode(load_episode(out_dir / "runs" / r["run_id"]), label=planner), path
            )
        except Exception:  # a missing run folder must not sink the report
            continue
        doc.add(
            Image(
                f"figures/{path.name}",
                f"{family_of(r)} {r['robot']} seed {r['seed']}: {r.get('failed_required')}",
            )
        )


def _context_of(row: dict[str, Any]) -> str:
    return str(row.get("context") or "given")


def _rerun_folder(row: dict[str, Any]) -> str:
    return f"rerun-{family_of(row)}-{row['robot']}-{row['planner']}-{row['seed']}"


def _rerun_command(rows: Sequence[dict[str, Any]], context: str = "given", out: str = "") -> str:
    """The ``socialnav compare`` command that reruns ``rows`` (seeds as their covering range)
    with ``--context`` ``context`` (``given``, the default, is left out), into ``out`` when
    given (a fresh folder: rerun in the report's own folder, ``--resume`` would skip the
    stored run)."""
    if not rows:
        return "socialnav compare --suite generated --seeds A:B"
    seeds = sorted({int(r["seed"]) for r in rows})
    families = ",".join(sorted({family_of(r) for r in rows}))
    planners = ",".join(_planner_order(rows))
    robots = ",".join(sorted({r["robot"] for r in rows}))
    return (
        f"socialnav compare --suite generated --families {families} "
        f"--seeds {seeds[0]}:{seeds[-1] + 1} --planners {planners} --robots {robots}"
        + (f" --context {context}" if context != "given" else "")
        + (f" --out {out}" if out else "")
    )


def build_generated_report(rows: Sequence[dict[str, Any]], out_dir: Path) -> Path:
    """Write ``report.md`` and ``report.html`` of a generated-suite run into ``out_dir``.

    With runs of both contexts, every section but "Social context" reports the given runs; a
    run of one context reports it and names it. Each planner that ran gets its worst failures
    (``paccet`` its ``WORST_FAILURES`` worst, a baseline its ``WORST_BASELINE_FAILURES``)."""
    all_rows = list(rows)
    all_ok = [r for r in rows if not r.get("error")]
    contexts = {_context_of(r) for r in rows}
    both = len(contexts) > 1
    if both:
        rows = [r for r in rows if _context_of(r) == "given"] or list(rows)
    context = "both" if both else next(iter(contexts), "given")
    detected = sum(_context_of(r) != "given" for r in all_rows) if both else 0
    ok = [r for r in rows if not r.get("error")]
    planners = _planner_order(ok) if ok else []
    seeds = sorted({int(r["seed"]) for r in rows})
    split = (
        "reporting split (seeds >= 10000)"
        if seeds and seeds[0] >= 10_000
        else "development split (seeds < 10000)"
        if seeds and seeds[-1] < 10_000
        else "mixed development and reporting seeds"
    )
    if both:
        counted = f" with the context given (and {detected} with it detected, compared at the end)"
    elif context != "given":
        counted = f" with the context {context}"
    else:
        counted = ""
    doc = Document("socialnav: generated suite")
    doc.add(
        Paragraph(
            f"{len(rows)} runs{counted}"
            + f", seeds {seeds[0] if seeds else '–'}–{seeds[-1] if seeds else '–'} "
            f"({split}); planners {', '.join(planners)}. Arrival tolerance 0.10 m (and 0.2 rad at "
            f"social spots). Reproduce with `{_rerun_command(all_rows, context)}`."
        )
    )
    pass_rate_section(doc, ok, planners)
    efficiency_section(doc, ok, planners)
    crowdnav_section(doc, ok, planners)
    named = "given" if both else ("" if context == "given" else context)
    # ours first: the planner the report is about, then the baselines in display order
    for planner in sorted(planners or [OURS], key=lambda name: name != OURS):
        limit = WORST_FAILURES if planner == OURS else WORST_BASELINE_FAILURES
        worst_failures_section(doc, ok, out_dir, planner, named, limit)
    if any(_context_of(r) == "detected" for r in all_ok):
        context_section(doc, [{**r, "family": family_of(r)} for r in all_ok], planners)
    errors = [r for r in all_rows if r.get("error")]
    if errors:
        doc.add(Heading("Errors"))
        doc.add(
            Table(
                ["run", "error"], [[r["run_id"], str(r["error"]).splitlines()[0]] for r in errors]
            )
        )
    (out_dir / "report.md").write_text(to_markdown(doc))
    (out_dir / "report.html").write_text(to_html(doc, embed_from=out_dir))
    return out_dir / "report.md"

"""Social-context estimator: accuracy on public data, on generated queues, and time per estimate.

Run: ``.venv/bin/python benchmarks/bench_context.py [--fit]`` (from the repository root; the
public data are read from ``../shared/data``, relative to it; sections whose data are absent
are skipped). Prints Markdown tables and writes them to ``benchmarks/out/context.md``.

1. F-formations (Cristani et al., BMVC 2011: Synth and CoffeeBreak Seq1, read with
   :mod:`socialnav.crowds.fformations`; annotations matched to feature frames by timestamp;
   positions in cm converted to metres). First what the files say: the headings'
   quantisation step (CoffeeBreak: 90°, its four head-pose classes; Synth: 15°), the
   published settings (``settings.mat``: a 0.6 m stride for both), and which reading of the
   orientation column makes people face their own group (counter-clockwise from +x, for
   both). Then precision, recall and F1 at T = 2/3 and T = 1 with the rule of
   :func:`socialnav.metrics.groups.group_detection_scores`, each frame alone, with the
   defaults, with GCFF's vote (``heading_tolerance = 0``), with its fixed stride (no
   wide-circle merge), with the dataset's published stride (and position σ), and with the
   heading step allowed for a priori (:func:`quantisation_allowed`); also Synth with its
   headings quantised to 4 directions, as CoffeeBreak's are, to see what quantisation alone
   costs. A dataset whose heading step is coarser than Synth's also gets parameters fitted
   on Synth with its headings quantised to that step (:func:`fit_on_synth`, the grid of the
   defaults and an open grid). ``--fit`` repeats the grid search on Synth that chose the
   defaults of :class:`FFormationParams`; CoffeeBreak is never used for fitting, except by
   ``--bound``: the best CoffeeBreak score of a 2880-point grid chosen on CoffeeBreak itself,
   an upper bound on what these parameters can reach (minutes). Then the frames as a
   sequence, through the estimator as it runs online (track smoothing: a standing person's
   position and heading are the running mean of their observations; optionally
   hysteresis), with the defaults and, for a coarse heading step, the open-grid parameters
   fitted on Synth quantised to it: both files are sequences
   (Synth: 10 static scenes of 10 jittered frames whose ids are reused by other people, so
   the estimator is reset at each scene; CoffeeBreak: one scene, people coming and going).
   The files give no time between frames, so Δt = 0.1 s (people missed for a frame are
   coasted; a few centimetres of jitter per frame reads as walking) and 1 s (beyond the
   0.6 s coast time: they are not) are both shown. Last, wide
   circles: 105 jittered circles (2–6 members, radius 0.6–1.5 m, σ 0.05 m, 10°, spacing
   jitter σ 0.15 rad; seed 0), found whole with GCFF's fixed stride and with the wide-circle
   merge (``FFormationParams.max_stride``, ``merge_facing``).

   **The sequence at any frame spacing** (``--only spacing``; also part of the F-formation
   section). The protocol, fixed and committed before its CoffeeBreak result was run:
   (a) F-formation parameters from :func:`protocol_fit`: the best of a 1152-point grid
   (:func:`protocol_grid`) on Synth's single frames with its headings quantised to the
   heading step detected in CoffeeBreak's features (90°), objective the mean of F1 at
   T = 2/3 and T = 1, fitted once; (b) the files' frames as a raw tracker reports them
   (:func:`raw_tracks`: velocities are finite differences over Δt, no standing is assumed);
   (c) the estimator online with ``velocity_source="positions"`` (its standing test from
   the position history, :func:`socialnav.social.perception.estimator.history_velocity`,
   with its a-priori values), hysteresis off; (d) scored on the people each frame lists
   (a person coasted over a missed detection is dropped from a detected group before
   scoring: the annotations cover listed people only); (e) Δt = 0.1, 0.4, 1 and 2 s, since
   the files do not give it. Also shown: the same with the differenced velocities taken as
   the tracks' own (the standing test before), hysteresis on, coasted people kept, the
   earlier open-grid fit (whose grid was widened after a CoffeeBreak result), and a table of
   how the result moves when each value of the standing test is changed alone (reported,
   not used to choose).
   **Dominant sets** (``--only dominant_sets``; also part of the F-formation section): the
   second F-formation detector (:mod:`socialnav.social.perception.dominant_sets`, Hung &
   Kröse 2011). Its protocol, fixed and committed before its CoffeeBreak result was run:
   the best of :func:`dominant_sets_grid` (875 sets) on Synth's single frames with headings
   quantised to the step detected in CoffeeBreak's features (90°), objective the mean of F1
   at T = 2/3 and T = 1 (first in grid order on ties); CoffeeBreak then scored once with it.
   **Calibrated to the heading source** (``--only calibrated``, minutes). Its protocol, fixed
   and committed before its CoffeeBreak result was run: the share of wrong headings of the
   held-out source estimated from its features alone (:func:`front_share` matched on Synth
   with that share of headings replaced at random), then the dominant-sets grid fitted on
   Synth so corrupted and quantised; CoffeeBreak scored once. Then, post hoc and so not
   held out, the fits with their lengths scaled by the two sets' spacing of mutual nearest
   neighbours.
2. Queues: 400 generated scenes (seeds 1014/1015; the parameters were tuned on 14/15), 2–8
   members, spacing 0.6–1.1 m, lateral bends up to 0.4 m, any orientation, position noise
   σ 0.1 m, heading noise σ 15°, with and without a desk (a service point from the map); a
   scene is correct when exactly one queue is found with the true members in the true order.
3. Walking groups on ETH hotel and UCY zara01 (Pellegrini et al. 2009; Lerner et al. 2007),
   read with :func:`socialnav.crowds.load_obsmat`, against their ``groups.txt``: pairwise
   precision and recall, pairs counted per annotated frame among the people present, with the
   estimator run over the frames in order (0.4 s apart, hysteresis on). The walking-group
   defaults were set a priori, not tuned on either.
4. Time per ``ContextEstimator.update`` with 10 and 50 people (a mix of conversations, a
   queue, walkers), exact tracks or with the simulator's default perception noise: the NumPy
   reference against the compiled GCFF solve, every component solved every cycle or
   incrementally (the default); median of 41 cycles after 20 warm-up cycles. ``--only``
   runs one section.
"""

from __future__ import annotations

import argparse
import itertools
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

from harness import Case, machine_note, run_table
from socialnav.core.scene import Person
from socialnav.crowds.fformations import (
    HEADING_CONVENTIONS,
    facing_offsets,
    front_share,
    heading_step,
    load_fformation_frames,
    load_fformation_settings,
    mutual_neighbours,
)
from socialnav.metrics.groups import PairCounts, group_detection_scores, pairwise_scores
from socialnav.sim.perception import PerceptionNoise
from socialnav.social.perception import ContextEstimator, EstimatorParams, MapKnowledge, gcff_kernel
from socialnav.social.perception.dominant_sets import DominantSetsParams, dominant_sets
from socialnav.social.perception.estimator import estimate_once
from socialnav.social.perception.fformations import FFormationParams, facility_location, gcff
from socialnav.social.perception.tracking import HysteresisParams

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / ".." / "shared" / "data"
OUT = ROOT / "benchmarks" / "out"
LINES: list[str] = []


def emit(line: str = "") -> None:
    print(line)
    LINES.append(line)


# --- 1. F-formations ------------------------------------------------------------------------


def load_fformations(folder: Path) -> list[tuple[np.ndarray, list[list[int]]]]:
    """(rows [id, x_m, y_m, yaw], true groups) per annotated frame, read with
    :func:`socialnav.crowds.fformations.load_fformation_frames` (annotations matched to
    feature frames by timestamp; centimetres converted to metres)."""
    return [
        (np.column_stack([f.ids, f.positions, f.yaws]), f.groups)
        for f in load_fformation_frames(folder)
    ]


def quantisation_allowed(p: FFormationParams, step: float) -> FFormationParams:
    """``p`` with the headings' quantisation step ``step`` (rad) allowed for, a priori: a
    heading known only to the nearest multiple of ``step`` is off by up to ``step / 2``
    (standard deviation ``step / √12``), which moves a vote ``stride`` ahead by
    ``stride · step / √12`` across the gaze, added in quadrature to σ (and to
    ``sigma_along``'s floor); the merge step's facing test is widened by ``step / 2``."""
    jitter = p.stride * step / np.sqrt(12.0)
    sigma = float(np.hypot(p.sigma, jitter))
    return replace(
        p,
        sigma=sigma,
        sigma_along=max(p.sigma_along, sigma),
        merge_facing=p.merge_facing + step / 2,
    )


def data_facts_section(folders: dict[str, Path]) -> dict[str, float]:
    """What the files say, before any detector runs: sizes, the headings' quantisation step,
    the published settings, and which reading of the orientation column makes people face
    their own group (:func:`socialnav.crowds.fformations.facing_offsets`). Returns the
    heading step (rad) of each dataset."""
    emit("\n## F-formation data (the files themselves)\n")
    emit(
        "| data | annotated frames | people per frame | heading step | published stride | "
        "published σ position / heading | facing offset, median (share < 90°) per reading |"
    )
    emit("|---|---|---|---|---|---|---|")
    steps = {}
    for name, folder in folders.items():
        frames = load_fformation_frames(folder)
        settings = load_fformation_settings(folder / "settings.mat")
        steps[name] = heading_step(np.concatenate([f.yaws for f in frames]))
        people = np.mean([f.ids.size for f in frames])
        readings = []
        for reading, convention in HEADING_CONVENTIONS.items():
            off = np.degrees(facing_offsets(frames, convention))
            readings.append(f"{reading}: {np.median(off):.0f}° ({np.mean(off < 90):.0%})")
        emit(
            f"| {name} | {len(frames)} | {people:.1f} | {np.degrees(steps[name]):g}° | "
            f"{settings.stride:g} m | {settings.position_sigma:.2f} m / "
            f"{np.degrees(settings.heading_sigma):.1f}° | {'; '.join(readings)} |"
        )
    return steps


def published_params(p: FFormationParams, folder: Path, with_sigma: bool) -> FFormationParams:
    """``p`` with the dataset's own published stride (``settings.mat`` ``radius``) and, with
    ``with_sigma``, σ = the published position standard deviation (``covmat``), keeping
    ``sigma_along / sigma``."""
    s = load_fformation_settings(folder / "settings.mat")
    if not with_sigma:
        return replace(p, stride=s.stride)
    ratio = p.sigma_along / p.sigma
    return replace(p, stride=s.stride, sigma=s.position_sigma, sigma_along=ratio * s.position_sigma)


def detect_frames(frames, params: FFormationParams) -> list[list[list[int]]]:
    out = []
    for rows, _ in frames:
        ids = rows[:, 0].astype(int)
        out.append([ids[g].tolist() for g in gcff(rows[:, 1:3], rows[:, 3], params)])
    return out


def _published_costs(votes, positions, labels, mdl: float) -> np.ndarray:
    """GCFF's costs as its authors' code computes them (franzsetti/GCFF, ``gc.m``): the squared
    distance (m²) of every vote to each label's mean vote, plus the soft visibility term: for
    two candidates ``j``, ``k`` of a centre (both cheaper than ``mdl``), ``k`` farther from it
    and within ``arccos 0.75`` (41°) of ``j`` seen from it pays ``100^(cos · d_k / d_j)``
    (in cm² there, converted to m² here)."""
    used = np.unique(labels)
    out = np.zeros((len(votes), used.size))
    for col, u in enumerate(used):
        centre = votes[labels == u].mean(axis=0)
        out[:, col] = ((votes - centre) ** 2).sum(axis=1)
        cand = np.flatnonzero(out[:, col] < mdl)
        rel = positions - centre
        dist = np.maximum(np.linalg.norm(rel, axis=1), 1e-12)
        penalty = np.zeros(len(votes))
        for j in cand:
            for k in cand:
                cos = rel[k] @ rel[j] / (dist[k] * dist[j])
                if dist[k] > dist[j] and cos > 0.75:
                    penalty[k] += 1e-4 * 100.0 ** min(cos * dist[k] / dist[j], 10.0)
        out[:, col] += penalty
    return out


def detect_published(frames, stride: float, mdl: float) -> list[list[list[int]]]:
    """GCFF as published: isotropic costs of :func:`_published_costs`, one label per person
    to start, re-solved (our facility-location search in place of α-expansion) with the
    centres re-estimated until the labelling is stable, at most 10 times."""
    out = []
    for rows, _ in frames:
        ids, pos, yaw = rows[:, 0].astype(int), rows[:, 1:3], rows[:, 3]
        votes = pos + stride * np.column_stack([np.cos(yaw), np.sin(yaw)])
        labels = np.arange(len(rows))
        for _ in range(10):
            new = np.unique(
                facility_location(_published_costs(votes, pos, labels, mdl), mdl),
                return_inverse=True,
            )[1]
            if np.array_equal(new, labels):
                break
            labels = new
        out.append(
            [ids[labels == u].tolist() for u in np.unique(labels) if (labels == u).sum() > 1]
        )
    return out


def published_section(frames, bound: bool) -> None:
    """GCFF as its authors' code computes it, its stride and MDL (as the reach √MDL) fitted on
    Synth by the criterion of :func:`fit_on_synth` (and, with ``bound``, chosen on
    CoffeeBreak itself: an upper bound, not a result)."""
    grid = list(itertools.product([0.4, 0.5, 0.6, 0.7], [0.5, 0.6, 0.7, 0.8, 1.0]))

    def scores(name: str, stride: float, reach: float) -> list[float]:
        det, truth = detect_published(frames[name], stride, reach**2), [t for _, t in frames[name]]
        return [group_detection_scores(det, truth, t).f1 for t in (2 / 3, 1.0)]

    chosen = {"fitted on Synth": max(grid, key=lambda g: sum(scores("Synth", *g)))}
    if bound:
        chosen["chosen on CoffeeBreak (bound)"] = max(
            grid, key=lambda g: scores("CoffeeBreak_Seq1", *g)[0]
        )
    emit("\n## GCFF as published (isotropic costs, soft visibility; single frames)\n")
    emit("| stride, reach √MDL | data | F1, T = 2/3 | F1, T = 1 |")
    emit("|---|---|---|---|")
    for how, (stride, reach) in chosen.items():
        for name in ("Synth", "CoffeeBreak_Seq1"):
            f23, f1 = scores(name, stride, reach)
            emit(f"| {how}: {stride:g} m, {reach:g} m | {name} | {f23:.3f} | {f1:.3f} |")


def mean_f1(frames, params: FFormationParams) -> float:
    """The fit criterion: the mean of F1 at T = 2/3 and T = 1."""
    det, truth = detect_frames(frames, params), [t for _, t in frames]
    return sum(group_detection_scores(det, truth, t).f1 for t in (2 / 3, 1.0)) / 2


def fit_on_synth(
    frames, along: tuple[int, ...] = (3, 4), max_tolerance: float = 30.0, label: str = "Synth"
) -> FFormationParams:
    """The grid search that chose the defaults: stride, σ, sigma_along (``along`` × σ), mdl
    with GCFF's exact heading, then ``heading_tolerance`` (2.5° steps up to
    ``max_tolerance`` degrees) with those held (first best on ties)."""
    best: tuple[float, FFormationParams] | None = None
    grid = itertools.product([0.4, 0.5, 0.6, 0.7], [0.1, 0.15, 0.2], along, [8, 16, 25])
    for stride, sigma, ratio, mdl in grid:
        p = FFormationParams(
            stride=stride, sigma=sigma, sigma_along=ratio * sigma, mdl=mdl, heading_tolerance=0.0
        )
        score = mean_f1(frames, p)
        if best is None or score > best[0] + 1e-9:
            best = (score, p)
    assert best is not None
    for degrees in np.arange(2.5, max_tolerance + 1.0, 2.5):
        p = replace(best[1], heading_tolerance=float(np.radians(degrees)))
        score = mean_f1(frames, p)
        if score > best[0] + 1e-9:
            best = (score, p)
    p = best[1]
    emit(
        f"fitted on {label} (mean F1 of T=2/3 and T=1 = {best[0]:.3f}): stride {p.stride:g} m, "
        f"σ {p.sigma:g} m, sigma_along {p.sigma_along:g} m, mdl {p.mdl:g}, "
        f"heading tolerance {np.degrees(p.heading_tolerance):g}°"
    )
    return p


def quantise_headings(frames, step: float):
    """``frames`` with every heading rounded to the nearest multiple of ``step`` (rad)."""
    return [
        (np.column_stack([rows[:, :3], np.round(rows[:, 3] / step) * step]), truth)
        for rows, truth in frames
    ]


def fformation_section(fit: bool, bound: bool = False) -> None:
    sets = {n: DATA / "fformations" / n for n in ("Synth", "CoffeeBreak_Seq1")}
    if not all(p.exists() for p in sets.values()):
        emit("F-formation data not found: skipped")
        return
    emit(
        "\nHow to read these tables: a detected group D matches a true group G when "
        "|G∩D| / max(|G|, |D|) ≥ T (T = 2/3, and T = 1 for exact groups; Cristani et al. 2011); "
        "people alone are left out on both sides; precision and recall are averaged over "
        "frames and F1 is computed from the two means. Every parameter was chosen on Synth "
        "(and the defaults also on development scenes, seeds below 10000): **the CoffeeBreak "
        "rows are held out**, except the upper-bound section, which is chosen on CoffeeBreak "
        "itself and says so."
    )
    steps = data_facts_section(sets)
    frames = {n: load_fformations(p) for n, p in sets.items()}
    # how much 4-direction headings (CoffeeBreak's head-pose classes) alone cost on Synth
    quantised = "Synth, headings quantised to 90°"
    frames[quantised] = quantise_headings(frames["Synth"], np.pi / 2)
    steps[quantised] = np.pi / 2
    folder_of = {**sets, quantised: sets["Synth"]}
    params = fit_on_synth(frames["Synth"]) if fit else FFormationParams()
    # A dataset whose headings are coarser than Synth's own gets parameters fitted on Synth with
    # its headings quantised to that step (the data's documented property, never its labels):
    # with the grid of the defaults, and with an open grid (sigma_along from σ, the heading
    # tolerance up to half the step), since the defaults' sigma_along >= 3σ serves the
    # simulator's accurate headings.
    coarse: dict[float, dict[str, FFormationParams]] = {}
    for name in frames:
        step = steps[name]
        if step > steps["Synth"] + 1e-9 and step not in coarse:
            q = quantise_headings(frames["Synth"], step)
            label = f"Synth quantised to {np.degrees(step):g}°"
            coarse[step] = {
                f"fitted on {label}, grid of the defaults": fit_on_synth(q, label=label),
                f"fitted on {label}, open grid": fit_on_synth(
                    q, (1, 2, 3, 4), max(30.0, np.degrees(step) / 2), label + " (open grid)"
                ),
            }

    def variants(name: str) -> dict[str, FFormationParams]:
        folder, step = folder_of[name], steps[name]
        return {
            "defaults": params,
            "heading tolerance 0 (GCFF's vote)": replace(params, heading_tolerance=0.0),
            "fixed stride (no wide-circle merge)": replace(params, max_stride=0.0),
            "published stride (settings.mat radius)": published_params(params, folder, False),
            "published stride and position σ": published_params(params, folder, True),
            f"heading step {np.degrees(step):g}° allowed for": quantisation_allowed(params, step),
            **coarse.get(step, {}),
        }

    emit("\n## F-formations (GCFF, single frames)\n")
    emit("| data | parameters | frames | T | precision | recall | F1 |")
    emit("|---|---|---|---|---|---|---|")
    for name, fr in frames.items():
        truth = [t for _, t in fr]
        for variant, p in variants(name).items():
            det = detect_frames(fr, p)
            for label, t in (("2/3", 2 / 3), ("1", 1.0)):
                s = group_detection_scores(det, truth, t)
                scores = f"{s.precision:.3f} | {s.recall:.3f} | {s.f1:.3f}"
                emit(f"| {name} | {variant} | {s.frames} | {label} | {scores} |")
    published_section(frames, bound)
    if bound:
        bound_section(frames)
    emit("\n## F-formations over the sequence (the estimator online, defaults)\n")
    emit("| data | Δt | hysteresis | F-formations | T | precision | recall | F1 |")
    emit("|---|---|---|---|---|---|---|---|")
    runs = [(dt, h, "defaults", None) for dt, h in itertools.product((0.1, 1.0), (False, True))]
    runs.append((1.0, False, "fixed stride", {"max_stride": 0.0}))
    for name in ("Synth", quantised, "CoffeeBreak_Seq1"):
        fr, truth = frames[name], [t for _, t in frames[name]]
        # the open-grid parameters of a coarse heading step, online (Δt unknown: both shown)
        extra = [
            (dt, h, variant.replace("fitted on ", ""), asdict(p))
            for variant, p in coarse.get(steps[name], {}).items()
            if "open grid" in variant
            for dt, h in itertools.product((0.1, 1.0), (False, True))
        ]
        for dt, hysteresis, variant, overrides in (runs if name != quantised else []) + extra:
            scene = SYNTH_SCENE if name != "CoffeeBreak_Seq1" else None
            det = detect_sequence(fr, dt, scene, hysteresis, overrides)
            for label, t in (("2/3", 2 / 3), ("1", 1.0)):
                s = group_detection_scores(det, truth, t)
                scores = f"{s.precision:.3f} | {s.recall:.3f} | {s.f1:.3f}"
                on = "on" if hysteresis else "off"
                emit(f"| {name} | {dt:g} s | {on} | {variant} | {label} | {scores} |")
    cb_step = steps["CoffeeBreak_Seq1"]
    open_fit = next((p for v, p in coarse.get(cb_step, {}).items() if "open grid" in v), None)
    gcff_protocol = protocol_fit(frames["Synth"], cb_step)
    spacing_section(frames, open_fit, gcff_protocol)
    dominant_sets_section(frames, gcff_protocol)
    circle_section()
    suite_group_section()


def bound_section(frames) -> None:
    """An upper bound, not a result: the best CoffeeBreak F1 (T = 2/3) of single-frame GCFF
    over a grid of every parameter, chosen on CoffeeBreak itself (which the fit never uses),
    with Synth's score at that point: what no choice of these parameters can beat."""
    grid = itertools.product(
        [0.3, 0.4, 0.5, 0.6, 0.7, 0.8],  # stride
        [0.1, 0.15, 0.2, 0.25, 0.3],  # σ
        [1, 2, 3],  # sigma_along / σ
        [9, 16, 25, 36],  # mdl
        [0.0, 15.0, 30.0, 45.0],  # heading tolerance, degrees
        [0.0, 2.0],  # max_stride (0: no wide-circle merge)
    )
    cb, truth = frames["CoffeeBreak_Seq1"], [t for _, t in frames["CoffeeBreak_Seq1"]]
    best: tuple[float, FFormationParams] | None = None
    n = 0
    for stride, sigma, along, mdl, tol, max_stride in grid:
        p = FFormationParams(
            stride=stride,
            sigma=sigma,
            sigma_along=along * sigma,
            mdl=mdl,
            heading_tolerance=float(np.radians(tol)),
            max_stride=max_stride,
        )
        f1 = group_detection_scores(detect_frames(cb, p), truth).f1
        n += 1
        if best is None or f1 > best[0] + 1e-9:
            best = (f1, p)
    assert best is not None
    p = best[1]
    cb_s = group_detection_scores(detect_frames(cb, p), truth)
    syn, syn_truth = frames["Synth"], [t for _, t in frames["Synth"]]
    syn_f1 = group_detection_scores(detect_frames(syn, p), syn_truth).f1
    emit(f"\n## Upper bound: the best of {n} parameter sets chosen on CoffeeBreak itself\n")
    emit(
        "| stride | σ | sigma_along | mdl | heading tolerance | merge | "
        "CoffeeBreak P / R / F1 | Synth F1 |"
    )
    emit("|---|---|---|---|---|---|---|---|")
    emit(
        f"| {p.stride:g} m | {p.sigma:g} m | {p.sigma_along:g} m | {p.mdl:g} | "
        f"{np.degrees(p.heading_tolerance):g}° | {'on' if p.max_stride > p.stride else 'off'} | "
        f"{cb_s.precision:.3f} / {cb_s.recall:.3f} / {cb_s.f1:.3f} | {syn_f1:.3f} |"
    )


SYNTH_SCENE = 10  # Synth: 10 static scenes of 10 frames each (ids reused across scenes)


def detect_sequence(
    frames, dt: float, scene: int | None, hysteresis: bool, fformation: dict | None = None
) -> list[list[list[int]]]:
    """F-formations of every frame with the estimator run over the frames in order (Δt ``dt``
    s, reset every ``scene`` frames), its pipeline reduced to the F-formation detector as in
    the single-frame rows; the candidates of each frame (``hysteresis=False``) or its active
    structures."""
    hyst = HysteresisParams() if hysteresis else HysteresisParams(0.0, on=0.0, off=0.0)
    params = EstimatorParams(
        pipeline=("fformation",),
        hysteresis=hyst,
        detector_params={"fformation": fformation or {}},
    )
    est = ContextEstimator(params=params)
    out = []
    for i, (rows, _) in enumerate(frames):
        if scene and i % scene == 0:
            est.reset()
        people = [Person(int(r[0]), (r[1], r[2]), yaw=float(r[3])) for r in rows]
        e = est.update(i * dt, people)
        found = e.structures if hysteresis else e.candidates
        out.append([list(s.members) for s in found if s.kind == "fformation"])
    return out


def raw_tracks(frames, dt: float, scene: int | None) -> list[list[Person]]:
    """The people of every frame as a raw tracker reports them at a frame spacing ``dt`` (s):
    the file's positions and headings, velocities the finite differences of an id's
    consecutive positions over ``dt`` (zero on its first frame, after a gap, and at a new
    scene of ``scene`` frames)."""
    out, last = [], {}
    for i, (rows, _) in enumerate(frames):
        if scene and i % scene == 0:
            last = {}
        here = {}
        people = []
        for r in rows:
            pid, xy = int(r[0]), np.array(r[1:3], dtype=float)
            prev = last.get(pid)
            v = (0.0, 0.0) if prev is None else tuple((xy - prev) / dt)
            people.append(Person(pid, (float(xy[0]), float(xy[1])), v, float(r[3])))
            here[pid] = xy
        out.append(people)
        last = here
    return out


def detect_online(
    frames,
    dt: float,
    scene: int | None,
    hysteresis: bool,
    fformation: dict | None,
    velocity_source: str,
    listed_only: bool,
    standing: dict | None = None,
) -> list[list[list[int]]]:
    """F-formations of every frame from :func:`raw_tracks` at spacing ``dt`` through the
    estimator online (pipeline reduced to the F-formation detector, reset every ``scene``
    frames), with ``velocity_source`` (``measured``: the finite differences are taken as the
    tracker's velocities; ``positions``: the estimator's own least-squares test). With
    ``listed_only`` a detected group keeps only the people the frame lists (people coasted
    over a missed detection are dropped before scoring: the annotations cover the listed
    people only, and how many frames a 0.6 s coast spans depends on ``dt``). ``standing``:
    overrides of the standing test's :class:`EstimatorParams` fields."""
    hyst = HysteresisParams() if hysteresis else HysteresisParams(0.0, on=0.0, off=0.0)
    params = EstimatorParams(
        pipeline=("fformation",),
        hysteresis=hyst,
        detector_params={"fformation": fformation or {}},
        velocity_source=velocity_source,  # type: ignore[arg-type]
        **(standing or {}),
    )
    est = ContextEstimator(params=params)
    out = []
    for i, people in enumerate(raw_tracks(frames, dt, scene)):
        if scene and i % scene == 0:
            est.reset()
        e = est.update(i * dt, people)
        listed = {p.id for p in people}
        found = e.structures if hysteresis else e.candidates
        groups = [
            [m for m in s.members if not listed_only or m in listed]
            for s in found
            if s.kind == "fformation"
        ]
        out.append([g for g in groups if len(g) > 1])
    return out


SPACINGS = (0.1, 0.4, 1.0, 2.0)  # s: the files do not say; the result must not depend on it


def spacing_section(
    frames, coarse_params: FFormationParams | None, protocol: FFormationParams | None = None
) -> None:
    """The sequence protocol, fixed before CoffeeBreak was run with it: raw tracks
    (:func:`raw_tracks`) at every spacing of :data:`SPACINGS`; the estimator online with its
    standing test from the position history (``velocity_source="positions"``, its a-priori
    defaults: 1 s window, at least 3 samples, 0.05 m jitter floor, z = 2); F-formation
    parameters the defaults, or, for CoffeeBreak's 90° headings, the open-grid set fitted once
    on Synth with its headings quantised to the detected step (single frames, mean F1 of
    T = 2/3 and T = 1); scored on the people each frame lists (and, for comparison, with
    coasted people kept). The ``measured`` rows take the finite differences as velocities:
    what the standing test did before."""
    emit(
        "\n## F-formations over the sequence at any frame spacing (raw tracks: velocities "
        "are finite differences)\n"
    )
    emit(
        "The files number their frames and do not give the time between them, so the table "
        "covers Δt = " + ", ".join(f"{d:g}" for d in SPACINGS) + " s. T = 2/3 unless said; "
        "'listed' scores the people the frame lists, 'all' keeps people coasted over a missed "
        "detection (0.6 s: only Δt ≤ 0.6 s coasts)."
    )
    emit("")
    head = " | ".join(f"Δt {d:g} s" for d in SPACINGS)
    emit(f"| data | F-formation parameters | standing test | hysteresis | scored | {head} |")
    emit("|---|---|---|---|---|" + "---|" * len(SPACINGS))
    rows: list[tuple[str, str, dict | None]] = [("Synth", "defaults", None)]
    if protocol is not None:
        for name in ("Synth", "CoffeeBreak_Seq1"):
            rows.append((name, "**protocol fit** (Synth quantised to 90°)", asdict(protocol)))
    if coarse_params is not None:
        rows.append(("Synth", "fitted on Synth quantised to 90°", asdict(coarse_params)))
        rows.append(("CoffeeBreak_Seq1", "fitted on Synth quantised to 90°", asdict(coarse_params)))
    rows.append(("CoffeeBreak_Seq1", "defaults", None))
    for name, variant, overrides in rows:
        fr, truth = frames[name], [t for _, t in frames[name]]
        scene = SYNTH_SCENE if name == "Synth" else None
        for source, hysteresis, listed in (
            ("measured", False, True),
            ("positions", False, True),
            ("positions", True, True),
            ("positions", False, False),
        ):
            cells = []
            for dt in SPACINGS:
                det = detect_online(fr, dt, scene, hysteresis, overrides, source, listed)
                s = group_detection_scores(det, truth, 2 / 3)
                cells.append(f"{s.precision:.3f} / {s.recall:.3f} / **{s.f1:.3f}**")
            test = "finite differences (before)" if source == "measured" else "least squares"
            emit(
                f"| {name} | {variant} | {test} | {'on' if hysteresis else 'off'} | "
                f"{'listed' if listed else 'all'} | {' | '.join(cells)} |"
            )
    emit("\nCells: precision / recall / **F1** at T = 2/3.")
    if protocol is not None:
        cb, truth = frames["CoffeeBreak_Seq1"], [t for _, t in frames["CoffeeBreak_Seq1"]]
        s = group_detection_scores(detect_frames(cb, protocol), truth, 2 / 3)
        emit(
            f"\nThe protocol fit on CoffeeBreak's single frames: {s.precision:.3f} / "
            f"{s.recall:.3f} / **{s.f1:.3f}**."
        )
        sensitivity_section(frames["CoffeeBreak_Seq1"], asdict(protocol), "protocol fit")
    if coarse_params is not None:
        sensitivity_section(frames["CoffeeBreak_Seq1"], asdict(coarse_params), "open-grid fit")


#: The standing test's a-priori values and the alternatives of the sensitivity table.
STANDING_ALTERNATIVES = {
    "velocity_window": (0.5, 2.0),
    "leave_distance": (0.0, 0.3, 0.7),
    "motion_z": (1.0, 3.0),
    "position_jitter": (0.02, 0.1),
}


def sensitivity_section(frames, overrides: dict, label: str) -> None:
    """How much the CoffeeBreak sequence result (hysteresis off, people listed) owes to the
    standing test's a-priori values: each changed alone, F1 at T = 2/3 per spacing and the
    worst. Reported, not used to choose (the values were fixed before, see
    :class:`EstimatorParams`)."""
    truth = [t for _, t in frames]
    emit(
        f"\n## Sensitivity of the CoffeeBreak sequence F1 to the standing test ({label}; "
        "reported, not a fit)\n"
    )
    head = " | ".join(f"Δt {d:g} s" for d in SPACINGS)
    emit(f"| standing test | {head} | worst |")
    emit("|---|" + "---|" * len(SPACINGS) + "---|")
    cases: list[tuple[str, dict]] = [("a-priori values (1 s, 0.5 m, z 2, 0.05 m)", {})]
    cases += [(f"{k} = {v:g}", {k: v}) for k, vs in STANDING_ALTERNATIVES.items() for v in vs]
    for case, standing in cases:
        f1 = [
            group_detection_scores(
                detect_online(frames, dt, None, False, overrides, "positions", True, standing),
                truth,
                2 / 3,
            ).f1
            for dt in SPACINGS
        ]
        emit(f"| {case} | " + " | ".join(f"{x:.3f}" for x in f1) + f" | {min(f1):.3f} |")


def protocol_grid(step: float) -> list[FFormationParams]:
    """The fit protocol's grid, fixed before its result on CoffeeBreak was seen: every
    combination of stride D 0.3–0.8 m (0.1 m steps: Kendon's o-space, a person's distance
    to the centre of the conversation they face, for pairs to circles of about 1.5 m), σ
    0.10–0.25 m, ``sigma_along`` 1–4 σ, mdl 9, 16, 25, 36 (a joining vote within 3–6 σ) and
    a heading tolerance of 0, ``step / 4`` and ``step / 2`` (a heading known to the nearest
    multiple of ``step`` is off by at most half of it). Other parameters are the defaults."""
    return [
        FFormationParams(
            stride=stride,
            sigma=sigma,
            sigma_along=ratio * sigma,
            mdl=mdl,
            heading_tolerance=float(tolerance * step),
        )
        for stride, sigma, ratio, mdl, tolerance in itertools.product(
            (0.3, 0.4, 0.5, 0.6, 0.7, 0.8),
            (0.1, 0.15, 0.2, 0.25),
            (1, 2, 3, 4),
            (9, 16, 25, 36),
            (0.0, 0.25, 0.5),
        )
    ]


def protocol_fit(synth, step: float) -> FFormationParams:
    """The fit protocol: Synth's headings quantised to ``step`` (rad: the step
    :func:`~socialnav.crowds.fformations.heading_step` detects in the held-out file's
    headings, a property of its features, never its labels), single frames, objective the
    mean of F1 at T = 2/3 and T = 1 (:func:`mean_f1`), the best of :func:`protocol_grid`
    (the first in grid order on ties). Run once; the held-out data are then scored once."""
    q = quantise_headings(synth, step)
    grid = protocol_grid(step)
    scores = [mean_f1(q, p) for p in grid]
    best = int(np.argmax(scores))
    p = grid[best]
    emit(
        f"protocol fit on Synth quantised to {np.degrees(step):g}° ({len(grid)} sets, mean F1 "
        f"of T=2/3 and T=1 = {scores[best]:.3f}): stride {p.stride:g} m, σ {p.sigma:g} m, "
        f"sigma_along {p.sigma_along:g} m, mdl {p.mdl:g}, heading tolerance "
        f"{np.degrees(p.heading_tolerance):g}°"
    )
    return p


def spacing_only() -> None:
    """``--only spacing``: the fit of the protocol (once, on Synth quantised to CoffeeBreak's
    detected heading step) and :func:`spacing_section`, without the other F-formation rows."""
    sets = {n: DATA / "fformations" / n for n in ("Synth", "CoffeeBreak_Seq1")}
    if not all(p.exists() for p in sets.values()):
        emit("F-formation data not found: skipped")
        return
    frames = {n: load_fformations(p) for n, p in sets.items()}
    step = heading_step(np.concatenate([rows[:, 3] for rows, _ in frames["CoffeeBreak_Seq1"]]))
    label = f"Synth quantised to {np.degrees(step):g}°"
    q = quantise_headings(frames["Synth"], step)
    fitted = fit_on_synth(q, (1, 2, 3, 4), max(30.0, np.degrees(step) / 2), label + " (open grid)")
    spacing_section(frames, fitted, protocol_fit(frames["Synth"], step))


# --- 1b. F-formations as dominant sets ---------------------------------------------------------


def dominant_sets_grid() -> list[DominantSetsParams]:
    """The dominant-sets fit protocol's grid, fixed and committed before its CoffeeBreak result
    was run: proximity scale σ_d 0.4–1.2 m (conversational distances, Hall's personal to
    social zone), heading reliability ρ 0–1 in quarters, stride D 0.4, 0.6, 0.8 m and vote
    scale σ_o 0.3, 0.6 m (ignored, so taken once, at ρ = 0), minimum cohesion 0.1–0.7. Other
    parameters are the a-priori defaults of :class:`DominantSetsParams`."""
    out = []
    for sd, rho, stride, sv, c in itertools.product(
        (0.4, 0.6, 0.8, 1.0, 1.2),
        (0.0, 0.25, 0.5, 0.75, 1.0),
        (0.4, 0.6, 0.8),
        (0.3, 0.6),
        (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7),
    ):
        if rho == 0.0 and (stride, sv) != (0.4, 0.3):
            continue  # the heading term is off: stride and σ_o do not matter
        p = DominantSetsParams(
            sigma_distance=sd, reliability=rho, stride=stride, sigma_vote=sv, min_cohesion=c
        )
        out.append(p)
    return out


def detect_frames_ds(frames, params: DominantSetsParams) -> list[list[list[int]]]:
    """Dominant sets of every frame alone (:func:`dominant_sets`)."""
    out = []
    for rows, _ in frames:
        ids = rows[:, 0].astype(int)
        found = dominant_sets(rows[:, 1:3], rows[:, 3], params)
        out.append([ids[g].tolist() for g, _ in found])
    return out


def ds_mean_f1(frames, params: DominantSetsParams) -> float:
    """The objective: the mean of F1 at T = 2/3 and T = 1, single frames."""
    det, truth = detect_frames_ds(frames, params), [t for _, t in frames]
    return sum(group_detection_scores(det, truth, t).f1 for t in (2 / 3, 1.0)) / 2


def dominant_sets_fit(synth, step: float) -> tuple[DominantSetsParams, float]:
    """The dominant-sets protocol: Synth's headings quantised to ``step`` (rad, detected in the
    held-out file's features, never its labels), single frames, objective :func:`ds_mean_f1`,
    the best of :func:`dominant_sets_grid` (first in grid order on ties). Returns the set and
    its objective."""
    q = quantise_headings(synth, step)
    grid = dominant_sets_grid()
    scores = [ds_mean_f1(q, p) for p in grid]
    best = int(np.argmax(scores))
    return grid[best], scores[best]


def dominant_sets_section(frames, gcff_protocol: FFormationParams | None = None) -> None:
    """F-formations as dominant sets (:mod:`socialnav.social.perception.dominant_sets`):
    the protocol fit (:func:`dominant_sets_fit`, on Synth quantised to CoffeeBreak's detected
    heading step) scored on Synth, Synth quantised, and CoffeeBreak (held out, run once with
    the fitted set), single frames; with ``gcff_protocol`` (GCFF's :func:`protocol_fit`, the
    same protocol) GCFF's rows beside them."""
    cb = frames["CoffeeBreak_Seq1"]
    step = heading_step(np.concatenate([rows[:, 3] for rows, _ in cb]))
    p, objective = dominant_sets_fit(frames["Synth"], step)
    emit(
        f"\n## F-formations as dominant sets (Hung & Kröse 2011; single frames)\n\n"
        f"Protocol fit on Synth quantised to {np.degrees(step):g}° ({len(dominant_sets_grid())} "
        f"sets, mean F1 of T=2/3 and T=1 = {objective:.3f}): σ_d {p.sigma_distance:g} m, "
        f"ρ {p.reliability:g}, stride {p.stride:g} m, σ_o {p.sigma_vote:g} m, min cohesion "
        f"{p.min_cohesion:g}.\n"
    )
    emit("| data | parameters | frames | T | precision | recall | F1 |")
    emit("|---|---|---|---|---|---|---|")
    data = {
        "Synth": frames["Synth"],
        f"Synth, headings quantised to {np.degrees(step):g}°": quantise_headings(
            frames["Synth"], step
        ),
        "CoffeeBreak_Seq1 (held out)": cb,
    }
    for name, fr in data.items():
        truth = [t for _, t in fr]
        runs = [("dominant sets, protocol fit", detect_frames_ds(fr, p))]
        if gcff_protocol is not None:
            runs.append(("GCFF, its protocol fit", detect_frames(fr, gcff_protocol)))
        for variant, det in runs:
            for label, t in (("2/3", 2 / 3), ("1", 1.0)):
                s = group_detection_scores(det, truth, t)
                scores = f"{s.precision:.3f} | {s.recall:.3f} | {s.f1:.3f}"
                emit(f"| {name} | {variant} | {s.frames} | {label} | {scores} |")


def dominant_sets_only() -> None:
    """``--only dominant_sets``: :func:`dominant_sets_section` alone."""
    sets = {n: DATA / "fformations" / n for n in ("Synth", "CoffeeBreak_Seq1")}
    if not all(p.exists() for p in sets.values()):
        emit("F-formation data not found: skipped")
        return
    dominant_sets_section({n: load_fformations(p) for n, p in sets.items()})


# --- 1c. Dominant sets calibrated to the heading source ---------------------------------------

#: Shares of wrong headings tried when matching a source's :func:`front_share` (0–95 %).
ERROR_SHARES = tuple(round(0.05 * k, 2) for k in range(20))
#: Corruption draws per share when matching the statistic, and draws the fit averages over.
MATCH_SEEDS = range(5)
FIT_SEEDS = range(3)


def corrupt_headings(frames, share: float, seed: int, step: float):
    """``frames`` with a ``share`` of the headings (drawn with ``seed``) replaced by uniformly
    random directions, an outlier model of a head-pose classifier's confusions, then every
    heading quantised to ``step`` (rad; 0 keeps them continuous)."""
    rng = np.random.default_rng(seed)
    out = []
    for rows, truth in frames:
        r = rows.copy()
        wrong = rng.random(len(r)) < share
        r[wrong, 3] = rng.uniform(0.0, 2 * np.pi, int(wrong.sum()))
        if step > 0:
            r[:, 3] = np.round(r[:, 3] / step) * step
        out.append((r, truth))
    return out


def _front(frames) -> float:
    return front_share((rows[:, 1:3], rows[:, 3]) for rows, _ in frames)[0]


def heading_error_share(target, synth, step: float) -> tuple[float, float, list[float]]:
    """The share of wrong headings of ``target``'s source, from its features alone (never its
    labels): the share of :data:`ERROR_SHARES` whose corrupted Synth
    (:func:`corrupt_headings`, quantised to ``step``, mean over :data:`MATCH_SEEDS`) has the
    :func:`front_share` nearest the target's (first on ties). Returns (share, the target's
    statistic, the curve over :data:`ERROR_SHARES`)."""
    f_target = _front(target)
    curve = [
        float(np.mean([_front(corrupt_headings(synth, e, s, step)) for s in MATCH_SEEDS]))
        for e in ERROR_SHARES
    ]
    best = int(np.argmin([abs(f - f_target) for f in curve]))
    return ERROR_SHARES[best], f_target, curve


def calibrated_fit(synth, step: float, share: float) -> tuple[DominantSetsParams, float]:
    """The best of :func:`dominant_sets_grid` on Synth with a ``share`` of its headings wrong
    and all quantised to ``step`` (:func:`corrupt_headings`), objective :func:`ds_mean_f1`
    averaged over :data:`FIT_SEEDS` (first in grid order on ties)."""
    data = [corrupt_headings(synth, share, s, step) for s in FIT_SEEDS]
    grid = dominant_sets_grid()
    scores = [float(np.mean([ds_mean_f1(d, p) for d in data])) for p in grid]
    best = int(np.argmax(scores))
    return grid[best], scores[best]


def calibrated_section(frames) -> DominantSetsParams:
    """Dominant sets calibrated to the heading source. The protocol, fixed and committed before
    its CoffeeBreak result was run: (a) the heading step detected in the held-out features
    (:func:`heading_step`); (b) the share of wrong headings estimated from the held-out
    features alone (:func:`heading_error_share`); (c) the dominant-sets grid fitted on Synth
    corrupted to that share and step (:func:`calibrated_fit`); (d) CoffeeBreak scored once,
    single frames. Synth run as the target shows what (b) finds for clean headings."""
    synth, cb = frames["Synth"], frames["CoffeeBreak_Seq1"]
    emit("\n## Dominant sets calibrated to the heading source (single frames)\n")
    emit("| target | heading step | front share (target) | wrong headings estimated |")
    emit("|---|---|---|---|")
    found = {}
    for name, target in (("Synth", synth), ("CoffeeBreak_Seq1", cb)):
        step = heading_step(np.concatenate([rows[:, 3] for rows, _ in target]))
        share, f_target, curve = heading_error_share(target, synth, step)
        found[name] = (step, share)
        emit(f"| {name} | {np.degrees(step):g}° | {f_target:.3f} | {share:.0%} |")
        emit(
            "\nfront share of corrupted Synth at "
            + ", ".join(f"{e:.0%}: {f:.3f}" for e, f in zip(ERROR_SHARES, curve, strict=True))
            + "\n"
        )
    step, share = found["CoffeeBreak_Seq1"]
    p, objective = calibrated_fit(synth, step, share)
    emit(
        f"Fit on Synth with {share:.0%} wrong headings, quantised to {np.degrees(step):g}° "
        f"({len(dominant_sets_grid())} sets × {len(FIT_SEEDS)} draws, mean F1 of T=2/3 and "
        f"T=1 = {objective:.3f}): σ_d {p.sigma_distance:g} m, ρ {p.reliability:g}, stride "
        f"{p.stride:g} m, σ_o {p.sigma_vote:g} m, min cohesion {p.min_cohesion:g}.\n"
    )
    emit("| data | frames | T | precision | recall | F1 |")
    emit("|---|---|---|---|---|---|")
    for name, fr in (("Synth", synth), ("CoffeeBreak_Seq1 (held out)", cb)):
        det, truth = detect_frames_ds(fr, p), [t for _, t in fr]
        for label, t in (("2/3", 2 / 3), ("1", 1.0)):
            s = group_detection_scores(det, truth, t)
            emit(
                f"| {name} | {s.frames} | {label} | {s.precision:.3f} | {s.recall:.3f} "
                f"| {s.f1:.3f} |"
            )
    return p


def mutual_neighbour_spacing(frames) -> float:
    """Median distance (m) between mutual nearest neighbours over ``frames``: a label-free
    measure of how far apart a scene's people stand."""
    return float(np.median(np.concatenate([mutual_neighbours(r[:, 1:3])[2] for r, _ in frames])))


def scaled_section(frames, calibrated: DominantSetsParams) -> None:
    """Post hoc, designed after :func:`calibrated_section`'s CoffeeBreak result was seen, so
    not a held-out result: the dominant-sets fits with their lengths (σ_d, stride, σ_o)
    scaled by the ratio of CoffeeBreak's to Synth's :func:`mutual_neighbour_spacing`."""
    synth, cb = frames["Synth"], frames["CoffeeBreak_Seq1"]
    ratio = mutual_neighbour_spacing(cb) / mutual_neighbour_spacing(synth)
    emit(
        f"\nPost hoc (designed after the row above was seen; not held out): lengths scaled by "
        f"the ratio of mutual-nearest-neighbour spacings, CoffeeBreak / Synth = {ratio:.3f}.\n"
    )
    emit("| fit | lengths | T = 2/3 precision | recall | F1 | T = 1 F1 |")
    emit("|---|---|---|---|---|---|")
    truth = [t for _, t in cb]
    fits = {"quantised Synth (the defaults)": DominantSetsParams(), "calibrated": calibrated}
    for name, p in fits.items():
        scaled = replace(
            p,
            sigma_distance=p.sigma_distance * ratio,
            stride=p.stride * ratio,
            sigma_vote=p.sigma_vote * ratio,
        )
        for lengths, q in (("as fitted", p), ("scaled", scaled)):
            det = detect_frames_ds(cb, q)
            s, s1 = (group_detection_scores(det, truth, t) for t in (2 / 3, 1.0))
            emit(
                f"| {name} | {lengths} | {s.precision:.3f} | {s.recall:.3f} | {s.f1:.3f} "
                f"| {s1.f1:.3f} |"
            )


def calibrated_only() -> None:
    """``--only calibrated``: :func:`calibrated_section` alone."""
    sets = {n: DATA / "fformations" / n for n in ("Synth", "CoffeeBreak_Seq1")}
    if not all(f.is_dir() for f in sets.values()):
        emit("F-formation data not found; section skipped")
        return
    frames = {n: load_fformations(f) for n, f in sets.items()}
    scaled_section(frames, calibrated_section(frames))


def jittered_circles(seed: int = 0) -> list[tuple[int, float, np.ndarray, np.ndarray]]:
    """(members, radius, positions (K, 2), yaws (K,)) of 105 circles facing their centres."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(2, 7):
        for r in np.linspace(0.6, 1.5, 7):
            for _ in range(3):
                a = 2 * np.pi * np.arange(k) / k + rng.uniform(-np.pi, np.pi)
                a = a + rng.normal(0, 0.15, k)
                pos = r * np.column_stack([np.cos(a), np.sin(a)]) + rng.normal(0, 0.05, (k, 2))
                out.append((k, float(r), pos, a + np.pi + rng.normal(0, np.radians(10), k)))
    return out


def circle_section() -> None:
    circles = jittered_circles()
    variants = {
        "GCFF's fixed stride (max_stride = stride)": FFormationParams(max_stride=0.0),
        "defaults (wide-circle merge, facing 20°)": FFormationParams(),
        "merge, facing 25°": FFormationParams(merge_facing=float(np.radians(25.0))),
    }
    emit("\n## Wide circles (105 jittered circles, found whole)\n")
    emit("| parameters | all 105 | 5–6 members, radius > 1.2 m | 2 members | 3 members |")
    emit("|---|---|---|---|---|")
    for name, p in variants.items():
        whole = [[g.size for g in gcff(pos, yaw, p)] == [k] for k, _, pos, yaw in circles]

        def rate(sel, whole=whole) -> str:
            idx = [i for i, c in enumerate(circles) if sel(c[0], c[1])]
            return f"{sum(whole[i] for i in idx)}/{len(idx)}"

        emit(
            f"| {name} | {rate(lambda k, r: True)} | {rate(lambda k, r: k >= 5 and r > 1.2)} | "
            f"{rate(lambda k, r: k == 2)} | {rate(lambda k, r: k == 3)} |"
        )


def suite_group_section(seeds: range = range(60)) -> None:
    """The generated suite's own standing groups (families group_join, group_lead, mixed;
    development seeds): the standing people observed through the simulator's default
    perception model for 3 s at 10 Hz, the estimator online; a group counts when it is one
    detected group with exactly its members at the end."""
    from socialnav.sim.generate.common import generate
    from socialnav.sim.perception import PerceptionModel
    from socialnav.sim.scenario import Stand

    emit(
        f"\n## Generated group scenes (development seeds {seeds.start}–{seeds.stop - 1}, "
        "found whole; the wide-circle merge was checked on these, so they are not held out)\n"
    )
    emit("| family | fixed stride | wide-circle merge (defaults) | 5+ members, radius > 1.2 m |")
    emit("|---|---|---|---|")
    for family in ("group_join", "group_lead", "mixed"):
        counts = {}
        for max_stride in (0.0, FFormationParams().max_stride):
            ok = n = wide_ok = wide_n = 0
            for seed in seeds:
                scn = generate(family, seed)
                stand = [p for p in scn.people if isinstance(p.behavior, Stand)]
                ids = np.array([p.id for p in stand])
                pos = np.array([p.position for p in stand], dtype=float).reshape(-1, 2)
                yaw = np.array([p.yaw or 0.0 for p in stand])
                model = PerceptionModel(bounds=(0.0, 0.0, 14.0, 14.0), seed=seed)
                overrides = {"fformation": {"max_stride": max_stride}}
                est = ContextEstimator(params=EstimatorParams(detector_params=overrides))
                for i in range(30):
                    out = est.update(0.1 * i, model.observe(ids, pos, np.zeros_like(pos), yaw))
                found = [set(g.member_ids) for g in out.context.groups if g.mode != "walking"]
                for g in scn.groups:
                    if g.mode == "walking":
                        continue
                    hit = set(g.members) in found
                    xy = pos[np.isin(ids, g.members)]
                    wide = len(g.members) >= 5 and np.hypot(*(xy - xy.mean(0)).T).mean() > 1.2
                    ok, n = ok + hit, n + 1
                    wide_ok, wide_n = wide_ok + (hit and wide), wide_n + wide
            counts[max_stride] = (ok, n, wide_ok, wide_n)
        (a, n, wa, wn), (b, _, wb, _) = counts.values()
        emit(f"| {family} | {a}/{n} | {b}/{n} | {wa}/{wn} → {wb}/{wn} |")


# --- 2. queues ------------------------------------------------------------------------------


def generated_queue(rng: np.random.Generator, desk: bool):
    k = int(rng.integers(2, 9))
    spacing = rng.uniform(0.6, 1.1)
    direction = rng.uniform(-np.pi, np.pi)
    d = np.array([np.cos(direction), np.sin(direction)])
    n = np.array([-d[1], d[0]])
    bend = rng.uniform(-0.4, 0.4)
    head = rng.uniform(-5, 5, size=2)
    s = np.arange(k) * spacing
    lateral = bend * (s / max(s[-1], 1e-9)) ** 2  # a smooth bend, up to 0.4 m at the tail
    true_pos = head + s[:, None] * d + lateral[:, None] * n
    # each person faces the one ahead (the head faces the desk)
    ahead = np.vstack([head - 0.7 * d, true_pos[:-1]])
    yaw = np.arctan2(*(ahead - true_pos).T[::-1])
    pos = true_pos + rng.normal(0, 0.1, size=true_pos.shape)
    yaw = yaw + rng.normal(0, np.radians(15), size=k)
    ids = rng.permutation(100)[:k]
    people = [Person(int(i), tuple(p), yaw=float(y)) for i, p, y in zip(ids, pos, yaw, strict=True)]
    rng.shuffle(people)
    knowledge = MapKnowledge(service_points=(head - 0.7 * d)[None] if desk else np.zeros((0, 2)))
    return people, tuple(int(i) for i in ids), knowledge


def queue_section(scenes: int = 200) -> None:
    emit("\n## Queues (generated, σ 0.1 m, 15°)\n")
    emit("| desk | scenes | membership correct | membership and order correct |")
    emit("|---|---|---|---|")
    for desk in (True, False):
        # the queue parameters were tuned on seeds 14 and 15; these seeds are held out
        rng = np.random.default_rng(1014 if desk else 1015)
        member_ok = order_ok = 0
        for _ in range(scenes):
            people, truth, knowledge = generated_queue(rng, desk)
            queues = estimate_once(people, knowledge).context.queues
            if len(queues) == 1 and set(queues[0].member_ids) == set(truth):
                member_ok += 1
                order_ok += queues[0].member_ids == truth
        emit(
            f"| {'yes' if desk else 'no'} | {scenes} | {member_ok / scenes:.1%} | "
            f"{order_ok / scenes:.1%} |"
        )


# --- 3. walking groups ----------------------------------------------------------------------


def walking_section(params: EstimatorParams | None = None) -> None:
    emit("\n## Walking groups (pairwise, per frame)\n")
    emit("| recording | frames | true pairs | precision | recall |")
    emit("|---|---|---|---|---|")
    for name in ("eth_hotel", "ucy_zara01"):
        obs, grp = DATA / "crowds" / f"{name}_obsmat.txt", DATA / "crowds" / f"{name}_groups.txt"
        if not obs.exists() or not grp.exists():
            emit(f"| {name} | data not found | | | |")
            continue
        from socialnav.crowds import load_obsmat

        recording = load_obsmat(obs, groups=grp)
        truth = [list(g) for g in recording.groups]
        est = ContextEstimator(params=params or EstimatorParams())
        # the annotated instants: every sample time of every track (0.4 s apart)
        samples: dict[float, list[Person]] = {}
        for track in recording.tracks:
            for t, x, v, h in zip(
                track.times, track.positions, track.velocities, track.headings, strict=True
            ):
                person = Person(int(track.id), (x[0], x[1]), (v[0], v[1]), float(h))
                samples.setdefault(round(float(t), 6), []).append(person)
        frames = np.array(sorted(samples))
        total = PairCounts()
        for t in frames:
            people = samples[float(t)]
            out = est.update(float(t), people)
            detected = [s.members for s in out.structures if s.kind == "walking_group"]
            total = total + pairwise_scores(detected, truth, [p.id for p in people])
        emit(
            f"| {name} | {frames.size} | {total.tp + total.fn} | {total.precision:.3f} | "
            f"{total.recall:.3f} |"
        )


# --- 4. time --------------------------------------------------------------------------------


def crowd(n: int, seed: int = 0) -> tuple[list[Person], MapKnowledge]:
    rng = np.random.default_rng(seed)
    people: list[Person] = []
    pid = 0
    while len(people) < n:
        c = rng.uniform(-10, 10, size=2)
        kind = len(people) % 3
        if kind == 0:  # a conversation of 3
            for a in np.linspace(0, 2 * np.pi, 4)[:3]:
                p = c + 0.7 * np.array([np.cos(a), np.sin(a)])
                people.append(Person(pid, tuple(p), yaw=float(a + np.pi)))
                pid += 1
        elif kind == 1:  # two walkers
            v = rng.normal(0, 1, 2)
            v = 1.2 * v / np.linalg.norm(v)
            for off in (0.0, 0.7):
                people.append(Person(pid, tuple(c + off), tuple(v), float(np.arctan2(v[1], v[0]))))
                pid += 1
        else:  # a queue of 3
            for k in range(3):
                people.append(Person(pid, (c[0] + 0.8 * k, c[1]), yaw=float(np.pi)))
                pid += 1
    return people[:n], MapKnowledge(service_points=np.array([[0.0, 0.0]]))


def noisy(people: list[Person], rng: np.random.Generator) -> list[Person]:
    """The default perception noise of the simulator (σ 0.05 m, 10°, 0.05 m/s) on one cycle."""
    n = PerceptionNoise()
    return [
        Person(
            p.id,
            tuple(np.asarray(p.position) + rng.normal(0, n.position_sigma, 2)),
            tuple(np.asarray(p.velocity) + rng.normal(0, n.velocity_sigma, 2)),
            float(p.yaw + rng.normal(0, n.heading_sigma)),
        )
        for p in people
    ]


def timing_section() -> None:
    """Cycles of one estimator at 10 Hz over a static crowd, its tracks exact or with the
    default perception noise; each timed call is one ``update`` after 20 warm-up cycles (the
    tracker's running means settle): the NumPy reference or the compiled GCFF solve
    (:mod:`socialnav.social.perception.gcff_kernel`), every component solved every cycle or
    incrementally (:class:`~socialnav.social.perception.fformations.FFormationDetector`)."""
    cases = []
    off = {"fformation": {"reuse_distance": 0.0}}
    only = EstimatorParams(pipeline=("fformation",), detector_params=off)
    full_off = EstimatorParams(detector_params=off)
    for n in (10, 50):
        people, knowledge = crowd(n)
        for tracks in ("exact", "noisy"):
            group = f"{n} people, {tracks} tracks"
            variants = (
                ("fformation only, reference, every cycle", only, False),
                ("full, reference, every cycle", full_off, False),
                ("full, compiled, every cycle", full_off, True),
                ("full, compiled, incremental (default)", EstimatorParams(), True),
            )
            for name, params, compiled in variants:
                est = ContextEstimator(knowledge, params)
                rng = np.random.default_rng(7)
                # the observations of every cycle, drawn before timing
                frames = [noisy(people, rng) if tracks == "noisy" else people for _ in range(61)]
                clock = itertools.count()

                def step(e=est, fr=frames, c=clock, jit=compiled) -> None:
                    previous = gcff_kernel.set_enabled(jit)
                    i = next(c)
                    e.update(0.1 * i, fr[i % len(fr)])
                    gcff_kernel.set_enabled(previous)

                base = "full, reference, every cycle"
                cases.append(Case(group, name, step, 41, 20, baseline=base))
    rows = run_table(cases, f"Time per estimate ({machine_note()})")
    emit("\n## Time per estimate (median of 41 cycles after 20 warm-up cycles)\n")
    emit("| crowd | tracks | variant | median | speed-up vs full, reference, every cycle |")
    emit("|---|---|---|---|---|")
    for r in rows:
        crowd_, tracks = r.group.split(", ")
        ratio = f"{r.ratio:.1f}×" if r.ratio else ""
        emit(f"| {crowd_} | {tracks} | {r.variant} | {r.median_s * 1e3:.2f} ms | {ratio} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fit", action="store_true", help="refit the GCFF grid on Synth")
    parser.add_argument(
        "--bound",
        action="store_true",
        help="also the upper bound of a parameter grid tuned on CoffeeBreak (minutes)",
    )
    parser.add_argument(
        "--queue-scenes", type=int, default=200, help="generated queue scenes per desk variant"
    )
    parser.add_argument(
        "--only",
        choices=(
            "fformations",
            "spacing",
            "dominant_sets",
            "calibrated",
            "queues",
            "walking",
            "time",
        ),
        help="one section (details in the module docstring): fformations = F-formation "
        "precision, recall and F1 at match threshold T on Synth and CoffeeBreak; spacing = the "
        "same data as raw tracks at several frame spacings; dominant_sets = the second "
        "detector's fit protocol; calibrated = dominant sets calibrated to the heading source "
        "(minutes); queues = generated queues; walking = walking groups on ETH/UCY; time = "
        "time per estimate",
    )
    args = parser.parse_args()
    if args.only in (None, "fformations"):
        fformation_section(args.fit, args.bound)
    if args.only == "spacing":
        spacing_only()
    if args.only == "dominant_sets":
        dominant_sets_only()
    if args.only == "calibrated":
        calibrated_only()
    if args.only in (None, "queues"):
        queue_section(args.queue_scenes)
    if args.only in (None, "walking"):
        walking_section()
    if args.only in (None, "time"):
        timing_section()
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "context.md").write_text("\n".join(LINES) + "\n")


if __name__ == "__main__":
    main()

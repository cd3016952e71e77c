"""Drawing primitives shared by the top-down plots and the animation (private).

Every function draws onto a given matplotlib ``Axes`` and returns the artists it made, so the
animation can update them. Coordinates are world metres; yaw CCW from +x.
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from types import ModuleType
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection, PatchCollection, PolyCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import FloatArray
from socialnav.viz.style import COLORS

#: Hall's personal-space radius (centre to centre, m) drawn around people.
PERSONAL_SPACE = 1.2
#: A person slower than this on average (m/s) is drawn as standing (facing arrow from the context).
STANDING_SPEED = 0.05


# ----------------------------------------------------------------------------- validation
def check_record(record: EpisodeRecord) -> None:
    """Raise ``ValueError`` for a record that cannot be drawn (empty or non-finite robot)."""
    if not isinstance(record, EpisodeRecord):
        raise ValueError(f"expected an EpisodeRecord, got {type(record).__name__}")
    if record.num_steps == 0:
        raise ValueError(f"record {record.scenario!r} has no samples (T = 0); nothing to draw")
    if not np.all(np.isfinite(record.robot_poses)):
        raise ValueError(f"record {record.scenario!r}: robot_poses contain NaN or inf")
    for name in ("start", "goal", "target"):
        value = np.asarray(getattr(record, name), dtype=float)
        if value.shape != (3,) or not np.all(np.isfinite(value)):
            raise ValueError(f"record {record.scenario!r}: {name} must be a finite (3,) pose")


def new_figure(width: float, height: float) -> Figure:
    """A pyplot-free figure with the Agg canvas attached (no global state)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def social_spaces() -> ModuleType | None:
    """``socialnav.social.spaces`` if importable, else ``None`` (the layer is then not drawn).

    Imported lazily so the viz layer works while the social package is incomplete.
    """
    try:
        return importlib.import_module("socialnav.social.spaces")
    except ImportError:
        return None


# ----------------------------------------------------------------------------- geometry
def footprints(poses: FloatArray, footprint: FloatArray) -> FloatArray:
    """World vertices ``(n, V, 2)`` of the body-frame ``footprint (V, 2)`` at ``poses (n, 3)``."""
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    rot = np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)  # (n, 2, 2)
    return np.einsum("nij,vj->nvi", rot, footprint) + poses[:, None, :2]


def path_length(xy: FloatArray) -> FloatArray:
    """Cumulative arc length ``(T,)`` (m) of a polyline ``(T, 2)``, starting at 0."""
    seg = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    return np.concatenate([[0.0], np.cumsum(seg)])


def every_metres(xy: FloatArray, spacing: float) -> np.ndarray:
    """Sample indices roughly ``spacing`` metres of travel apart (first and last included).

    Spacing by distance, not time, so a robot waiting in place does not pile up outlines.
    """
    s = path_length(xy)
    if s[-1] <= 0.0:
        return np.array([0, xy.shape[0] - 1])
    marks = np.arange(0.0, s[-1], spacing)
    idx = np.searchsorted(s, marks, side="left")
    return np.unique(np.concatenate([idx, [xy.shape[0] - 1]]))


def closest_approach(record: EpisodeRecord) -> tuple[int, int, float] | None:
    """``(sample, person index, centre distance m)`` of the robot's closest approach to anyone."""
    if record.people_positions.shape[1] == 0:
        return None
    d = np.linalg.norm(record.people_positions - record.robot_xy[:, None, :], axis=-1)
    d = np.where(np.isfinite(d), d, np.inf)
    flat = int(np.argmin(d))
    t, k = np.unravel_index(flat, d.shape)
    if not np.isfinite(d[t, k]):
        return None
    return int(t), int(k), float(d[t, k])


def _reach_bounding_walls(
    lo: FloatArray, hi: FloatArray, segments: FloatArray, reach: float
) -> tuple[FloatArray, FloatArray]:
    """Grow ``lo``/``hi`` to the nearest wall beyond each side (within ``reach`` m, +0.3 m).

    Without it a corridor's far wall is cut when the robot kept to one side, and the picture
    hides the room the robot had. ``segments`` is ``(S, 2, 2)``.
    """
    lo, hi = lo.copy(), hi.copy()
    seg_lo, seg_hi = segments.min(axis=1), segments.max(axis=1)  # (S, 2) boxes
    for axis in (0, 1):
        other = 1 - axis
        # walls that face the region across this axis
        facing = (seg_hi[:, other] >= lo[other]) & (seg_lo[:, other] <= hi[other])
        below = facing & (seg_hi[:, axis] < lo[axis]) & (seg_hi[:, axis] >= lo[axis] - reach)
        above = facing & (seg_lo[:, axis] > hi[axis]) & (seg_lo[:, axis] <= hi[axis] + reach)
        if below.any():
            lo[axis] = seg_hi[below, axis].max() - 0.3
        if above.any():
            hi[axis] = seg_lo[above, axis].min() + 0.3
    return lo, hi


def region_of_interest(
    records: Sequence[EpisodeRecord],
    margin: float = 1.0,
    min_span: float = 4.0,
    wall_reach: float = 3.0,
) -> tuple[float, float, float, float]:
    """``(xmin, xmax, ymin, ymax)`` in metres, map frame: robot paths, people, goals and social
    geometry plus ``margin`` (m), at least ``min_span`` wide, grown to the nearest wall on each
    side when it is within ``wall_reach`` (m), clipped to the walls' extent (+0.3 m)."""
    pts: list[FloatArray] = []
    world: list[FloatArray] = []
    for r in records:
        pts.append(r.robot_xy)
        people = r.people_positions.reshape(-1, 2)
        pts.append(people[np.all(np.isfinite(people), axis=1)])
        pts.append(np.stack([r.start[:2], r.goal[:2], r.target[:2]]))
        if r.waypoint is not None:
            pts.append(np.asarray(r.waypoint, dtype=float).reshape(1, 2))
        for art in r.context.artworks:
            pts.append(np.asarray(art.center, dtype=float).reshape(1, 2))
        for q in r.context.queues:
            pts.append(np.asarray(q.service_point, dtype=float).reshape(1, 2))
        if r.walls.size:
            world.append(r.walls.reshape(-1, 2))
        world.extend(np.asarray(o, dtype=float) for o in r.obstacles)
    p = np.concatenate(pts)
    lo, hi = p.min(axis=0) - margin, p.max(axis=0) + margin
    centre, span = 0.5 * (lo + hi), np.maximum(hi - lo, min_span)
    lo, hi = centre - span / 2, centre + span / 2
    walls = [r.walls.reshape(-1, 2, 2) for r in records if r.walls.size]
    if walls:
        lo, hi = _reach_bounding_walls(lo, hi, np.concatenate(walls), wall_reach)
    if world:
        w = np.concatenate(world)
        lo = np.maximum(lo, w.min(axis=0) - 0.3)
        hi = np.minimum(hi, w.max(axis=0) + 0.3)
    return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])


def figure_size(
    roi: tuple[float, float, float, float],
    width: float = 6.0,
    *,
    legend_right: bool = True,
    cols: int = 1,
    rows: int = 1,
) -> tuple[float, float]:
    """Figure inches for ``rows × cols`` equal-aspect maps of ``roi``, each ``width`` inches wide
    (height follows the aspect, clamped), plus room for labels, titles and the legend."""
    dx, dy = roi[1] - roi[0], roi[3] - roi[2]
    panel_h = float(np.clip(width * dy / max(dx, 1e-9), 1.0, 1.4 * width))
    w = cols * width + 0.9 + (2.9 if legend_right else 0.0)
    h = rows * (panel_h + 0.7) + 0.4 + (0.0 if legend_right else 1.4)
    return w, h


# ----------------------------------------------------------------------------- layers
def draw_map(ax: Axes, record: EpisodeRecord) -> list[Any]:
    """Walls as thick dark segments, obstacles as filled grey polygons, artworks on the wall."""
    artists: list[Any] = []
    if record.walls.size:
        lc = LineCollection(
            record.walls,
            colors=COLORS["wall"],
            linewidths=3.0,
            capstyle="projecting",
            zorder=3,
            label="wall",
        )
        artists.append(ax.add_collection(lc, autolim=False))
    if record.obstacles:
        pc = PolyCollection(
            [np.asarray(o, dtype=float) for o in record.obstacles],
            facecolors=COLORS["obstacle"],
            edgecolors=COLORS["wall"],
            linewidths=1.0,
            zorder=3,
            label="obstacle",
        )
        artists.append(ax.add_collection(pc, autolim=False))
    for art in record.context.artworks:
        c = np.asarray(art.center, dtype=float)
        t = np.array([-np.sin(art.facing), np.cos(art.facing)])  # along the wall
        n = np.array([np.cos(art.facing), np.sin(art.facing)])
        # Inset by the wall's half-thickness so the artwork shows in front of the wall line.
        ends = np.stack([c - 0.5 * art.width * t, c + 0.5 * art.width * t]) + 0.08 * n
        (line,) = ax.plot(
            ends[:, 0],
            ends[:, 1],
            color=COLORS["artwork"],
            linewidth=6.0,
            solid_capstyle="butt",
            zorder=4,
            label="artwork",
        )
        artists.append(line)
    return artists


def draw_social(ax: Axes, record: EpisodeRecord) -> dict[str, list[Any]]:
    """O-spaces and group circles, activity spaces, queue lines and cut-in bands; structures of
    registered kinds through their own ``draw``.

    Geometry comes from :mod:`socialnav.social.spaces` (drawn only when that module imports).
    Returns artists by kind: ``o_space``, ``group_circle``, ``activity_space``, ``queue_band``,
    ``queue_line``.
    """
    out: dict[str, list[Any]] = {
        "o_space": [],
        "group_circle": [],
        "activity_space": [],
        "queue_band": [],
        "queue_line": [],
    }
    ctx = record.context
    for q in ctx.queues:  # the line itself needs no social module
        line = np.vstack([np.asarray(q.service_point, dtype=float), ctx.positions(q.member_ids)])
        if record.family == "queue":
            line = np.vstack([line, record.target[:2]])
        (ln,) = ax.plot(
            line[:, 0],
            line[:, 1],
            color=COLORS["queue_line"],
            linestyle=(0, (1, 2)),
            linewidth=1.0,
            zorder=2,
            label="queue line",
        )
        out["queue_line"].append(ln)
    spaces = social_spaces()
    if spaces is None:
        return out
    try:  # a group the planner plans around as people has no circle or o-space to draw
        from socialnav.social.plausibility import plausible_context

        groups = plausible_context(ctx).groups
    except ImportError:
        groups = ctx.groups
    for g in groups:
        pos = ctx.positions(g.member_ids)
        try:
            center, radius = spaces.fit_circle(pos)
            oc, orad = spaces.o_space(pos)
        except (ValueError, AttributeError):
            continue
        ring = Circle(
            center,
            radius,
            fill=False,
            edgecolor=COLORS["group_circle"],
            linestyle="--",
            linewidth=0.9,
            zorder=2,
            label="group circle",
        )
        disc = Circle(
            oc,
            orad,
            facecolor=COLORS["o_space"],
            alpha=0.28,
            edgecolor=COLORS["o_space"],
            linewidth=1.2,
            zorder=1.5,
            label="o-space",
        )
        out["group_circle"].append(ax.add_patch(ring))
        out["o_space"].append(ax.add_patch(disc))
    for art in ctx.artworks:
        for vid in art.viewer_ids:
            try:
                poly = spaces.activity_space_polygon(
                    art.center, art.width, art.facing, ctx.person(vid).position
                )
            except (ValueError, AttributeError):
                continue
            patch = Polygon(
                np.asarray(poly, dtype=float),
                closed=True,
                facecolor=COLORS["activity"],
                alpha=0.25,
                edgecolor=COLORS["activity"],
                hatch="///",
                linewidth=1.0,
                zorder=1.5,
                label="activity space",
            )
            out["activity_space"].append(ax.add_patch(patch))
    for q in ctx.queues:
        try:
            bands = spaces.queue_band_polygons(ctx.positions(q.member_ids))
        except (ValueError, AttributeError):
            continue
        if len(bands):
            pc = PolyCollection(
                [np.asarray(b, dtype=float) for b in bands],
                facecolors=COLORS["queue_band"],
                alpha=0.18,
                edgecolors=COLORS["queue_band"],
                linewidths=0.8,
                hatch="xx",
                zorder=1.5,
                label="queue cut-in band",
            )
            out["queue_band"].append(ax.add_collection(pc, autolim=False))
    if record.context.structures:  # kinds registered in socialnav.social.structures draw themselves
        from socialnav.social.structures import STRUCTURES

        for structure in record.context.structures:
            STRUCTURES.get(structure.kind).draw(ax, structure.params, record.context)
    return out


def draw_people(
    ax: Axes, record: EpisodeRecord, *, tracks: bool = True, end_space: bool = True
) -> dict[str, list[Any]]:
    """People tracks (dotted magenta), start rings, end discs (body radius), heading arrows
    (motion direction, or the context yaw for people standing), and faint personal-space
    circles at the end. Returns artists by kind."""
    out: dict[str, list[Any]] = {"track": [], "body": [], "arrow": [], "personal_space": []}
    P = record.people_positions  # (T, K, 2)
    K = P.shape[1]
    if K == 0:
        return out
    color = COLORS["person"]
    ends, heads = np.full((K, 2), np.nan), np.full((K, 2), np.nan)
    starts = np.full((K, 2), np.nan)
    yaw_by_id = {p.id: p.yaw for p in record.context.people}
    for k in range(K):
        ok = np.all(np.isfinite(P[:, k]), axis=1)
        if not ok.any():
            continue
        track = P[ok, k]
        starts[k], ends[k] = track[0], track[-1]
        dur = max(record.times[ok][-1] - record.times[ok][0], 1e-9)
        moving = path_length(track)[-1] / dur > STANDING_SPEED
        if moving and tracks:
            (ln,) = ax.plot(
                track[:, 0],
                track[:, 1],
                color=color,
                linestyle=":",
                linewidth=1.8,
                zorder=5,
                label="person track",
            )
            out["track"].append(ln)
            # Direction arrows along the track (the paper marks walking directions so).
            mid = every_metres(track, 2.0)[1:-1]
            mid = mid[mid < track.shape[0] - 1]
            if mid.size:
                d = track[mid + 1] - track[mid]
                d = 0.35 * d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-9)
                out["arrow"].append(_arrows(ax, track[mid], d, color, 0.018, 4.0, 4.5))
        if moving:
            step = track[-1] - track[max(0, track.shape[0] - 6)]
            yaw = float(np.arctan2(step[1], step[0]))
        else:
            yaw = float(yaw_by_id.get(int(record.people_ids[k]), np.nan))
        heads[k] = [np.cos(yaw), np.sin(yaw)] if np.isfinite(yaw) else [np.nan, np.nan]
    have = np.all(np.isfinite(ends), axis=1)
    moved = have & (np.linalg.norm(ends - starts, axis=1) > 0.3)
    if moved.any():
        out["body"].append(
            ax.scatter(
                starts[moved, 0],
                starts[moved, 1],
                s=28,
                facecolors="white",
                edgecolors=color,
                linewidths=1.2,
                zorder=6,
                label="person start",
            )
        )
    bodies = [Circle(e, r) for e, r, h in zip(ends, record.people_radii, have, strict=True) if h]
    if bodies:
        pc = PatchCollection(
            bodies,
            facecolors=color,
            edgecolors="black",
            linewidths=0.6,
            alpha=0.85,
            zorder=6,
            label="person",
        )
        out["body"].append(ax.add_collection(pc, autolim=False))
    arrow_ok = have & np.all(np.isfinite(heads), axis=1)
    if arrow_ok.any():
        tails = ends[arrow_ok]
        vec = heads[arrow_ok] * 0.55
        out["arrow"].append(_arrows(ax, tails, vec, color, 0.022, 3.5, 4.0))
    if end_space:
        circles = [Circle(e, PERSONAL_SPACE) for e, h in zip(ends, have, strict=True) if h]
        pc = PatchCollection(
            circles,
            facecolors=color,
            edgecolors=color,
            alpha=0.06,
            linewidths=0.8,
            zorder=1.2,
            label=f"personal space ({PERSONAL_SPACE:g} m)",
        )
        out["personal_space"].append(ax.add_collection(pc, autolim=False))
        # The fill is faint; a separate outline keeps the boundary readable.
        rings = PatchCollection(
            [Circle(e, PERSONAL_SPACE) for e, h in zip(ends, have, strict=True) if h],
            facecolors="none",
            edgecolors=color,
            alpha=0.45,
            linewidths=0.8,
            linestyle="--",
            zorder=1.2,
        )
        out["personal_space"].append(ax.add_collection(rings, autolim=False))
    return out


def draw_robot_path(
    ax: Axes,
    record: EpisodeRecord,
    *,
    color: str,
    linestyle: str = "-",
    label: str | None = None,
    footprint_every: float | None = 1.5,
    linewidth: float = 2.0,
) -> dict[str, list[Any]]:
    """Robot path, footprint outlines every ``footprint_every`` metres of travel (``None``:
    only start and end), heading arrows at those outlines, collision marks."""
    out: dict[str, list[Any]] = {"path": [], "footprint": [], "arrow": [], "collision": []}
    xy = record.robot_xy
    (ln,) = ax.plot(
        xy[:, 0],
        xy[:, 1],
        color=color,
        linestyle=linestyle,
        linewidth=linewidth,
        zorder=8,
        label=label,
    )
    out["path"].append(ln)
    fp = np.asarray(record.robot_footprint, dtype=float)
    idx = (
        every_metres(xy, footprint_every)
        if footprint_every is not None and footprint_every > 0
        else np.array([0, xy.shape[0] - 1])
    )
    if fp.ndim == 2 and fp.shape[0] >= 3 and fp.shape[1] == 2:
        polys = footprints(record.robot_poses[idx], fp)
        pc = PolyCollection(
            polys,
            facecolors="none",
            edgecolors=color,
            linewidths=0.9,
            alpha=0.55,
            linestyles=linestyle,
            zorder=7,
        )
        out["footprint"].append(ax.add_collection(pc, autolim=False))
        last = PolyCollection(
            polys[-1:],
            facecolors=color,
            edgecolors=color,
            alpha=0.3,
            linewidths=1.4,
            zorder=7,
        )
        out["footprint"].append(ax.add_collection(last, autolim=False))
    yaw = record.robot_poses[idx, 2]
    size = max(0.35, 0.8 * float(record.robot_radius))
    out["arrow"].append(
        ax.quiver(
            xy[idx, 0],
            xy[idx, 1],
            size * np.cos(yaw),
            size * np.sin(yaw),
            angles="xy",
            scale_units="xy",
            scale=1.0,
            color=color,
            units="inches",
            width=0.018,
            headwidth=3.5,
            headlength=4.0,
            zorder=9,
        )
    )
    hit = np.asarray(record.collision_person, bool) | np.asarray(record.collision_obstacle, bool)
    if hit.any():
        out["collision"].append(
            ax.scatter(
                xy[hit, 0],
                xy[hit, 1],
                marker="x",
                s=40,
                color=COLORS["collision"],
                linewidths=1.5,
                zorder=10,
                label="collision",
            )
        )
    return out


def draw_closest_approach(
    ax: Axes, record: EpisodeRecord, color: str, label_slot: int = 0
) -> list[Any]:
    """At the moment of closest approach: the person's personal-space circle, the person and
    the robot footprint at that moment, and the centre distance as a labelled segment
    (``label_slot`` stacks the labels of overlaid runs so they do not overlap)."""
    hit = closest_approach(record)
    if hit is None:
        return []
    t, k, dist = hit
    p = record.people_positions[t, k]
    r = record.robot_xy[t]
    artists: list[Any] = [
        ax.add_patch(
            Circle(
                p,
                PERSONAL_SPACE,
                fill=False,
                edgecolor=color,
                linestyle=(0, (4, 2)),
                linewidth=1.1,
                alpha=0.8,
                zorder=6,
            )
        ),
        ax.add_patch(
            Circle(
                p,
                float(record.people_radii[k]),
                facecolor="none",
                edgecolor=COLORS["person"],
                linewidth=1.0,
                linestyle="--",
                zorder=6,
            )
        ),
    ]
    fp = np.asarray(record.robot_footprint, dtype=float)
    if fp.ndim == 2 and fp.shape[0] >= 3:
        poly = footprints(record.robot_poses[t : t + 1], fp)[0]
        artists.append(
            ax.add_patch(
                Polygon(
                    poly, closed=True, facecolor="none", edgecolor=color, linewidth=1.6, zorder=9
                )
            )
        )
    (seg,) = ax.plot([p[0], r[0]], [p[1], r[1]], color=color, linewidth=0.9, zorder=9)
    mid = 0.5 * (p + r)
    txt = ax.annotate(
        f"{dist:.2f} m",
        mid,
        xytext=(4, 4 + 12 * label_slot),
        textcoords="offset points",
        fontsize=8,
        color=color,
        zorder=11,
        bbox={
            "boxstyle": "round,pad=0.15",
            "facecolor": "white",
            "edgecolor": "none",
            "alpha": 0.8,
        },
    )
    artists.extend([seg, txt])
    return artists


def target_label(family: str) -> str:
    """Legend name of ``record.target`` for each scenario family."""
    return {
        "queue": "queue tail slot (target)",
        "group": "free spot (target)",
        "gallery_present": "presenter spot (target)",
    }.get(family, "social goal (target)")


def draw_goals(ax: Axes, record: EpisodeRecord, *, start: bool = True) -> dict[str, list[Any]]:
    """Start (black ring), given goal (red star), the target when it differs from the goal
    (gold diamond with a heading arrow and the success-tolerance ring) and the waypoint."""
    out: dict[str, list[Any]] = {"start": [], "goal": [], "target": [], "waypoint": []}
    if start:
        out["start"].append(
            ax.scatter(
                [record.start[0]],
                [record.start[1]],
                marker="o",
                s=60,
                facecolors="white",
                edgecolors=COLORS["start"],
                linewidths=1.6,
                zorder=12,
                label="start",
            )
        )
    out["goal"].append(
        ax.scatter(
            [record.goal[0]],
            [record.goal[1]],
            marker="*",
            s=260,
            color=COLORS["goal"],
            edgecolors="black",
            linewidths=0.6,
            zorder=12,
            label="given goal",
        )
    )
    tgt = np.asarray(record.target, dtype=float)
    if np.linalg.norm(tgt[:2] - record.goal[:2]) > 1e-6:
        out["target"].append(
            ax.scatter(
                [tgt[0]],
                [tgt[1]],
                marker="D",
                s=80,
                color=COLORS["target"],
                edgecolors="black",
                linewidths=1.0,
                zorder=12,
                label=target_label(record.family),
            )
        )
        out["target"].append(
            ax.quiver(
                [tgt[0]],
                [tgt[1]],
                [0.5 * np.cos(tgt[2])],
                [0.5 * np.sin(tgt[2])],
                angles="xy",
                scale_units="xy",
                scale=1.0,
                color="black",
                units="inches",
                width=0.014,
                zorder=12,
            )
        )
        out["target"].append(
            ax.add_patch(
                Circle(
                    tgt[:2],
                    record.goal_tolerance,
                    fill=False,
                    edgecolor="black",
                    linestyle=":",
                    linewidth=0.9,
                    zorder=11,
                )
            )
        )
    if record.waypoint is not None:
        w = np.asarray(record.waypoint, dtype=float).reshape(2)
        out["waypoint"].append(
            ax.scatter(
                [w[0]],
                [w[1]],
                marker="^",
                s=90,
                color=COLORS["waypoint"],
                edgecolors="black",
                linewidths=1.0,
                zorder=12,
                label="social waypoint",
            )
        )
    return out


def dedup_legend_handles(axes: Sequence[Axes]) -> tuple[list[Any], list[str]]:
    """Legend handles/labels over ``axes``, one per label (first occurrence wins)."""
    handles, labels, seen = [], [], set()
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            if lab and not lab.startswith("_") and lab not in seen:
                seen.add(lab)
                handles.append(h)
                labels.append(lab)
    return handles, labels


def finish_map_axes(ax: Axes, roi: tuple[float, float, float, float]) -> None:
    """Equal aspect, the ROI limits, metre labels and a light grid."""
    ax.set_xlim(roi[0], roi[1])
    ax.set_ylim(roi[2], roi[3])
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, color="#dddddd", linewidth=0.5, zorder=0)
    ax.set_axisbelow(True)


def _arrows(
    ax: Any,
    tails: np.ndarray,
    vectors: np.ndarray,
    color: Any,
    width: float,
    headwidth: float,
    headlength: float,
) -> Any:
    """Direction arrows in data units: ``tails (K, 2)`` + ``vectors (K, 2)`` (m)."""
    return ax.quiver(
        tails[:, 0],
        tails[:, 1],
        vectors[:, 0],
        vectors[:, 1],
        angles="xy",
        scale_units="xy",
        scale=1.0,
        color=color,
        units="inches",
        width=width,
        headwidth=headwidth,
        headlength=headlength,
        zorder=7,
    )

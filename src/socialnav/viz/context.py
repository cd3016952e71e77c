"""Picture of an estimated social context: people, the structures found, their confidence.

Left: the scene at one frame — people (dots with heading ticks), F-formations (o-space circle),
walking groups (a line through the members), queues (a polyline from the service point through
the members, head marked), artwork viewers (a line to the artwork), walls. Right: every
structure's confidence over time (one line per track). Positions in metres, world frame.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from socialnav.core.geometry import FloatArray
from socialnav.social.perception import Estimate

KIND_COLORS = {
    "fformation": "tab:blue",
    "walking_group": "tab:orange",
    "queue": "tab:green",
    "viewers": "tab:purple",
}


def plot_context(
    estimates: Sequence[Estimate],
    frame: int | None = None,
    walls: FloatArray | None = None,
    title: str = "",
    robot_poses: FloatArray | None = None,
) -> Figure:
    """Figure of ``estimates`` (one per frame); the scene is drawn at ``frame`` (default:
    the frame with the most structures of confidence ≥ 0.5, then their highest total
    confidence), zoomed on the people and the robot.

    ``robot_poses (T, 3)`` (x, y, yaw; m, rad, world frame), one per estimate, draws the robot
    at the frame (a recording has none). The legend lists only the kinds that occur.
    Raises ``ValueError`` with no estimates, or robot poses of another length."""
    if not estimates:
        raise ValueError("no estimates to draw")
    chosen = frame is None
    if frame is None:
        # confident structures first: a track fading out beside its successor is not a scene
        conf = [[s.confidence for s in e.structures if s.confidence >= 0.5] for e in estimates]
        key = [(len(c), sum(c)) for c in conf]
        frame = max(range(len(key)), key=lambda i: key[i])
    est = estimates[frame]
    if robot_poses is not None and len(robot_poses) != len(estimates):
        raise ValueError(f"{len(robot_poses)} robot poses for {len(estimates)} estimates")
    fig = Figure(figsize=(11, 5), layout="constrained")
    ax, ax_t = fig.subplots(1, 2, width_ratios=(1.1, 1))
    if walls is not None:
        for i, (a, b) in enumerate(np.asarray(walls, dtype=float).reshape(-1, 2, 2)):
            # a recording's walls are the border of its annotated area
            label = "walls / area border" if i == 0 else None
            ax.plot([a[0], b[0]], [a[1], b[1]], color="0.3", lw=1.5, label=label)
    people = {p.id: p for p in est.context.people}
    for i, p in enumerate(people.values()):
        x, y = p.position
        ax.plot(
            x,
            y,
            "o",
            color="0.2",
            ms=5,
            zorder=3,
            label="person (tick: heading)" if i == 0 else None,
        )
        ax.plot([x, x + 0.35 * np.cos(p.yaw)], [y, y + 0.35 * np.sin(p.yaw)], color="0.2", lw=1)
    for art in est.context.artworks:
        n = np.array([np.cos(art.facing), np.sin(art.facing)])
        t = np.array([-n[1], n[0]])
        c = np.asarray(art.center)
        ends = np.stack([c - 0.5 * art.width * t, c + 0.5 * art.width * t])
        ax.plot(ends[:, 0], ends[:, 1], color=KIND_COLORS["viewers"], lw=4, alpha=0.5)
    labels: list[FloatArray] = []  # anchors of the labels placed so far
    for s in est.structures:
        color = KIND_COLORS.get(s.kind, "k")
        pts = np.array([people[m].position for m in s.members if m in people]).reshape(-1, 2)
        if s.kind == "fformation" and "ospace_center" in s.geometry:
            c = np.asarray(s.geometry["ospace_center"])
            r = float(s.geometry.get("ospace_radius", 0.5))
            a = np.linspace(0, 2 * np.pi, 60)
            ax.plot(c[0] + r * np.cos(a), c[1] + r * np.sin(a), color=color, lw=1.5)
        elif s.kind in ("walking_group", "queue"):
            ax.plot(pts[:, 0], pts[:, 1], "-", color=color, lw=2)
            if s.kind == "queue":
                ax.plot(
                    pts[0, 0], pts[0, 1], "s", color=color, ms=9, mfc="none", label="queue head"
                )
        elif s.kind == "viewers":
            for art in est.context.artworks:
                for v in art.viewer_ids:
                    if v in people:
                        at = people[v].position
                        ax.plot([at[0], art.center[0]], [at[1], art.center[1]], ":", color=color)
        if pts.size:
            anchor = pts.mean(axis=0)
            # structures sharing members have nearby centres: stack their labels
            # labels run to the right of their anchor: stack those that would overlap
            near = sum(
                1 for a in labels if abs(a[1] - anchor[1]) < 0.6 and abs(a[0] - anchor[0]) < 3.0
            )
            labels.append(anchor)
            ax.annotate(
                f"{s.kind} {s.confidence:.2f}",
                anchor,
                fontsize=7,
                color=color,
                xytext=(4, 4 + 9 * near),
                textcoords="offset points",
            )
    if robot_poses is not None:
        rx, ry, ryaw = (float(v) for v in robot_poses[frame])
        # a triangle turned to the robot's heading (marker angle in degrees, 0 = pointing up)
        arrow = (3, 0, float(np.degrees(ryaw)) - 90.0)
        ax.plot(rx, ry, marker=arrow, ls="", color="tab:red", ms=9, zorder=4, label="robot")
        ax.plot([rx, rx + 0.5 * np.cos(ryaw)], [ry, ry + 0.5 * np.sin(ryaw)], color="tab:red")
    shown = [p.position for p in people.values()]
    if robot_poses is not None:
        shown.append(tuple(robot_poses[frame][:2]))
    if shown:
        xy = np.array(shown, dtype=float)
        lo, hi = xy.min(axis=0) - 2.0, xy.max(axis=0) + 2.0
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    why = "\n(the frame with the most confident structures)" if chosen else ""
    ax.set_title(f"{title} t = {est.time:.1f} s".strip() + why, fontsize=10)
    series: dict[int, tuple[str, list[float], list[float]]] = {}
    for e in estimates:
        for s in e.structures:
            kind, ts, cs = series.setdefault(s.track_id, (s.kind, [], []))
            ts.append(e.time)
            cs.append(s.confidence)
    for kind, ts, cs in series.values():
        ax_t.plot(ts, cs, ".", ms=2, color=KIND_COLORS.get(kind, "k"))
    seen = {kind for kind, _, _ in series.values()}
    for kind, color in KIND_COLORS.items():
        if kind in seen:
            ax_t.plot([], [], "-", color=color, label=kind)
    ax_t.axvline(est.time, color="0.6", lw=0.8)
    ax_t.set_ylim(0, 1.05)
    ax_t.set_xlabel("time (s)")
    ax_t.set_ylabel("confidence (active structures)")
    if seen:
        ax_t.legend(loc="lower right", fontsize=8)
    else:
        ax_t.text(0.5, 0.5, "no structure found", ha="center", transform=ax_t.transAxes)
    handles, names = ax.get_legend_handles_labels()
    if handles:
        unique = dict(zip(names, handles, strict=True))  # one entry per label
        ax.legend(unique.values(), unique.keys(), loc="best", fontsize=8, framealpha=0.6)
    return fig

"""Robot paths over a replayed crowd's tracks (the crowd suite's figure).

People present for part of an episode are drawn only where they are present (NaN breaks their
track): thin magenta lines, a dot where each one appears, contacts as red marks where the
robot was when they began (× active, + passive — ``socialnav.metrics.crowd``), all in the
legend. Panels of one task (the same start and goal: a planner and the straight-line
reference) share their axis limits, so they compare at a glance. Metres, world frame.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.artist import Artist
from matplotlib.figure import Figure

from socialnav.core.episode import EpisodeRecord
from socialnav.viz.style import COLORS, planner_style


def plot_crowd_episodes(
    records: Sequence[EpisodeRecord], title: str = "", columns: int = 3
) -> Figure:
    """One panel per record: the crowd's tracks, the robot's path, start, goal and contacts.
    ``records`` may mix planners (each path in its planner's colour)."""
    from socialnav.metrics.crowd import contact_events

    n = max(len(records), 1)
    cols = min(columns, n)
    rows = int(np.ceil(n / cols))
    fig = Figure(figsize=(4.2 * cols, 4.2 * rows))
    # one view per task: the union of its panels' paths and goal, 2 m around
    views: dict[tuple[float, ...], tuple[np.ndarray, np.ndarray]] = {}
    for rec in records:
        key = _task(rec)
        lo = np.minimum(rec.robot_xy.min(axis=0), rec.goal[:2]) - 2.0
        hi = np.maximum(rec.robot_xy.max(axis=0), rec.goal[:2]) + 2.0
        if key in views:
            lo, hi = np.minimum(lo, views[key][0]), np.maximum(hi, views[key][1])
        views[key] = (lo, hi)
    for i, rec in enumerate(records):
        ax = fig.add_subplot(rows, cols, i + 1)
        for a, b in np.asarray(rec.walls).reshape(-1, 2, 2):
            ax.plot(*np.stack([a, b]).T, color=COLORS["wall"], lw=1.2)
        for k in range(rec.people_positions.shape[1]):
            track = rec.people_positions[:, k]
            label = "people (a dot where each appears)" if k == 0 else None
            ax.plot(*track.T, color=COLORS["person"], lw=0.6, alpha=0.55, label=label)
            first = np.flatnonzero(rec.people_present[:, k])
            if first.size:
                ax.plot(*track[first[0]], ".", color=COLORS["person"], ms=3)
        style = planner_style(str(rec.meta.get("planner")))
        ax.plot(
            *rec.robot_xy.T,
            color=style.color,
            ls=style.linestyle,
            lw=1.8,
            label=style.label or str(rec.meta.get("planner")),
        )
        ax.plot(*rec.start[:2], "o", color=COLORS["start"], ms=5, label="start")
        ax.plot(*rec.goal[:2], "*", color=COLORS["goal"], ms=11, label="goal")
        labelled: set[bool] = set()
        for _, onset, _, active in contact_events(rec):
            label = None
            if active not in labelled:
                label = "active contact" if active else "passive contact"
                labelled.add(active)
            ax.plot(
                *rec.robot_xy[onset],
                "x" if active else "+",
                color=COLORS["collision"],
                ms=9,
                mew=2,
                label=label,
            )
        lo, hi = views[_task(rec)]
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
        ax.set_xlabel("x (m)", fontsize=7)
        ax.set_ylabel("y (m)", fontsize=7)
        seed = "" if rec.meta.get("seed") is None else f" · seed {rec.meta['seed']}"
        ax.set_title(f"{rec.meta.get('planner')} · {rec.meta.get('robot')}{seed}", fontsize=8)
    # one legend for the figure, under the panels: inside one it hid the goal
    entries: dict[str, Artist] = {}
    for ax in fig.axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            entries.setdefault(label, handle)
    if entries:
        fig.legend(
            list(entries.values()),
            list(entries),
            loc="lower center",
            ncol=min(len(entries), 4),
            fontsize=7,
            frameon=False,
        )
        fig.subplots_adjust(bottom=0.08 + 0.05 * np.ceil(len(entries) / 4) / rows)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


def _task(rec: EpisodeRecord) -> tuple[float, ...]:
    """A record's task: its start and goal (m), rounded to a millimetre."""
    return tuple(round(float(v), 3) for v in (*rec.start[:2], *rec.goal[:2]))

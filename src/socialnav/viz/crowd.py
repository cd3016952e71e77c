"""Robot paths over a replayed crowd's tracks (the crowd suite's figure).

People present for part of an episode are drawn only where they are present (NaN breaks their
track): thin magenta lines, a dot where each one appears, contacts as red crosses (filled for
active contacts, hollow for passive ones — ``socialnav.metrics.crowd``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
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
    for i, rec in enumerate(records):
        ax = fig.add_subplot(rows, cols, i + 1)
        for a, b in np.asarray(rec.walls).reshape(-1, 2, 2):
            ax.plot(*np.stack([a, b]).T, color=COLORS["wall"], lw=1.2)
        for k in range(rec.people_positions.shape[1]):
            track = rec.people_positions[:, k]
            ax.plot(*track.T, color=COLORS["person"], lw=0.6, alpha=0.55)
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
        ax.plot(*rec.start[:2], "o", color=COLORS["start"], ms=5)
        ax.plot(*rec.goal[:2], "*", color=COLORS["goal"], ms=11)
        for _, onset, _, active in contact_events(rec):
            ax.plot(
                *rec.robot_xy[onset], "x" if active else "+", color=COLORS["collision"], ms=9, mew=2
            )
        lo = np.minimum(rec.robot_xy.min(axis=0), rec.goal[:2]) - 2.0
        hi = np.maximum(rec.robot_xy.max(axis=0), rec.goal[:2]) + 2.0
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
        seed = "" if rec.meta.get("seed") is None else f" · seed {rec.meta['seed']}"
        ax.set_title(f"{rec.meta.get('planner')} · {rec.meta.get('robot')}{seed}", fontsize=8)
        ax.legend(fontsize=7, loc="upper right")
    if title:
        fig.suptitle(title, fontsize=10)
    return fig

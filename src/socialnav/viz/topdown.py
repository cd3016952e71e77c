"""Top-down figures of recorded episodes, in the style of the paper's result figures.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach",
section "Results": robot trajectories of the traditional planner (dashed green) and of the PaCcET
planner (solid blue) over the map, people as dotted magenta tracks, directions as arrows, the social
goal as a star.

Deviations from the paper's figures:
- the given goal is the red star; the social goal (``record.target``) is a gold diamond, so both
  show when they differ;
- the robot footprint is drawn as periodic outlines (every ``show_footprint_every`` metres of
  travel) instead of two swept side lines;
- personal-space circles (1.2 m) at the closest approach and at the end, o-spaces, activity spaces
  and queue cut-in bands are drawn so a reader can check the social success conditions by eye;
- the view auto-zooms to the region of interest instead of the whole map.

Only ``matplotlib.figure.Figure`` objects with the Agg canvas are used (no pyplot state).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Literal

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from socialnav.core.episode import EpisodeRecord
from socialnav.viz import _layers as L
from socialnav.viz.style import PathStyle, assign_styles, planner_style

__all__ = ["plot_comparison", "plot_episode", "save_figure"]


def _planner_name(record: EpisodeRecord) -> str | None:
    name = record.meta.get("planner")
    return None if name is None else str(name)


def _stats_suffix(record: EpisodeRecord) -> str:
    """`` (goal in 13.2 s, 5.04 m, min 0.87 m)``: the ``time_to_goal`` metric (one definition
    of the time, the table's and the figure's), path length, closest centre distance. A run that
    never arrives says so, with how long it lasted."""
    from socialnav.metrics.table1 import time_to_goal

    arrival = time_to_goal(record)
    if np.isfinite(arrival):
        when = f"goal in {arrival:.1f} s"
    else:
        when = f"no arrival in {float(record.times[-1] - record.times[0]):.1f} s"
    length = float(L.path_length(record.robot_xy)[-1])
    hit = L.closest_approach(record)
    near = "" if hit is None else f", min {hit[2]:.2f} m"
    return f" ({when}, {length:.2f} m{near})"


def _title(record: EpisodeRecord) -> str:
    parts = [record.scenario]
    extra = [str(record.meta[k]) for k in ("planner", "robot") if record.meta.get(k) is not None]
    if "seed" in record.meta:
        extra.append(f"seed {record.meta['seed']}")
    return " — ".join([*parts, " · ".join(extra)]) if extra else parts[0]


def _common_title(records: Sequence[EpisodeRecord]) -> str:
    """The scenario, plus the robot when every record used the same one."""
    robots = {str(r.meta.get("robot")) for r in records if r.meta.get("robot") is not None}
    robot = f" · {robots.pop()}" if len(robots) == 1 else ""
    return f"{records[0].scenario}{robot}"


def _draw_scene(ax: Axes, record: EpisodeRecord, *, show_people: bool, show_social: bool) -> None:
    L.draw_map(ax, record)
    if show_social:
        L.draw_social(ax, record)
    if show_people:
        L.draw_people(ax, record)


def _draw_robot(
    ax: Axes,
    record: EpisodeRecord,
    style: PathStyle,
    label: str,
    *,
    show_people: bool,
    show_footprint_every: float | None,
    slot: int = 0,
) -> None:
    L.draw_robot_path(
        ax,
        record,
        color=style.color,
        linestyle=style.linestyle,
        label=label,
        footprint_every=show_footprint_every,
    )
    if show_people:
        L.draw_closest_approach(ax, record, style.color, slot)


def _legend(fig: Figure, axes: Sequence[Axes], wide: bool, first: Sequence[str] = ()) -> None:
    """One figure legend; the robot paths (``first``) lead, the scene follows."""
    handles, labels = L.dedup_legend_handles(axes)
    if not handles:
        return
    rank = {lab: i for i, lab in enumerate(first)}
    order = sorted(range(len(labels)), key=lambda i: (rank.get(labels[i], len(rank)), i))
    handles, labels = [handles[i] for i in order], [labels[i] for i in order]
    if wide:
        # About 2.6 in per column keeps long planner labels (with stats) inside the figure.
        ncols = max(1, min(len(handles), int(fig.get_figwidth() // 2.6)))
        fig.legend(
            handles, labels, loc="outside lower center", ncols=ncols, fontsize=8, frameon=False
        )
    else:
        fig.legend(handles, labels, loc="outside right upper", fontsize=8, frameon=False)


def _is_wide(roi: tuple[float, float, float, float]) -> bool:
    return (roi[3] - roi[2]) / max(roi[1] - roi[0], 1e-9) < 0.45


def plot_episode(
    record: EpisodeRecord,
    ax: Axes | None = None,
    *,
    label: str | None = None,
    color: str | None = None,
    linestyle: str | None = None,
    show_people: bool = True,
    show_social: bool = True,
    show_footprint_every: float | None = 1.5,
    show_stats: bool = True,
    margin: float = 1.0,
    legend: bool = True,
    title: str | None = None,
) -> Figure | Axes:
    """Top-down plot of one episode.

    Draws walls and obstacles, artworks, social geometry (o-spaces, activity spaces, queue
    lines and cut-in bands), people tracks with start/end markers and heading arrows,
    personal-space circles (1.2 m) at the end and at the robot's closest approach, the robot
    path with footprint outlines every ``show_footprint_every`` metres of travel (``None``:
    start and end only), start, given goal (red star), target and waypoint.

    The view is zoomed to the robot path, people and goals plus ``margin`` (m), equal aspect.
    ``label``/``color``/``linestyle`` default to the planner's style (``record.meta["planner"]``);
    ``show_stats`` appends duration, path length and closest distance to the label.

    Returns a new :class:`Figure` when ``ax`` is None, else draws into ``ax`` and returns it
    (then no figure legend is added; call ``ax.legend()`` yourself). Raises ``ValueError`` on an
    empty record or a non-finite robot trajectory.
    """
    L.check_record(record)
    base = planner_style(_planner_name(record))
    style = PathStyle(color or base.color, linestyle or base.linestyle, base.marker, base.label)
    text = label or base.label or _planner_name(record) or "robot"
    if show_stats:
        text += _stats_suffix(record)
    roi = L.region_of_interest([record], margin=margin)
    wide = _is_wide(roi)
    own = ax is None
    if ax is None:
        fig = L.new_figure(*L.figure_size(roi, width=8.0 if wide else 6.0, legend_right=not wide))
        ax = fig.add_subplot()
    _draw_scene(ax, record, show_people=show_people, show_social=show_social)
    _draw_robot(
        ax, record, style, text, show_people=show_people, show_footprint_every=show_footprint_every
    )
    L.draw_goals(ax, record)
    L.finish_map_axes(ax, roi)
    ax.set_title(title if title is not None else _title(record), fontsize=10)
    if not own:
        return ax
    if legend:
        _legend(fig, [ax], wide, first=[text])
    return fig


def _people_differ(a: EpisodeRecord, b: EpisodeRecord, tol: float = 0.01) -> bool:
    if a.people_positions.shape[1:] != b.people_positions.shape[1:]:
        return True
    n = min(a.num_steps, b.num_steps)
    d = np.abs(a.people_positions[:n] - b.people_positions[:n])
    return bool(np.nanmax(d, initial=0.0) > tol)


def plot_comparison(
    records: Sequence[EpisodeRecord],
    labels: Sequence[str] | None = None,
    *,
    mode: Literal["overlay", "panels"] = "overlay",
    ncols: int | None = None,
    show_people: bool = True,
    show_social: bool = True,
    show_footprint_every: float | None = 2.0,
    show_stats: bool = True,
    margin: float = 1.0,
    title: str | None = None,
) -> Figure:
    """Several planners' episodes of one scenario on one map (the paper's traditional vs
    PaCcET figures), or side by side with ``mode="panels"`` (shared limits).

    Colours/line styles come from each record's planner name (``meta["planner"]``), so a
    planner looks the same in every figure; ``labels`` (one per record) override the legend
    names. In overlay mode the map, social geometry, people and goals are those of the first
    record; people tracks of other records are added (in their planner's colour) only where
    they differ, e.g. with reactive humans. Raises ``ValueError`` on no records, mismatched
    ``labels``, or (overlay) records of different scenarios.
    """
    records = list(records)
    if not records:
        raise ValueError("plot_comparison needs at least one record")
    if labels is not None and len(labels) != len(records):
        raise ValueError(f"got {len(labels)} labels for {len(records)} records")
    if mode not in ("overlay", "panels"):
        raise ValueError(f"mode must be 'overlay' or 'panels', got {mode!r}")
    for r in records:
        L.check_record(r)
    names = [_planner_name(r) for r in records]
    styles = assign_styles(names)
    texts = [
        (labels[i] if labels is not None else (styles[i].label or names[i] or f"run {i}"))
        for i in range(len(records))
    ]
    if show_stats:
        texts = [t + _stats_suffix(r) for t, r in zip(texts, records, strict=True)]
    roi = L.region_of_interest(records, margin=margin)
    wide = _is_wide(roi)
    first = records[0]
    if mode == "overlay":
        if len({r.scenario for r in records}) > 1:
            raise ValueError("overlay needs records of one scenario; use mode='panels'")
        fig = L.new_figure(*L.figure_size(roi, width=8.0 if wide else 6.0, legend_right=not wide))
        ax = fig.add_subplot()
        _draw_scene(ax, first, show_people=show_people, show_social=show_social)
        for i, r in enumerate(records):
            if show_people and i > 0 and _people_differ(first, r):
                for k in range(r.people_positions.shape[1]):
                    ax.plot(
                        *r.people_positions[:, k].T,
                        color=styles[i].color,
                        linestyle=":",
                        linewidth=1.0,
                        alpha=0.7,
                        zorder=5,
                    )
            _draw_robot(
                ax,
                r,
                styles[i],
                texts[i],
                show_people=show_people,
                show_footprint_every=show_footprint_every,
                slot=i,
            )
            L.draw_goals(ax, r, start=i == 0)
        L.finish_map_axes(ax, roi)
        ax.set_title(title if title is not None else _common_title(records), fontsize=10)
        _legend(fig, [ax], wide, first=texts)
        return fig
    n = len(records)
    cols = ncols or (1 if wide else min(n, 3))
    rows = int(np.ceil(n / cols))
    fig = L.new_figure(
        *L.figure_size(roi, width=7.0 if wide else 4.5, legend_right=not wide, cols=cols, rows=rows)
    )
    axes = fig.subplots(rows, cols, sharex=True, sharey=True, squeeze=False).ravel()
    for i, r in enumerate(records):
        ax = axes[i]
        _draw_scene(ax, r, show_people=show_people, show_social=show_social)
        _draw_robot(
            ax,
            r,
            styles[i],
            texts[i],
            show_people=show_people,
            show_footprint_every=show_footprint_every,
        )
        L.draw_goals(ax, r)
        L.finish_map_axes(ax, roi)
        ax.set_title(texts[i], fontsize=9, color=styles[i].color)
        ax.label_outer()
    for ax in axes[n:]:
        ax.set_visible(False)
    if title is not None or len({r.scenario for r in records}) == 1:
        fig.suptitle(title if title is not None else _common_title(records), fontsize=11)
    _legend(fig, list(axes[:n]), wide, first=texts)
    return fig


def save_figure(fig: Figure | Axes, path: str | Path, dpi: int = 200) -> Path:
    """Write ``fig`` (or the figure of an ``Axes``) to ``path``; the format comes from the
    suffix (png, pdf, svg, ...). Parent folders are created. Returns the path."""
    figure = fig.get_figure() if isinstance(fig, Axes) else fig
    if not isinstance(figure, Figure):
        raise ValueError(f"expected a matplotlib Figure or Axes, got {type(fig).__name__}")
    out = Path(path)
    if not out.suffix:
        raise ValueError(f"{out}: give a file suffix (.png, .pdf, .svg) to choose the format")
    out.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(out, dpi=dpi, bbox_inches="tight", pad_inches=0.05)
    return out

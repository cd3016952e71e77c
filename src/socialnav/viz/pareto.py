"""Decision plots: why one trajectory won a control cycle, and social quality vs efficiency.

:func:`plot_decision` follows the paper's "Multi-Objective solution space" figure (Banisetty et
al., section "Multi-objective optimization"): solid markers are the Pareto (non-dominated) points,
hollow markers the dominated ones. A second panel shows the PaCcET-transformed candidates, where
the current front lies on the simplex ``sum(T) = 1`` (as in the PaCcET reference code). Deviations:
objectives are minimized (the paper's illustration maximizes), illegal candidates are drawn as grey
crosses, and with more than two objectives the panels are 2-D projections on a pair of objectives
chosen so that the selected candidate is seen as non-dominated where some pair allows it
(:func:`decision_pair`): a projection in which it looks beaten explains nothing. An objective that
is the same for every candidate is drawn on a narrow axis and labelled as constant, never
stretched over an arbitrary range.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Literal

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from socialnav.viz import _layers as L
from socialnav.viz.style import COLORS, assign_styles

__all__ = ["decision_pair", "plot_decision", "plot_tradeoff"]

_FRONT = "#1f77b4"
_DOMINATED = "#7f9fbf"
_ILLEGAL = "#9a9a9a"


def _as_mask(value: Any, n: int, name: str) -> np.ndarray:
    mask = np.asarray(value)
    if mask.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},), got {mask.shape}")
    return mask.astype(bool)


def _validate(
    F: Any,
    legal: Any,
    nondominated: Any,
    transformed: Any,
    fitness: Any,
    chosen: int | None,
    objective_names: Sequence[str] | None,
    pair: tuple[int, int] | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None, list[str]]:
    F = np.asarray(F, dtype=float)
    if F.ndim != 2 or F.shape[0] == 0 or F.shape[1] < 2:
        raise ValueError(f"F must be a non-empty (N, m) array with m >= 2, got {F.shape}")
    n, m = F.shape
    legal = _as_mask(legal, n, "legal")
    if np.isnan(F[legal]).any():
        raise ValueError("F has NaN in legal rows")
    j, k = (0, 1) if pair is None else pair
    if not (0 <= j < m and 0 <= k < m and j != k):
        raise ValueError(f"pair {pair} must be two different objective indices in [0, {m})")
    names = list(objective_names) if objective_names is not None else [f"f{i}" for i in range(m)]
    if len(names) != m:
        raise ValueError(f"{len(names)} objective names for {m} objectives")
    usable = legal & np.isfinite(F).all(axis=1)
    if nondominated is None:
        nondominated = np.zeros(n, dtype=bool)
        if usable.any():
            from socialnav.moo.nondominated import nondominated_mask

            nondominated[np.flatnonzero(usable)] = nondominated_mask(F[usable])
    else:
        nondominated = _as_mask(nondominated, n, "nondominated")
    T = None
    if transformed is not None:
        T = np.asarray(transformed, dtype=float)
        if T.shape != (n, m):
            raise ValueError(f"transformed must have shape ({n}, {m}), got {T.shape}")
    fit = None
    if fitness is not None:
        fit = np.asarray(fitness, dtype=float)
        if fit.shape != (n,):
            raise ValueError(f"fitness must have shape ({n},), got {fit.shape}")
    if chosen is not None and not 0 <= int(chosen) < n:
        raise ValueError(f"chosen={chosen} out of range for N={n}")
    return F, legal, nondominated, T, fit, names


def _scatter_space(
    ax: Axes,
    X: np.ndarray,
    legal: np.ndarray,
    nondominated: np.ndarray,
    chosen: int | None,
    *,
    colors: np.ndarray | None = None,
    step_front: bool = False,
) -> None:
    """Illegal (grey x), dominated (hollow), non-dominated (solid), chosen (red star)."""
    finite = np.isfinite(X).all(axis=1)
    ill = ~legal & finite
    dom = legal & ~nondominated & finite
    front = legal & nondominated & finite
    if ill.any():
        ax.scatter(
            X[ill, 0],
            X[ill, 1],
            marker="x",
            s=14,
            color=_ILLEGAL,
            linewidths=0.8,
            label=f"illegal ({int(ill.sum())})",
            zorder=2,
        )
    if colors is None:
        if dom.any():
            ax.scatter(
                X[dom, 0],
                X[dom, 1],
                s=18,
                facecolors="none",
                edgecolors=_DOMINATED,
                linewidths=0.8,
                label=f"dominated ({int(dom.sum())})",
                zorder=3,
            )
        if front.any():
            ax.scatter(
                X[front, 0],
                X[front, 1],
                s=30,
                color=_FRONT,
                edgecolors="black",
                linewidths=0.4,
                label=f"non-dominated ({int(front.sum())})",
                zorder=4,
            )
    else:
        sc = None
        for mask, edge, lab in ((dom, "none", "dominated"), (front, "black", "non-dominated")):
            if mask.any():
                sc = ax.scatter(
                    X[mask, 0],
                    X[mask, 1],
                    s=30 if edge == "black" else 18,
                    c=colors[mask],
                    cmap="viridis",
                    edgecolors=edge,
                    linewidths=0.5,
                    vmin=np.nanmin(colors[legal & finite]),
                    vmax=np.nanmax(colors[legal & finite]),
                    label=f"{lab} ({int(mask.sum())})",
                    zorder=3 + (edge != "none"),
                )
        if sc is not None:
            ax.figure.colorbar(
                sc, ax=ax, fraction=0.046, pad=0.02, label="fitness (lower is better)"
            )
    if step_front and front.sum() > 1:
        pts = X[front]
        pts = pts[np.argsort(pts[:, 0])]
        ax.step(
            pts[:, 0], pts[:, 1], where="post", color=_FRONT, linewidth=1.0, alpha=0.7, zorder=3
        )
    if chosen is not None and finite[chosen]:
        ax.scatter(
            [X[chosen, 0]],
            [X[chosen, 1]],
            marker="*",
            s=260,
            color=COLORS["goal"],
            edgecolors="black",
            linewidths=0.8,
            label=f"chosen (#{chosen})",
            zorder=6,
        )
        ax.annotate(
            f"#{chosen}",
            X[chosen],
            xytext=(8, 8),
            textcoords="offset points",
            fontsize=8,
            color=COLORS["goal"],
            zorder=7,
        )


def _dominators(X: np.ndarray, usable: np.ndarray, chosen: int) -> np.ndarray:
    """Mask of usable rows of ``X (N, d)`` that Pareto-dominate row ``chosen`` (minimizing)."""
    points = np.asarray(X)
    ref = points[chosen]
    return usable & np.all(points <= ref, axis=1) & np.any(points < ref, axis=1)


def decision_pair(F: Any, legal: Any, chosen: int | None) -> tuple[int, int]:
    """The two objectives of ``F (N, m)`` to plot so that the decision can be seen.

    Among pairs of objectives that vary over the legal candidates, the one in which the fewest
    candidates dominate ``chosen`` in the 2-D projection (none, whenever some pair allows it),
    then the one with the largest spread (ranges relative to each objective's scale). ``(0, 1)``
    when nothing distinguishes the pairs.
    """
    F = np.asarray(F, dtype=float)
    m = F.shape[1]
    usable = np.asarray(legal, dtype=bool) & np.isfinite(F).all(axis=1)
    if m == 2 or not usable.any():
        return (0, 1)
    spread = np.ptp(F[usable], axis=0) / np.maximum(np.abs(F[usable]).max(axis=0), 1e-12)
    varying = [i for i in range(m) if spread[i] > 1e-9]
    best, best_key = (0, 1), (np.inf, 0.0)
    for j in range(m):
        for k in range(j + 1, m):
            moving = (j in varying) + (k in varying)
            beaten = 0 if chosen is None else int(_dominators(F[:, [j, k]], usable, chosen).sum())
            key = (float(beaten) - moving * 1e6, -(spread[j] + spread[k]))
            if key < best_key:
                best, best_key = (j, k), key
    return best


def _flat_axes(ax: Axes, X: np.ndarray, usable: np.ndarray, names: Sequence[str]) -> None:
    """Narrow limits and a label for a plotted objective that every candidate shares."""
    for dim, name in enumerate(names):
        values = X[usable, dim]
        if values.size == 0 or np.ptp(values) > 1e-9 * max(1.0, float(np.abs(values).max())):
            continue
        value = float(values[0])
        half = 0.1 * abs(value) if value != 0 else 0.05
        text = f"{name} — constant: {value:.3g} for every legal candidate"
        if dim == 0:
            ax.set_xlim(value - half, value + half)
            ax.set_xlabel(text)
        else:
            ax.set_ylim(value - half, value + half)
            ax.set_ylabel(text)


def plot_decision(
    F: Any,
    legal: Any,
    nondominated: Any = None,
    transformed: Any = None,
    chosen: int | None = None,
    objective_names: Sequence[str] | None = None,
    *,
    fitness: Any = None,
    pair: tuple[int, int] | None = None,
    title: str | None = None,
) -> Figure:
    """Why did this candidate win? One control cycle's objective space.

    - ``F (N, m)`` raw objective values (minimized; ``m >= 2``); non-finite rows are not drawn.
    - ``legal (N,)`` bool; ``nondominated (N,)`` bool (default: computed over legal finite rows
      with :func:`socialnav.moo.nondominated.nondominated_mask`).
    - ``transformed (N, m)`` PaCcET coordinates (optional second panel, with the simplex edge
      ``T_j + T_k = 1`` and points coloured by ``fitness (N,)`` when given).
    - ``chosen``: index of the selected candidate (red star), or ``None``.
    - ``pair``: the two objective columns to plot (projection when ``m > 2``); by default
      :func:`decision_pair`, the pair in which the chosen candidate is seen as non-dominated.

    With ``m > 2`` the markers say whether a candidate is dominated in *all* objectives; when the
    chosen candidate is still beaten in the plotted pair, a note names the objectives in which
    those candidates are worse. With ``fitness``, the transformed panel's title gives the chosen
    candidate's rank (PaCcET selects the lowest fitness).

    Returns a :class:`~matplotlib.figure.Figure`. Raises ``ValueError`` on inconsistent shapes,
    NaN in legal rows, an out-of-range ``chosen`` or a bad ``pair``.
    """
    F, legal, nd, T, fit, names = _validate(
        F, legal, nondominated, transformed, fitness, chosen, objective_names, pair
    )
    j, k = decision_pair(F, legal, chosen) if pair is None else pair
    m = F.shape[1]
    usable = legal & np.isfinite(F).all(axis=1)
    panels = 2 if T is not None else 1
    fig = L.new_figure(5.2 * panels + (0.8 if fit is not None else 0.0), 4.6)
    axes = fig.subplots(1, panels, squeeze=False).ravel()
    ax = axes[0]
    _scatter_space(ax, F[:, [j, k]], legal, nd, chosen, step_front=(m == 2))
    ax.set_xlabel(f"{names[j]} (minimize)")
    ax.set_ylabel(f"{names[k]} (minimize)")
    proj = "" if m == 2 else f" — projection of {m} objectives"
    ax.set_title(f"raw objectives{proj}", fontsize=10)
    ax.grid(True, color="#e5e5e5", linewidth=0.5)
    _flat_axes(ax, F[:, [j, k]], usable, [f"{names[j]} (minimize)", f"{names[k]} (minimize)"])
    notes = []
    if m > 2:
        notes.append(f"markers: dominated or not in all {m} objectives")
    if chosen is not None:
        beaten = _dominators(F[:, [j, k]], usable, chosen)
        if beaten.any():
            worse = [
                names[i]
                for i in range(m)
                if i not in (j, k) and np.any(F[beaten, i] > F[chosen, i])
            ]
            notes.append(
                f"the {int(beaten.sum())} candidates that beat #{chosen} here are worse in "
                + (", ".join(worse) or "no objective (ties)")
            )
    if notes:
        ax.text(
            0.01,
            0.99,
            "\n".join(notes),
            transform=ax.transAxes,
            ha="left",
            va="top",
            fontsize=7,
            color="#444444",
            zorder=8,
        )
    hidden = int((~np.isfinite(F[:, [j, k]]).all(axis=1)).sum())
    if hidden:
        ax.text(
            0.99,
            0.01,
            f"{hidden} non-finite rows not shown",
            transform=ax.transAxes,
            ha="right",
            va="bottom",
            fontsize=7,
            color=_ILLEGAL,
        )
    ax.legend(fontsize=8, loc="best", framealpha=0.85)
    if T is not None:
        ax2 = axes[1]
        colors = None
        if fit is not None and np.isfinite(fit[legal]).any():
            colors = np.where(np.isfinite(fit), fit, np.nan)
        _scatter_space(ax2, T[:, [j, k]], legal, nd, chosen, colors=colors)
        ax2.plot(
            [0.0, 1.0],
            [1.0, 0.0],
            color="black",
            linestyle="--",
            linewidth=1.0,
            label=f"simplex {'ΣT = 1' if m == 2 else f'edge T{j}+T{k} = 1'}",
            zorder=1,
        )
        ax2.set_xlabel(f"T[{names[j]}]")
        ax2.set_ylabel(f"T[{names[k]}]")
        heading = "PaCcET-transformed"
        if fit is not None and chosen is not None and np.isfinite(fit[chosen]):
            # PaCcET picks the lowest fitness among the non-dominated (archive) candidates
            pool = usable & np.isfinite(fit) & (nd if nd[chosen] else True)
            rank = 1 + int(np.sum(fit[pool] < fit[chosen]))
            among = f"the {int(pool.sum())} non-dominated" if nd[chosen] else "the legal"
            if rank == 1:
                heading += f":\n#{chosen} has the lowest fitness of {among}"
            else:
                heading += f":\n#{chosen} has fitness rank {rank} of {among}"
        ax2.set_title(heading, fontsize=10)
        # the simplex (and every point) in view, however flat the transformed values are
        TX = T[:, [j, k]][usable & np.isfinite(T[:, [j, k]]).all(axis=1)]
        lo = np.minimum(0.0, TX.min(axis=0)) if TX.size else np.zeros(2)
        hi = np.maximum(1.0, TX.max(axis=0)) if TX.size else np.ones(2)
        pad = 0.05 * (hi - lo)
        ax2.set_xlim(lo[0] - pad[0], hi[0] + pad[0])
        ax2.set_ylim(lo[1] - pad[1], hi[1] + pad[1])
        ax2.set_aspect("equal", adjustable="box")
        ax2.grid(True, color="#e5e5e5", linewidth=0.5)
        ax2.legend(fontsize=8, loc="best", framealpha=0.85)
    if title is not None:
        fig.suptitle(title, fontsize=11)
    return fig


def plot_tradeoff(
    rows: Sequence[Mapping[str, Any]],
    xlabel: str,
    ylabel: str,
    *,
    x: str = "x",
    y: str = "y",
    xerr: str = "xerr",
    yerr: str = "yerr",
    group: str = "planner",
    annotate: str | None = "label",
    x_better: Literal["min", "max"] | None = None,
    y_better: Literal["min", "max"] | None = None,
    title: str | None = None,
) -> Figure:
    """Social quality vs efficiency: one marker (and colour) per planner.

    ``rows``: mappings with ``group`` (planner name), ``x``, ``y`` and optionally ``xerr``,
    ``yerr`` (error bars, e.g. std over seeds) and ``annotate`` (a text next to the point,
    e.g. the scenario). Rows with NaN ``x``/``y`` (undefined metrics) are skipped and counted in
    a footnote. ``x_better``/``y_better`` add "better" arrows to the axis labels.
    Raises ``ValueError`` on no rows or rows missing ``group``/``x``/``y``.
    """
    rows = list(rows)
    if not rows:
        raise ValueError("plot_tradeoff needs at least one row")
    for i, row in enumerate(rows):
        missing = [key for key in (group, x, y) if key not in row]
        if missing:
            raise ValueError(f"row {i} lacks {missing}")
    names = list(dict.fromkeys(str(r[group]) for r in rows))
    styles = dict(zip(names, assign_styles(list(names)), strict=True))
    fig = L.new_figure(6.4, 4.6)
    ax = fig.add_subplot()
    skipped = 0
    for name in names:
        st = styles[name]
        sel = [r for r in rows if str(r[group]) == name]
        xs = np.array([float(r[x]) for r in sel])
        ys = np.array([float(r[y]) for r in sel])
        ok = np.isfinite(xs) & np.isfinite(ys)
        skipped += int((~ok).sum())
        if not ok.any():
            continue
        xe = np.array([float(r.get(xerr, np.nan)) for r in sel])
        ye = np.array([float(r.get(yerr, np.nan)) for r in sel])
        ax.errorbar(
            xs[ok],
            ys[ok],
            xerr=np.where(np.isfinite(xe), xe, 0.0)[ok] if np.isfinite(xe).any() else None,
            yerr=np.where(np.isfinite(ye), ye, 0.0)[ok] if np.isfinite(ye).any() else None,
            fmt=st.marker,
            color=st.color,
            markersize=8,
            markeredgecolor="black",
            markeredgewidth=0.6,
            ecolor=st.color,
            elinewidth=1.0,
            capsize=3,
            linestyle="none",
            label=st.label or name,
            zorder=3,
        )
        if annotate is not None:
            for r, xv, yv, good in zip(sel, xs, ys, ok, strict=True):
                if good and r.get(annotate) is not None:
                    ax.annotate(
                        str(r[annotate]),
                        (xv, yv),
                        xytext=(5, 4),
                        textcoords="offset points",
                        fontsize=7,
                        color="#444444",
                    )
    arrow = {"min": "← better", "max": "better →"}
    ax.set_xlabel(xlabel + (f"   ({arrow[x_better]})" if x_better else ""))
    ylab_arrow = {"min": "↓ better", "max": "↑ better"}
    ax.set_ylabel(ylabel + (f"   ({ylab_arrow[y_better]})" if y_better else ""))
    ax.grid(True, color="#e5e5e5", linewidth=0.5)
    if ax.get_legend_handles_labels()[0]:  # every row may have been skipped (NaN)
        ax.legend(fontsize=8, framealpha=0.85)
    if skipped:
        ax.text(
            0.99,
            0.01,
            f"{skipped} rows with undefined values not shown",
            transform=ax.transAxes,
            ha="right",
            va="bottom",
            fontsize=7,
            color=_ILLEGAL,
        )
    if title is not None:
        ax.set_title(title, fontsize=10)
    return fig

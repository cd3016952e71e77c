"""Animations of recorded episodes: robot and people moving, optionally with the planner's
candidate fan (every rollout coloured by its fitness, the chosen one highlighted).

The fan mirrors the paper's "Navigation Planner" figure (Banisetty et al., section
"Methodology": candidate trajectory end points, the selected one highlighted). Deviations: whole
rollouts are drawn (not only end points) when the diagnostics carry them, and the colour is the
candidate's fitness relative to the best legal one in that cycle (0 = best, 1 = worst legal),
because absolute PaCcET fitness values are not comparable between cycles.

Frames are rendered with the Agg canvas and written with Pillow (GIF) or the ffmpeg shipped in
``imageio-ffmpeg`` (MP4, optional extra ``video``).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from matplotlib import colormaps
from matplotlib.collections import LineCollection
from matplotlib.colors import Normalize
from matplotlib.patches import Circle, Polygon

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import FloatArray
from socialnav.planner.record import EvaluationRecord
from socialnav.viz import _layers as L
from socialnav.viz.style import COLORS, planner_style

__all__ = ["FanFrame", "animate_episode", "fan_frame"]

#: Colormap of the fan: dark = best legal fitness, yellow = worst legal.
FAN_CMAP = "viridis"


@dataclass(frozen=True)
class FanFrame:
    """One control cycle's candidates, as the animation draws them.

    - ``poses (N, S, 2)``: world ``xy`` along each rollout (``S = 1``: end points only). Also
      accepted on construction: ``(N, S, 3)`` poses (yaw dropped), ``(N, 2)`` or ``(N, 3)`` end
      points.
    - ``fitness (N,)``: lower is better; ``+inf`` (or NaN) for illegal candidates.
    - ``legal (N,)`` bool; defaults to ``isfinite(fitness)`` when built by :func:`to_fan_frame`.
    - ``chosen``: index of the executed candidate, or ``None`` (no legal candidate).

    Raises ``ValueError`` on inconsistent shapes, non-finite poses or an out-of-range ``chosen``.
    """

    poses: FloatArray
    fitness: FloatArray
    legal: np.ndarray
    chosen: int | None = None

    def __post_init__(self) -> None:
        p = np.asarray(self.poses, dtype=float)
        if p.ndim == 2:
            p = p[:, None, :]
        if p.ndim != 3 or p.shape[-1] not in (2, 3) or p.shape[1] == 0:
            raise ValueError(
                f"FanFrame.poses must be (N, S, 2|3) or (N, 2|3), got {np.shape(self.poses)}"
            )
        p = np.ascontiguousarray(p[..., :2])
        n = p.shape[0]
        if not np.all(np.isfinite(p)):
            raise ValueError("FanFrame.poses contain NaN or inf")
        f = np.asarray(self.fitness, dtype=float).reshape(-1)
        legal = np.asarray(self.legal, dtype=bool).reshape(-1)
        if f.shape != (n,) or legal.shape != (n,):
            raise ValueError(
                f"FanFrame: fitness {f.shape} and legal {legal.shape} must both be ({n},)"
            )
        chosen = self.chosen
        if chosen is not None:
            chosen = int(chosen)
            if not 0 <= chosen < n:
                raise ValueError(f"FanFrame.chosen={chosen} out of range for N={n}")
        object.__setattr__(self, "poses", p)
        object.__setattr__(self, "fitness", f)
        object.__setattr__(self, "legal", legal)
        object.__setattr__(self, "chosen", chosen)

    def relative_fitness(self) -> FloatArray:
        """``(N,)`` fitness mapped to [0, 1] over legal finite candidates (0 = best); NaN for
        the rest. All-equal fitness maps to 0."""
        ok = self.legal & np.isfinite(self.fitness)
        out = np.full(self.fitness.shape, np.nan)
        if ok.any():
            lo, hi = self.fitness[ok].min(), self.fitness[ok].max()
            out[ok] = (self.fitness[ok] - lo) / (hi - lo) if hi > lo else 0.0
        return out


def fan_frame(record: EvaluationRecord | None) -> FanFrame | None:
    """The candidate fan of one control cycle, from the planner's evaluation record.

    ``record.end_poses (N, 3)`` become the fan's end points (``S = 1``; whole rollouts are not
    recorded), ``record.fitness (N,)``, ``record.legal (N,)`` and ``record.chosen`` are taken
    as they are. Returns ``None`` for a cycle that evaluated no candidates or selected none by
    fitness (no record, goal reached, a recovery step, rotate-to-goal without selection).
    """
    if record is None or record.num_samples == 0 or record.fitness is None:
        return None
    if record.end_poses.shape[0] != record.num_samples or record.legal.shape != (
        record.num_samples,
    ):
        return None
    return FanFrame(record.end_poses[:, :2], record.fitness, record.legal, record.chosen)


def _thin(n: int, chosen: int | None, limit: int) -> np.ndarray:
    """At most ``limit`` evenly spaced candidate indices, always keeping ``chosen``."""
    if n <= limit:
        return np.arange(n)
    idx = np.unique(np.linspace(0, n - 1, limit).round().astype(int))
    if chosen is not None:
        idx = np.union1d(idx, [chosen])
    return idx


def frame_indices(num_steps: int, stride: int | None, max_frames: int) -> np.ndarray:
    """Sample indices to render: every ``stride``-th (default 2 for long episodes), at most
    ``max_frames`` (stride grows), always ending on the last sample."""
    if max_frames < 2:
        raise ValueError(f"max_frames must be >= 2, got {max_frames}")
    if stride is None:
        stride = 2 if num_steps > 40 else 1
    if stride < 1:
        raise ValueError(f"stride must be >= 1, got {stride}")
    stride = max(stride, math.ceil(num_steps / (max_frames - 1)))
    idx = np.arange(0, num_steps, stride)
    if idx[-1] != num_steps - 1:
        idx = np.append(idx, num_steps - 1)
    return idx


def _format(path: Path, fmt: str | None) -> str:
    f = (fmt or path.suffix.lstrip(".")).lower()
    if f not in ("gif", "mp4"):
        raise ValueError(f"unsupported animation format {f!r}: use 'gif' or 'mp4'")
    return f


def animate_episode(
    record: EpisodeRecord,
    fans: Sequence[FanFrame | None] | None = None,
    path: str | os.PathLike[str] | None = None,
    *,
    fps: float = 10.0,
    fmt: Literal["gif", "mp4"] | None = None,
    stride: int | None = None,
    max_frames: int = 150,
    max_candidates: int = 300,
    dpi: int = 80,
    show_social: bool = True,
    margin: float = 1.0,
) -> Path:
    """Render ``record`` as an animation at ``path`` (required) and return the path.

    Call as ``animate_episode(record, fans, path)`` or
    ``animate_episode(record, path=...)``; ``animate_episode(record, path)`` also works.

    ``fans[i]`` (optional) belongs to sample ``i`` of the record: ``None`` or a
    :class:`FanFrame` (:func:`fan_frame` builds one from an evaluation record); the fan is drawn
    coloured by relative fitness, illegal candidates grey, the chosen one black. Frames are
    every ``stride``-th sample (default 2 on episodes longer than 40 samples) with at most
    ``max_frames`` frames; playback runs ``fps * dt * stride`` times real time. ``fmt``
    defaults to the path suffix: ``gif`` (Pillow) or ``mp4`` (needs ``imageio-ffmpeg``,
    ``pip install 'socialnav[video]'``; ``ImportError`` otherwise).

    Raises ``ValueError`` on an empty record, a missing path, an unknown format, ``fps <= 0``
    or more fans than the record has samples.
    """
    L.check_record(record)
    if isinstance(fans, str | os.PathLike):
        if path is not None:
            raise ValueError("fans must be a sequence, got a path (and a path was given)")
        fans, path = None, fans
    if path is None:
        raise ValueError("animate_episode needs an output path (.gif or .mp4)")
    out = Path(path)
    kind = _format(out, fmt)
    if not fps > 0:
        raise ValueError(f"fps must be positive, got {fps}")
    if fans is not None and len(fans) > record.num_steps:
        raise ValueError(f"{len(fans)} fans for a record of {record.num_steps} samples")
    ffmpeg: Any = None
    if kind == "mp4":
        try:
            import imageio_ffmpeg

            ffmpeg = imageio_ffmpeg
        except ImportError as exc:
            raise ImportError(
                "writing MP4 needs imageio-ffmpeg: pip install 'socialnav[video]' "
                "(or write a GIF with fmt='gif')"
            ) from exc
    frames = frame_indices(record.num_steps, stride, max_frames)
    shown = [fans[i] if fans is not None and i < len(fans) else None for i in frames]
    images = _render(
        record,
        frames,
        shown,
        dpi=dpi,
        show_social=show_social,
        margin=margin,
        max_candidates=max_candidates,
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    if kind == "gif":
        _write_gif(images, out, fps)
    else:
        _write_mp4(images, out, fps, ffmpeg)
    return out


def _render(
    record: EpisodeRecord,
    frames: np.ndarray,
    fans: list[FanFrame | None],
    *,
    dpi: int,
    show_social: bool,
    margin: float,
    max_candidates: int,
) -> list[np.ndarray]:
    """RGB frames ``(H, W, 3)`` uint8, all the same size."""
    style = planner_style(
        None if record.meta.get("planner") is None else str(record.meta["planner"])
    )
    roi = L.region_of_interest([record], margin=margin)
    w, h = L.figure_size(roi, width=6.0, legend_right=False)
    fig = L.new_figure(w + (1.0 if any(f is not None for f in fans) else 0.0), h - 1.1)
    fig.dpi = dpi
    ax = fig.add_subplot()
    # Static background: map, social geometry, faint full tracks, goals.
    L.draw_map(ax, record)
    if show_social:
        L.draw_social(ax, record)
    ax.plot(*record.robot_xy.T, color=style.color, alpha=0.25, linewidth=1.0, zorder=4)
    for k in range(record.people_positions.shape[1]):
        ax.plot(
            *record.people_positions[:, k].T,
            color=COLORS["person"],
            linestyle=":",
            alpha=0.5,
            linewidth=1.0,
            zorder=4,
        )
    L.draw_goals(ax, record)
    L.finish_map_axes(ax, roi)
    title = ax.set_title("", fontsize=9)
    # Dynamic artists.
    fp = np.asarray(record.robot_footprint, dtype=float)
    if fp.ndim != 2 or fp.shape[0] < 3:
        fp = record.robot_radius * np.array([[1, 0], [0, 1], [-1, 0], [0, -1]], dtype=float)
    body = ax.add_patch(
        Polygon(
            fp,
            closed=True,
            facecolor=style.color,
            alpha=0.45,
            edgecolor=style.color,
            linewidth=1.5,
            zorder=10,
        )
    )
    (trail,) = ax.plot(
        [], [], color=style.color, linestyle=style.linestyle, linewidth=2.0, zorder=9
    )
    (nose,) = ax.plot([], [], color="black", linewidth=1.5, zorder=11)
    K = record.people_positions.shape[1]
    bodies = [
        ax.add_patch(
            Circle(
                (0, 0),
                float(record.people_radii[k]),
                facecolor=COLORS["person"],
                edgecolor="black",
                linewidth=0.6,
                alpha=0.85,
                zorder=10,
            )
        )
        for k in range(K)
    ]
    spaces = [
        ax.add_patch(
            Circle(
                (0, 0),
                L.PERSONAL_SPACE,
                facecolor=COLORS["person"],
                alpha=0.07,
                edgecolor=COLORS["person"],
                linewidth=0.8,
                zorder=2,
            )
        )
        for k in range(K)
    ]
    cmap = colormaps[FAN_CMAP]
    fan = LineCollection([], linewidths=0.8, zorder=8)
    ax.add_collection(fan, autolim=False)
    ends = ax.scatter([], [], s=6, zorder=8)
    (best,) = ax.plot([], [], color="black", linewidth=2.4, zorder=9.5)
    if any(f is not None for f in fans):
        sm = fig.colorbar(
            _scalar_mappable(cmap),
            ax=ax,
            fraction=0.04,
            pad=0.02,
            label="relative fitness (0 = best legal)",
        )
        sm.ax.tick_params(labelsize=7)
    hit = np.asarray(record.collision_person, bool) | np.asarray(record.collision_obstacle, bool)
    images: list[np.ndarray] = []
    canvas = fig.canvas
    for i, fan_frame in zip(frames, fans, strict=True):
        pose = record.robot_poses[i]
        body.set_xy(L.footprints(pose[None], fp)[0])
        body.set_edgecolor(COLORS["collision"] if hit[i] else style.color)
        trail.set_data(record.robot_xy[: i + 1, 0], record.robot_xy[: i + 1, 1])
        reach = max(0.3, float(record.robot_radius))
        nose.set_data(
            [pose[0], pose[0] + reach * np.cos(pose[2])],
            [pose[1], pose[1] + reach * np.sin(pose[2])],
        )
        for k in range(K):
            p = record.people_positions[i, k]
            visible = bool(np.all(np.isfinite(p)))
            bodies[k].set_visible(visible)
            spaces[k].set_visible(visible)
            if visible:
                bodies[k].set_center(p)
                spaces[k].set_center(p)
        _update_fan(fan, ends, best, fan_frame, cmap, max_candidates)
        status = "" if record.status is None else f"  [{record.status[i]}]"
        title.set_text(f"{record.scenario} — t = {record.times[i]:5.1f} s{status}")
        canvas.draw()
        if not images:
            # Freeze the layout after the first frame so axes never jump between frames.
            fig.set_layout_engine("none")
        images.append(np.asarray(canvas.buffer_rgba())[..., :3].copy())
    return images


def _scalar_mappable(cmap: Any) -> Any:
    from matplotlib.cm import ScalarMappable

    return ScalarMappable(norm=Normalize(0.0, 1.0), cmap=cmap)


def _update_fan(
    fan: LineCollection,
    ends: Any,
    best: Any,
    frame: FanFrame | None,
    cmap: Any,
    max_candidates: int,
) -> None:
    if frame is None:
        fan.set_segments([])
        ends.set_offsets(np.empty((0, 2)))
        best.set_data([], [])
        return
    idx = _thin(frame.poses.shape[0], frame.chosen, max_candidates)
    rel = frame.relative_fitness()[idx]
    colors = np.where(
        np.isnan(rel)[:, None], np.array([[0.72, 0.72, 0.72, 0.5]]), cmap(np.nan_to_num(rel))
    )
    fan.set_segments(list(frame.poses[idx]))
    fan.set_colors(colors)
    fan.set_linewidths(np.where(np.isnan(rel), 0.5, 0.9))
    ends.set_offsets(frame.poses[idx, -1])
    ends.set_facecolors(colors)
    ends.set_edgecolors("none")
    if frame.chosen is None:
        best.set_data([], [])
    else:
        c = frame.poses[frame.chosen]
        best.set_data(c[:, 0], c[:, 1])


def _write_gif(images: list[np.ndarray], path: Path, fps: float) -> None:
    from PIL import Image

    # One palette for all frames, built from a strip of sampled frames (so the fan's colours
    # are in it): consecutive frames then differ only where something moved, and Pillow
    # stores just that region, which keeps long GIFs small.
    picks = np.unique(np.linspace(0, len(images) - 1, min(len(images), 8)).round().astype(int))
    strip = Image.fromarray(np.concatenate([images[i] for i in picks], axis=0))
    palette = strip.quantize(colors=192, method=Image.Quantize.MEDIANCUT)
    pil = [Image.fromarray(im).quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    pil[0].save(
        path,
        format="GIF",
        save_all=True,
        append_images=pil[1:],
        duration=max(20, round(1000.0 / fps)),
        loop=0,
    )


def _write_mp4(images: list[np.ndarray], path: Path, fps: float, ffmpeg: Any) -> None:
    # Pad with white to a multiple of 16 px so ffmpeg does not rescale (macro blocks).
    h, w = images[0].shape[:2]
    H, W = -(-h // 16) * 16, -(-w // 16) * 16
    writer = ffmpeg.write_frames(
        str(path), (W, H), fps=fps, codec="libx264", pix_fmt_in="rgb24", pix_fmt_out="yuv420p"
    )
    writer.send(None)
    try:
        for im in images:
            padded = np.full((H, W, 3), 255, dtype=np.uint8)
            padded[:h, :w] = im
            writer.send(np.ascontiguousarray(padded))
    finally:
        writer.close()

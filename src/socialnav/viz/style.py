"""Colours and line styles shared by every socialnav figure.

The paper's result figures (Banisetty et al., section "Results") draw the traditional ROS planner
dashed green (red in the queue figure), the PaCcET planner solid blue, people as dotted magenta
tracks and directions as arrows. Planner colours here are keyed by planner *name*, so the same
planner has the same colour in every figure of a report.
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass

__all__ = [
    "COLORS",
    "PLANNER_STYLES",
    "PathStyle",
    "assign_styles",
    "planner_style",
]


@dataclass(frozen=True)
class PathStyle:
    """How one planner's robot path is drawn: matplotlib ``color``, ``linestyle``, ``marker``
    (for scatter plots) and a display ``label``."""

    color: str
    linestyle: str = "-"
    marker: str = "o"
    label: str | None = None


#: Scene colours (people magenta as in the paper; the given goal is a red star).
COLORS: dict[str, str] = {
    "wall": "#2b2b2b",
    "obstacle": "#6b6b6b",
    "person": "#c51bc5",
    "personal_space": "#c51bc5",
    "o_space": "#e8a317",
    "group_circle": "#9c6b00",
    "activity": "#ff7f0e",
    "queue_band": "#d62728",
    "queue_line": "#7f7f7f",
    "artwork": "#8b5a00",
    "goal": "#d62728",
    "target": "#ffd21f",
    "waypoint": "#17becf",
    "start": "#000000",
    "collision": "#d62728",
}

#: Known planners (lower-case names). Unknown names get a stable colour from ``_FALLBACK``.
PLANNER_STYLES: dict[str, PathStyle] = {
    "traditional": PathStyle("#2ca02c", "--", "s", "traditional"),
    "paccet": PathStyle("#1f77b4", "-", "o", "PaCcET"),
    "weighted_sum": PathStyle("#ff7f0e", "-.", "^", "weighted sum"),
    "irl": PathStyle("#9467bd", ":", "v", "IRL"),
    "orca": PathStyle("#8c564b", "-.", "D", "ORCA"),
    "hl": PathStyle("#17becf", "-.", "P", "HL"),
    "straight_line": PathStyle("#555555", ":", "x", "straight line (reference)"),
    "socialforce": PathStyle("#bcbd22", "-.", "X", "social force"),
    "social_force": PathStyle("#bcbd22", "-.", "X", "social force"),
}

# No magenta (people) and no pure red (goal) among the fallbacks.
_FALLBACK: tuple[str, ...] = (
    "#8c564b",
    "#17becf",
    "#bcbd22",
    "#7f7f7f",
    "#9467bd",
    "#ff7f0e",
    "#1a9850",
    "#4575b4",
)
_FALLBACK_MARKERS: tuple[str, ...] = ("o", "s", "^", "v", "D", "P", "X", "h")


def planner_style(name: str | None) -> PathStyle:
    """The style of a planner name: exact match in :data:`PLANNER_STYLES`, then a known name
    contained in ``name`` (``"paccet_social"`` → PaCcET blue), else a stable hashed colour."""
    key = (name or "robot").strip().lower()
    if key in PLANNER_STYLES:
        return PLANNER_STYLES[key]
    for known, style in PLANNER_STYLES.items():
        if known in key and len(known) > 2:  # "hl" is too short to match inside other names
            return PathStyle(style.color, style.linestyle, style.marker, name)
    h = zlib.crc32(key.encode())  # stable across runs, unlike hash()
    return PathStyle(
        _FALLBACK[h % len(_FALLBACK)], "-", _FALLBACK_MARKERS[h % len(_FALLBACK_MARKERS)], name
    )


def assign_styles(names: list[str | None]) -> list[PathStyle]:
    """Styles for several planners drawn together: :func:`planner_style` per name, then
    distinct names that collide on a colour get the next unused fallback colour."""
    styles: list[PathStyle] = []
    used: dict[str, str] = {}  # colour -> the name holding it
    for name in names:
        style = planner_style(name)
        key = (name or "robot").strip().lower()
        if style.color in used and used[style.color] != key:
            free = [c for c in _FALLBACK if c not in used]
            if free:
                style = PathStyle(free[0], style.linestyle, style.marker, style.label)
        used.setdefault(style.color, key)
        styles.append(style)
    return styles

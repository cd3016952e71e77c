"""Layer 4: pictures — top-down episode plots, animations and multi-objective decision plots.

Everything draws on :class:`matplotlib.figure.Figure` objects with the Agg canvas; nothing touches
pyplot's global state, so the module is safe in workers and headless CI.
"""

from socialnav.viz.animation import FanFrame, animate_episode, fan_frame
from socialnav.viz.pareto import plot_decision, plot_tradeoff
from socialnav.viz.style import PLANNER_STYLES, PathStyle, planner_style
from socialnav.viz.topdown import plot_comparison, plot_episode, save_figure

__all__ = [
    "PLANNER_STYLES",
    "FanFrame",
    "PathStyle",
    "animate_episode",
    "fan_frame",
    "planner_style",
    "plot_comparison",
    "plot_decision",
    "plot_episode",
    "plot_tradeoff",
    "save_figure",
]

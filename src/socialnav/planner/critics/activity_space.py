"""Activity-space critic: keep out of the space between a viewer and an artwork.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach",
section "Results / art gallery": the robot should not traverse the activity space between a
person and the art they look at. The paper gives no formula; this critic is the project's.

Cost per trajectory, from the robot centre's signed distance ``s`` to each activity-space
trapezoid (:func:`socialnav.social.spaces.activity_space_polygon`, viewer shoulders ±``shoulder``
to the artwork's ends), with intrusion depth ``δ = max(margin − s, 0)`` (m; the space is grown
by ``margin``):
- ``measure="max_depth"`` (default): ``max_t δ`` (m);
- ``"time"``: time spent inside (s; a step counts when its start sample is inside);
- ``"depth_time"``: ``Σ δ·Δt`` (m·s).
0 outside every space. ``illegal_inside=True`` declares intruding trajectories illegal
(reason ``activity_space_intrusion``) — from inside a space (the robot starts there, or a viewer
stepped around it), only those that get deeper than now, so the robot can always leave.
Spaces come from the viewers' current positions.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Literal

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray, signed_distance_to_polygon
from socialnav.core.scene import SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner.critics.base import CRITICS, ESCAPE_TOLERANCE, Critic, CriticScore
from socialnav.social.spaces import activity_space_polygon

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


def activity_spaces(social: SocialContext, shoulder: float = 0.3) -> list[FloatArray]:
    """One ``(4, 2)`` trapezoid per (artwork, viewer) pair in ``social``."""
    return [
        activity_space_polygon(a.center, a.width, a.facing, social.person(v).position, shoulder)
        for a in social.artworks
        for v in a.viewer_ids
    ]


@CRITICS.register("activity_space")
@dataclass(frozen=True)
class ActivitySpaceCritic(Critic):
    """Intrusion into artworks' activity spaces (module docstring).

    Parameters: ``measure`` (``max_depth`` m | ``time`` s | ``depth_time`` m·s), ``margin`` (m),
    ``shoulder`` (m), ``illegal_inside`` (bool).
    """

    name: ClassVar[str] = "activity_space"
    unit: ClassVar[str] = "m (max_depth) | s (time) | m·s (depth_time)"

    measure: Literal["max_depth", "time", "depth_time"] = "max_depth"
    margin: float = 0.0
    shoulder: float = 0.3
    illegal_inside: bool = False

    def __post_init__(self) -> None:
        if self.measure not in ("max_depth", "time", "depth_time"):
            raise ConfigurationError(f"activity_space: unknown measure {self.measure!r}")
        if self.margin < 0 or self.shoulder < 0:
            raise ConfigurationError("activity_space: margin and shoulder must be >= 0")

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Raw cost ``(N,)`` and illegal masks of the batch (see the class docstring)."""
        n = len(trajs)
        polys = activity_spaces(ctx.social, self.shoulder)
        if not polys:
            return CriticScore(np.zeros(n))
        xy = trajs.xy
        depth = np.zeros(xy.shape[:2])  # (N, T)
        for poly in polys:
            # only points in the polygon's bounding box grown by the margin can intrude
            lo, hi = poly.min(axis=0) - self.margin, poly.max(axis=0) + self.margin
            near = np.all((xy >= lo) & (xy <= hi), axis=-1)
            if near.any():
                s = signed_distance_to_polygon(xy[near], poly)
                depth[near] = np.maximum(depth[near], self.margin - s)
        depth = np.maximum(depth, 0.0)
        # Escape (module docstring): inside, only deeper than now (+ ESCAPE_TOLERANCE) intrudes.
        now = 0.0
        if self.illegal_inside:
            here = np.asarray(ctx.pose[:2], dtype=float)[None]
            now = max(self.margin - float(signed_distance_to_polygon(here, p)[0]) for p in polys)
            now = now + ESCAPE_TOLERANCE if now > 0 else 0.0
        dt = np.append(np.diff(trajs.t), 0.0)  # (T,)
        if self.measure == "max_depth":
            cost = depth.max(axis=1)
        elif self.measure == "time":
            cost = (depth > 0) @ dt
        else:
            cost = depth @ dt
        illegal = (
            {"activity_space_intrusion": np.asarray((depth > now).any(axis=1))}
            if self.illegal_inside
            else {}
        )
        return CriticScore(np.asarray(cost, dtype=float), illegal)

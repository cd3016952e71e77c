"""Heading critic: how far the trajectory's final yaw is from the way the plan goes.

Banisetty et al., eq. "Cost function", term γ·Δ_heading (``Compute_Heading_Diff``); the paper's
prose ("the distance that the robot is from the global path") duplicates Δ_path, so this follows
ROS ``base_local_planner`` ``heading_scoring`` (``TrajectoryPlanner::headingDiff``) instead.

Exact definition (rad, in ``[0, pi]``), evaluated at the end pose ``(x, y, yaw)``:
1. ``i`` = nearest vertex of the global plan (densified to ``spacing`` m) to ``(x, y)``;
2. ``j`` = the first vertex at least ``heading_lookahead`` m further along the plan (or the last);
3. the desired direction is ``atan2`` of plan[j] − (x, y), or — when that point is closer than
   ``heading_lookahead / 2`` (at the end of the plan) — the plan's tangent at ``j``;
4. cost = ``|wrap(yaw − desired)|``.
Deviation from ROS: ROS picks the furthest plan point in line of sight (a costmap ray test per
sample); the look-ahead point along the plan needs no ray casting and is vectorized.
Near the goal (the robot within ``near_goal`` m of it) the cost is 0: the plan's last few cells
point in arbitrary directions there, and chasing them made the robot dither short of the goal
(the "oscillation at the goal" users report); Nav2 likewise drops its alignment critics near the
goal, and the goal-handling stage turns the robot to the goal yaw.

With ``goal_align`` (off in ROS; on in the ``paccet`` preset), for a holonomic base, the goal's
yaw takes the place of those cells: the tangent at the plan's last vertex, where the plan ends
at the goal, is the goal's yaw (a plan ends at a pose, as Nav2's do; the grid's last segment
points anywhere), and near the goal the cost is ``|wrap(yaw − goal yaw)|`` (Nav2 MPPI
``GoalAngleCritic``, whose ``threshold_to_consider`` is 0.5 m too). The base then turns to the
goal's yaw while it drives in instead of turning in place after arriving. Not at a social
waypoint the robot passes through (``steers_to_waypoint``): its yaw is not an end pose. Not for
a differential drive, which can only turn while it drives by bending its path: in the recorded
crowds that cost the Pioneer time and successes (measurements at
``presets.RECOMMENDED_PARAMS``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from socialnav.core.geometry import wrap_angle
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
from socialnav.planner.cache import HeadingPlan
from socialnav.planner.critics.base import CRITICS, Critic, CriticScore, CriticUnavailable
from socialnav.planner.critics.map_grid import densify_path

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


@CRITICS.register("heading")
@dataclass(frozen=True)
class HeadingCritic(Critic):
    """``heading_lookahead`` (m) along the plan; ``spacing`` (m) of the densified plan;
    ``near_goal`` (m): no heading cost within this distance of the goal, or with ``goal_align``
    the heading error to the goal's yaw."""

    name: ClassVar[str] = "heading"
    unit: ClassVar[str] = "rad"

    heading_lookahead: float = 0.325
    spacing: float = 0.05
    near_goal: float = 0.5
    goal_align: bool = False

    def __post_init__(self) -> None:
        if not (self.heading_lookahead > 0 and self.spacing > 0):
            raise ValueError("heading_lookahead and spacing must be positive")

    def _aligns(self, ctx: PlanningContext) -> bool:
        return self.goal_align and ctx.robot.holonomic and not ctx.steers_to_waypoint()

    def prepare(self, ctx: PlanningContext) -> None:
        """Densify the plan near the robot and its tangents (per cycle)."""
        if ctx.cache.heading_plan is not None:
            return
        path = np.asarray(ctx.global_path, dtype=float).reshape(-1, 2)
        if path.shape[0] == 0:
            raise CriticUnavailable("empty global plan")
        dense = densify_path(path, self.spacing)
        reach = ctx.cache.reach
        horizon = float(np.inf if reach is None else reach) + 2.0 + self.heading_lookahead
        if kernels.enabled() and dense.dtype == np.float64 and np.isfinite(dense).all():
            # One pass for the arc lengths; they never decrease, so the kept vertices are a
            # prefix (the same ones as the mask below).
            s = kernels.arc_lengths(dense)
            kept = max(int(np.searchsorted(s, horizon, side="right")), 1)
            dense, s = dense[:kept].copy(), s[:kept].copy()
        else:
            s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
            keep = s <= horizon
            keep[0] = True
            dense, s = dense[keep], s[keep]
        # Tangent at each vertex: direction of the segment arriving at it (first: leaving it).
        if dense.shape[0] > 1:
            d = np.diff(dense, axis=0)
            seg = np.arctan2(d[:, 1], d[:, 0])
            tangent = np.concatenate([seg[:1], seg])
        else:
            tangent = np.array([float(ctx.goal[2])])
        if self._aligns(ctx) and np.hypot(*(dense[-1] - ctx.goal[:2])) <= self.spacing:
            tangent[-1] = float(ctx.goal[2])
        ctx.cache.heading_plan = HeadingPlan(dense, s, tangent)

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Heading error (rad) ``(N,)`` of each end pose against the plan ahead."""
        if np.hypot(*(np.asarray(ctx.pose[:2]) - np.asarray(ctx.goal[:2]))) < self.near_goal:
            if self._aligns(ctx):
                yaw = trajs.poses[:, -1, 2].astype(float)
                return CriticScore(np.abs(wrap_angle(yaw - float(ctx.goal[2]))))
            return CriticScore(np.zeros(len(trajs)))
        plan = ctx.cache.heading_plan
        if plan is None:
            self.prepare(ctx)
            plan = ctx.cache.heading_plan
            assert plan is not None  # prepare stores it or raises
        dense, s, tangent = plan.dense, plan.s, plan.tangent
        end = trajs.poses[:, -1].astype(float)
        if kernels.enabled():
            i = kernels.nearest_vertex(end, dense)
        else:
            d2 = (end[:, None, 0] - dense[None, :, 0]) ** 2 + (
                end[:, None, 1] - dense[None, :, 1]
            ) ** 2
            i = np.argmin(d2, axis=1)
        j = np.minimum(np.searchsorted(s, s[i] + self.heading_lookahead - 1e-9), s.size - 1)
        delta = dense[j] - end[:, :2]
        far = np.hypot(delta[:, 0], delta[:, 1]) >= 0.5 * self.heading_lookahead
        desired = np.where(far, np.arctan2(delta[:, 1], delta[:, 0]), tangent[j])
        return CriticScore(np.abs(wrap_angle(end[:, 2] - desired)))

"""Recovery behaviours and a progress checker around a local planner (move_base / Nav2 style).

The paper (Banisetty et al.) runs the ROS navigation stack, whose ``move_base`` recoveries and
``base_local_planner`` escape (back up at -0.1 m/s) take over when no trajectory is legal. This is
a planner wrapper with the same ``plan(ctx, record)`` / ``reset()`` signature.

Behaviour (parameters in :class:`RecoveryParams`):
- When the wrapped planner returns ``NO_LEGAL_TRAJECTORY``, a recovery starts: (1) rotate in place
  toward the freest direction — the heading, among ``num_headings``, whose ray from the robot stays
  clear of INSCRIBED/LETHAL/UNKNOWN cells the longest (up to ``clearance_range``); (2) back up at
  ``backup_speed`` for ``backup_distance`` instead when the free space is behind, when the robot
  already faces the freest ray, or when turning is unsafe. Each command is first checked for
  footprint collision over its own rollout (one sample, the occupancy critic); an unsafe step
  is skipped. Afterwards the wrapped planner gets control back. Status ``RECOVERING``.
- ``STUCK`` (latched until ``reset`` or a new goal, zero command) when the robot has not moved
  ``progress_radius`` m within ``progress_time`` s (Nav2 SimpleProgressChecker, with 0.25 m / 10 s
  defaults), or after ``max_recoveries`` recoveries without an ``OK`` cycle in between.
  Goal-reached and rotate-to-goal cycles count as progress.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.occupancy import OccupancyCritic
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.planner.protocols import LocalPlannerProtocol
from socialnav.planner.rollout import RolloutParams, rollout
from socialnav.world.grid import INSCRIBED


@dataclass(frozen=True)
class RecoveryParams:
    """Recovery and progress-check parameters (m, s, rad, m/s)."""

    backup_speed: float = 0.1
    backup_distance: float = 0.15
    num_headings: int = 16
    clearance_range: float = 1.5
    rotate_tolerance: float = 0.2
    max_rotate_time: float = 6.0
    progress_radius: float = 0.25
    progress_time: float = 10.0
    max_recoveries: int = 5

    def __post_init__(self) -> None:
        for name in (
            "backup_speed",
            "backup_distance",
            "clearance_range",
            "rotate_tolerance",
            "max_rotate_time",
            "progress_radius",
            "progress_time",
        ):
            if not (np.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ValueError(f"{name} must be positive")
        if self.num_headings < 1 or self.max_recoveries < 1:
            raise ValueError("num_headings and max_recoveries must be >= 1")


def clearance(ctx: PlanningContext, headings: FloatArray, max_range: float) -> FloatArray:
    """Free distance (m) along rays ``(H,)`` world headings from the robot, up to ``max_range``."""
    res = ctx.costmap.resolution
    d = np.arange(1, int(np.ceil(max_range / res)) + 1) * res  # (R,)
    pts = (
        ctx.pose[:2]
        + d[None, :, None] * np.stack([np.cos(headings), np.sin(headings)], 1)[:, None, :]
    )
    blocked = ctx.costmap.cost_at(pts) >= INSCRIBED  # (H, R); off-map reads LETHAL
    first = np.where(blocked.any(axis=1), blocked.argmax(axis=1), d.size)
    return np.where(first > 0, d[np.maximum(first - 1, 0)], 0.0)


class RecoveringPlanner:
    """Wraps any :class:`LocalPlannerProtocol` (and is one): recoveries on
    ``NO_LEGAL_TRAJECTORY``, ``STUCK`` on no progress. Never raises on a well-typed context."""

    def __init__(self, planner: LocalPlannerProtocol, params: RecoveryParams | None = None) -> None:
        self.planner = planner
        self.params = params or RecoveryParams()
        self._occupancy = OccupancyCritic()
        self.reset()

    @property
    def robot(self) -> RobotModel:
        """The wrapped planner's robot model."""
        return self.planner.robot

    def reset(self) -> None:
        """Forget recoveries, the progress anchor and the STUCK latch."""
        self.planner.reset()
        self._stuck = False
        self._phase: str | None = None
        self._phase_start = 0.0
        self._target_yaw = 0.0
        self._backup_from: FloatArray | None = None
        self._recoveries = 0
        self._anchor: FloatArray | None = None
        self._anchor_time = 0.0
        self._goal: FloatArray | None = None

    def plan(self, ctx: PlanningContext, record: bool = False) -> PlannerResult:
        """One cycle: the wrapped planner, or a recovery step, or STUCK; never raises."""
        pose = np.asarray(ctx.pose, dtype=float)
        if pose.shape != (3,) or not np.all(np.isfinite(pose)) or not np.isfinite(ctx.time):
            return self.planner.plan(ctx, record)  # INVALID_INPUT from the planner
        goal = np.asarray(ctx.goal, dtype=float)
        if self._goal is None or goal.shape != self._goal.shape or np.any(goal != self._goal):
            self._goal = goal.copy()
            self._stuck, self._phase, self._recoveries = False, None, 0
            self._anchor = None
        if (
            self._anchor is None
            or np.hypot(*(pose[:2] - self._anchor[:2])) >= self.params.progress_radius
        ):
            self._anchor, self._anchor_time = pose.copy(), float(ctx.time)
        if self._stuck:
            return PlannerResult(
                np.zeros(3), PlannerStatus.STUCK, None, "stuck (latched)", self._goal
            )
        if float(ctx.time) - self._anchor_time > self.params.progress_time:
            return self._give_up(
                f"no {self.params.progress_radius} m progress in {self.params.progress_time} s"
            )
        if self._phase is not None:
            cmd = self._recovery_cmd(ctx)
            if cmd is not None:
                why = f"recovery: {self._phase}"
                return PlannerResult(cmd, PlannerStatus.RECOVERING, None, why, self._goal)
        result = self.planner.plan(ctx, record)
        if result.status in (PlannerStatus.GOAL_REACHED, PlannerStatus.ROTATING_TO_GOAL):
            self._anchor, self._anchor_time = pose.copy(), float(ctx.time)
        if result.status == PlannerStatus.OK:
            self._recoveries = 0
        if result.status != PlannerStatus.NO_LEGAL_TRAJECTORY:
            return result
        if self._recoveries >= self.params.max_recoveries:
            return self._give_up(f"{self._recoveries} recoveries without progress")
        self._recoveries += 1
        self._start(ctx)
        cmd = self._recovery_cmd(ctx)
        if cmd is None:
            cmd = np.zeros(3)
        return PlannerResult(
            cmd,
            PlannerStatus.RECOVERING,
            result.record,
            f"recovery after: {result.message}",
            self._goal,
        )

    def _give_up(self, why: str) -> PlannerResult:
        self._stuck, self._phase = True, None
        return PlannerResult(np.zeros(3), PlannerStatus.STUCK, None, why, self._goal)

    def _start(self, ctx: PlanningContext) -> None:
        p = self.params
        headings = ctx.pose[2] + np.arange(p.num_headings) * (2 * np.pi / p.num_headings)
        free = clearance(ctx, headings, p.clearance_range)
        # Freest ray; among equals the smallest turn (np.argmax takes the first = current yaw).
        best = int(np.argmax(free))
        self._target_yaw = float(wrap_angle(headings[best]))
        rear = free[p.num_headings // 2] if p.num_headings > 1 else 0.0
        # Free space behind: back up toward it (base_local_planner's escape); else turn to it.
        facing = abs(float(wrap_angle(self._target_yaw - ctx.pose[2]))) <= p.rotate_tolerance
        behind = rear >= 0.8 * free[best] and rear > 0
        self._phase = "backup" if behind or facing else "rotate"
        self._phase_start = float(ctx.time)
        self._backup_from = ctx.pose[:2].copy()

    def _safe(self, ctx: PlanningContext, twist: FloatArray, duration: float) -> bool:
        params = RolloutParams(sim_time=max(duration, 0.1))
        trajs = rollout(ctx.pose, ctx.velocity, twist[None], self.robot, params)
        score = self._occupancy.score(trajs, ctx)
        return bool(np.isfinite(score.cost[0]))

    def _recovery_cmd(self, ctx: PlanningContext) -> FloatArray | None:
        """The current recovery step's twist, or ``None`` when the recovery is over."""
        p, r = self.params, self.robot
        if self._phase == "rotate":
            err = float(wrap_angle(self._target_yaw - ctx.pose[2]))
            timed_out = float(ctx.time) - self._phase_start > p.max_rotate_time
            if abs(err) <= p.rotate_tolerance or timed_out:
                self._phase = None
                return None
            w = np.copysign(min(r.max_vel_theta, max(r.min_in_place_vel_theta, abs(err))), err)
            twist = np.array([0.0, 0.0, w])
            if self._safe(ctx, twist, abs(err) / abs(w)):
                return twist
            self._phase, self._backup_from = "backup", ctx.pose[:2].copy()  # cannot turn
        if self._phase == "backup" and self._backup_from is not None:
            speed = min(p.backup_speed, -r.min_vel_x)
            moved = float(np.hypot(*(ctx.pose[:2] - self._backup_from)))
            if speed > 0 and moved < p.backup_distance:
                twist = np.array([-speed, 0.0, 0.0])
                if self._safe(ctx, twist, 1.0):
                    return twist
        self._phase = None
        return None

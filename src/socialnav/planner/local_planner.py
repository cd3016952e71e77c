"""The trajectory-rollout local planner (ROS ``dwa_local_planner`` semantics, pluggable selection).

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization
Approach", section "Trajectory Planning" (Algorithms 1–3): sample the control space, forward
simulate, score, discard collisions, select (PaCcET there; here any ``SelectionStrategy``).
``traditional_planner`` = one "navigation" objective + ``WeightedSum([1.0])`` = the ROS planner.

Decisions and deviations:
- Goal handling follows ROS ``LatchedStopRotateController``: inside ``xy_goal_tolerance`` (latched)
  brake at the acceleration limits, then rotate in place to the goal yaw, then ``GOAL_REACHED``.
  The social goal's own tolerances replace the parameters when ``ctx.social_goal`` is the goal.
- Room to turn (an addition to ROS, which stays latched with the rotation illegal forever): when
  the in-place rotation to the goal yaw is illegal (a PR2 corner would sweep into the queue
  member it stands behind), the robot translates slowly (``MAKE_ROOM_SPEED``) in the direction,
  among its own (8 for a holonomic base, forward/back otherwise), from whose end the rotation is
  legal, staying inside the latch radius; once turned it drives back into the xy tolerance.
- Oscillation suppression (ROS ``OscillationCostFunction``) is planner state, not a critic: after a
  velocity axis changes sign, the opposite sign is illegal until the robot moved
  ``oscillation_reset_dist`` or turned ``oscillation_reset_angle``. If that leaves nothing legal
  the guard is reset for the cycle instead of stopping the robot.
- Failures are statuses with a zero command, never exceptions: ``INVALID_INPUT`` (NaN/shape),
  ``NO_PATH`` (empty plan), ``CRITIC_UNAVAILABLE`` (a critic's ``prepare`` gave up; an addition to
  the agreed status list), ``NO_LEGAL_TRAJECTORY``.
- Sample counts default to 6 × 5 × 11 (plus in-place rotations): ≈ 330 holonomic / 66
  differential samples, a few milliseconds per cycle in NumPy, inside a 10 Hz budget.
- ``heading_scale`` 0.2 per rad (the paper gives no value): 1 rad of misalignment weighs as much
  as 0.25 m of goal distance at the ROS ``goal_distance_bias``.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from enum import StrEnum
from typing import Protocol

import numpy as np

from socialnav.core.errors import ConfigurationError, checked_bool
from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.core.trajectories import Trajectories
from socialnav.moo.selection import Selection, SelectionStrategy
from socialnav.planner import kernels
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.arrival import ArrivalTimeCritic
from socialnav.planner.critics.base import Critic, CriticUnavailable
from socialnav.planner.critics.goal_distance import GoalDistanceCritic
from socialnav.planner.critics.heading import HeadingCritic
from socialnav.planner.critics.occupancy import OccupancyCritic
from socialnav.planner.critics.path_distance import PathDistanceCritic
from socialnav.planner.critics.plan_progress import PlanProgressCritic
from socialnav.planner.objectives import Evaluation, Objective, evaluate, with_indifference
from socialnav.planner.record import EvaluationRecord
from socialnav.planner.rollout import rollout, validate_rollout
from socialnav.planner.sampling import sample_twists, validate_sampling

#: m/s: the translation that makes room for an in-place rotation at the goal (module docstring)
MAKE_ROOM_SPEED = 0.1
MAKE_ROOM_STEPS = (0.5, 1.0, 1.5, 2.0)  # s of that translation tried, shortest first (5–20 cm)
#: gap (m) the footprint keeps from every person's disc during an in-place turn at the goal,
#: checked on the discs themselves: the rasterized check let a PR2 corner graze by 1–2 cm
TURN_CLEARANCE = 0.02


class PlannerStatus(StrEnum):
    """What a control cycle ended in; every status comes with a safe command."""

    OK = "OK"
    GOAL_REACHED = "GOAL_REACHED"
    ROTATING_TO_GOAL = "ROTATING_TO_GOAL"
    NO_LEGAL_TRAJECTORY = "NO_LEGAL_TRAJECTORY"
    RECOVERING = "RECOVERING"
    STUCK = "STUCK"
    INVALID_INPUT = "INVALID_INPUT"
    NO_PATH = "NO_PATH"
    CRITIC_UNAVAILABLE = "CRITIC_UNAVAILABLE"
    WAITING = "WAITING"
    EVADING = "EVADING"
    ROTATING_TO_PLAN = "ROTATING_TO_PLAN"


@dataclass(frozen=True)
class PlannerResult:
    """One control cycle's outcome, from a local planner, a recovering wrapper, the navigator or
    any simulator controller (the one per-step result type).

    - ``cmd (3,)``: body twist ``(vx, vy, wz)`` to apply, m/s and rad/s, robot frame;
    - ``status``: :class:`PlannerStatus`;
    - ``record``: the cycle's :class:`EvaluationRecord` when asked (``record=True``), else None;
    - ``message``: why, or what the control loop does, for a status other than ``OK``;
    - ``target``: the world pose ``(3,)`` the cycle drove toward (the social goal, a waypoint or
      the given goal), or None when the cycle did not get that far; success is measured against
      the target the controller recorded last.
    """

    cmd: FloatArray
    status: PlannerStatus
    record: EvaluationRecord | None = None
    message: str = ""
    target: FloatArray | None = None


@dataclass(frozen=True)
class LocalPlannerParams:
    """ROS-named parameters (SI units, radians). See the module docstring for the choices.

    Beyond ROS's names: ``stop_at_goal`` (rollouts that reach the goal stand on it, ranked by
    ``arrival_time_scale`` s⁻¹), ``goal_distance_measure`` (``bfs``: ROS ``GoalCostFunction``,
    the free-space BFS distance to the local goal; ``along_plan``: the plan's length still to
    go, :mod:`~socialnav.planner.critics.plan_progress`, legality unchanged),
    ``heading_goal_align`` (the heading critic's ``goal_align``: a holonomic base aligns with
    the goal's yaw on the way in, Nav2 MPPI ``GoalAngleCritic``), ``footprint_check`` and
    ``rollout_dtype``. ``ConfigurationError`` on a value out of range or a bool field given
    anything but a bool (NumPy's included, stored as Python's).
    """

    # sampling (dynamic window, DWA mode)
    vx_samples: int = 6
    vy_samples: int = 5
    vth_samples: int = 11
    controller_period: float = 0.1
    # rollout
    sim_time: float = 1.7
    sim_granularity: float = 0.025
    angular_sim_granularity: float = 0.1
    # goal handling
    xy_goal_tolerance: float = 0.1
    yaw_goal_tolerance: float = 0.1
    latch_xy_goal_tolerance: bool = True
    # A rollout that enters the xy goal tolerance stops there (the latched goal check stops the
    # robot there), so critics score where the robot will stop. Off = base_local_planner: the
    # end point after the full sim_time is scored, an approach at speed "overshoots" and the
    # speed decays like distance / sim_time near the goal (the slow final approach).
    stop_at_goal: bool = False
    arrival_time_scale: float = 0.5  # weight (per s) of ArrivalTimeCritic when stop_at_goal
    trans_stopped_vel: float = 0.1
    theta_stopped_vel: float = 0.1
    # scoring (meter scoring)
    path_distance_bias: float = 0.6
    goal_distance_bias: float = 0.8
    # "bfs": ROS GoalCostFunction (free-space BFS to the local goal); "along_plan": the plan's
    # length still to go from the end point (critics.plan_progress), so following a plan that
    # bends away from the straight line to the goal is progress
    goal_distance_measure: str = "bfs"
    occdist_scale: float = 0.01
    heading_scale: float = 0.2
    heading_lookahead: float = 0.325
    # the heading critic's goal alignment (critics.heading, ``goal_align``): a holonomic base
    # is scored against the goal's yaw within its reach of the goal (ignored for a differential
    # drive and at a social waypoint)
    heading_goal_align: bool = False
    footprint_check: bool = True
    rollout_dtype: str = "float64"  # "float32" is ~1.5x faster for large batches
    # oscillation
    oscillation_reset_dist: float = 0.05
    oscillation_reset_angle: float = 0.2

    def __post_init__(self) -> None:
        try:
            validate_sampling(self)
            validate_rollout(self)
        except ValueError as exc:
            raise ConfigurationError(str(exc)) from None
        if self.goal_distance_measure not in ("bfs", "along_plan"):
            raise ConfigurationError(
                "goal_distance_measure must be bfs or along_plan, "
                f"got {self.goal_distance_measure!r}"
            )
        for name in (
            "latch_xy_goal_tolerance",
            "stop_at_goal",
            "heading_goal_align",
            "footprint_check",
        ):
            object.__setattr__(self, name, checked_bool(getattr(self, name), name))
        if self.rollout_dtype not in ("float64", "float32"):
            raise ConfigurationError(
                f"rollout_dtype must be float64 or float32, got {self.rollout_dtype!r}"
            )
        for name in (
            "xy_goal_tolerance",
            "yaw_goal_tolerance",
            "path_distance_bias",
            "goal_distance_bias",
            "occdist_scale",
            "heading_scale",
            "oscillation_reset_dist",
            "oscillation_reset_angle",
            "arrival_time_scale",
        ):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0):
                raise ConfigurationError(f"{name} must be finite and >= 0, got {value}")


def turn_clearance(
    pose: FloatArray, end_yaw: float, robot: RobotModel, ctx: PlanningContext
) -> float:
    """Smallest gap (m) between the footprint turning in place at ``pose (3,)`` (world) to
    ``end_yaw`` (rad, unwrapped: the turn goes the way ``end_yaw - pose[2]`` says) and every
    person's disc in ``ctx.social`` (where they are now; ``inf`` when nobody is within the
    circumscribed radius + their radius + :data:`TURN_CLEARANCE`). Exact up to the
    1° yaw step (a corner 0.5 m out moves < 1 cm between samples, and the distance varies
    slower than that)."""
    from socialnav.core.geometry import signed_distance_to_polygon

    people, radii = ctx.social.positions(), ctx.social.radii()
    if len(people) == 0:
        return float("inf")
    pose = np.asarray(pose, dtype=float)
    reach = robot.circumscribed_radius + radii + TURN_CLEARANCE
    near = np.hypot(*(people - pose[:2]).T) <= reach
    if not near.any():
        return float("inf")
    steps = max(int(np.ceil(abs(end_yaw - pose[2]) / np.radians(1.0))), 1)
    best = float("inf")
    for yaw in np.linspace(pose[2], end_yaw, steps + 1):
        c, s = np.cos(yaw), np.sin(yaw)
        poly = robot.polygon @ np.array([[c, s], [-s, c]]) + pose[:2]
        gap = signed_distance_to_polygon(people[near], poly) - radii[near]
        best = min(best, float(gap.min()))
    return best


def stop_at_goal(trajs: Trajectories, goal: FloatArray, tolerance: float) -> Trajectories:
    """Each rollout ``(N, T, 3)`` that comes within ``tolerance`` (m) of ``goal`` (xy) has
    arrived: from its first pose inside on, it stands on the goal's xy (keeping that pose's
    yaw). Arrival counts as reaching the goal, so every arriving rollout scores as well as the
    slowest one that ends exactly on it; rollouts that never get there are unchanged."""
    d = np.hypot(trajs.xy[..., 0] - goal[0], trajs.xy[..., 1] - goal[1])  # (N, T)
    inside = d <= tolerance
    arrives = inside.any(axis=1)
    if not arrives.any():
        return trajs
    first = np.argmax(inside, axis=1)  # (N,)
    steps = np.arange(trajs.t.shape[0])
    index = np.where(arrives[:, None], np.minimum(steps[None], first[:, None]), steps[None])
    poses = np.take_along_axis(trajs.poses, index[..., None], axis=1)
    arrived = arrives[:, None] & (steps[None] >= first[:, None])
    poses[..., 0] = np.where(arrived, goal[0], poses[..., 0])
    poses[..., 1] = np.where(arrived, goal[1], poses[..., 1])
    return Trajectories(trajs.twists, poses, trajs.t)


def traditional_objectives(params: LocalPlannerParams | None = None) -> tuple[Objective, ...]:
    """The single "navigation" objective: path, goal, occupancy and heading terms."""
    p = params or LocalPlannerParams()
    goal: Critic = GoalDistanceCritic()
    if p.goal_distance_measure == "along_plan":
        goal = PlanProgressCritic()
    terms: tuple[tuple[Critic, float], ...] = (
        (PathDistanceCritic(), p.path_distance_bias),
        (goal, p.goal_distance_bias),
        (OccupancyCritic(footprint=p.footprint_check), p.occdist_scale),
        (
            HeadingCritic(heading_lookahead=p.heading_lookahead, goal_align=p.heading_goal_align),
            p.heading_scale,
        ),
    )
    if p.stop_at_goal:  # arriving rollouts tie on path and goal distance: the first one wins
        terms += ((ArrivalTimeCritic(), p.arrival_time_scale),)
    return (Objective("navigation", terms),)


def traditional_planner(
    robot: RobotModel, params: LocalPlannerParams | None = None
) -> LocalPlanner:
    """The ROS planner: one navigation objective selected by a weighted sum."""
    from socialnav.moo.selection import WeightedSum

    p = params or LocalPlannerParams()
    return LocalPlanner(robot, traditional_objectives(p), WeightedSum([1.0]), p)


class OscillationGuard:
    """ROS ``OscillationCostFunction`` flags for the x, y and rotation axes."""

    def __init__(self, reset_dist: float, reset_angle: float) -> None:
        self.reset_dist = reset_dist
        self.reset_angle = reset_angle
        self.reset()

    def reset(self) -> None:
        """Forget the per-episode state."""
        self.seen = np.zeros((3, 2), dtype=bool)  # axis × (positive, negative) seen
        self.only = np.zeros(3, dtype=np.int8)  # +1 positive only, -1 negative only, 0 free
        self.anchor: FloatArray | None = None

    def illegal(self, twists: FloatArray) -> np.ndarray:
        """``(N,)`` mask of twists reversing a locked axis."""
        mask = np.zeros(twists.shape[0], dtype=bool)
        for axis in range(3):
            if self.only[axis] > 0:
                mask |= twists[:, axis] < 0
            elif self.only[axis] < 0:
                mask |= twists[:, axis] > 0
        return mask

    def update(self, pose: FloatArray, cmd: FloatArray, min_vel_trans: float) -> None:
        """Record the executed ``cmd (3,)`` at ``pose (3,)``; lock an axis after a reversal."""
        flagged = False
        axes = [0, 1]
        if abs(cmd[0]) <= min_vel_trans and abs(cmd[1]) <= min_vel_trans:
            axes.append(2)  # ROS: rotation flags only while (almost) not translating
        for axis in axes:
            if cmd[axis] > 0:
                if self.seen[axis, 1]:
                    self.only[axis], flagged = 1, True
                self.seen[axis] = (True, False)
            elif cmd[axis] < 0:
                if self.seen[axis, 0]:
                    self.only[axis], flagged = -1, True
                self.seen[axis] = (False, True)
        if flagged:
            self.anchor = pose.copy()
        if self.only.any() and self.anchor is not None:
            moved = np.hypot(*(pose[:2] - self.anchor[:2]))
            turned = abs(float(wrap_angle(pose[2] - self.anchor[2])))
            if moved > self.reset_dist or turned > self.reset_angle:
                self.reset()


def _zero() -> FloatArray:
    return np.zeros(3)


def _valid_inputs(ctx: PlanningContext) -> str:
    """Empty string when the context is usable, else what is wrong."""
    for name in ("pose", "velocity", "goal"):
        value = np.asarray(getattr(ctx, name))
        if value.shape != (3,) or not np.all(np.isfinite(value)):
            return f"{name} must be a finite (3,) array, got {value!r}"
    path = np.asarray(ctx.global_path)
    if path.ndim != 2 or path.shape[1:] != (2,) or not np.all(np.isfinite(path)):
        return f"global_path must be a finite (P, 2) array, got shape {path.shape}"
    return ""


class ObjectiveSet(Protocol):
    """The objective set of one cycle, resolved from what is in view (people, groups, queues,
    artworks, social goal): ``resolve(ctx) -> (objectives, selection)``; the same instances
    are returned while the set is unchanged, so critic and selection state persists."""

    def resolve(self, ctx: PlanningContext) -> tuple[Sequence[Objective], SelectionStrategy]:
        """The objectives and selection strategy for this cycle's scene (``ctx.social``)."""
        ...

    def reset(self) -> None:
        """Reset the state of every critic of every objective set kept so far."""
        ...


@dataclass
class _Cycle:
    timing: dict[str, float] = field(default_factory=dict)
    twists: FloatArray | None = None
    trajs: Trajectories | None = None
    evaluation: Evaluation | None = None


class LocalPlanner:
    """Sample → roll out → evaluate objectives → select. ``plan`` never raises on a
    well-typed context.

    A :class:`~socialnav.moo.selection.PaccetSelection` without indifference thresholds takes
    the objectives' ``Objective.indifference``
    (:func:`~socialnav.planner.objectives.with_indifference`); one with thresholds must have one
    per objective, else the constructor raises ``ConfigurationError``."""

    def __init__(
        self,
        robot: RobotModel,
        objectives: Sequence[Objective],
        selection: SelectionStrategy,
        params: LocalPlannerParams | None = None,
        objective_set: ObjectiveSet | None = None,
    ) -> None:
        self.robot = robot
        self.objective_set = objective_set
        self.objectives = tuple(objectives)
        if not self.objectives or not all(isinstance(o, Objective) for o in self.objectives):
            raise ConfigurationError("objectives must be a non-empty sequence of Objective")
        if not callable(getattr(selection, "select", None)):
            raise ConfigurationError("selection must have a select(F, legal) method")
        self.selection = with_indifference(selection, self.objectives)
        self.params = params or LocalPlannerParams()
        self._oscillation = OscillationGuard(
            self.params.oscillation_reset_dist, self.params.oscillation_reset_angle
        )
        if kernels.enabled():
            kernels.warmup()  # compile (or load) now, never inside the first control step
        self.reset()

    def reset(self) -> None:
        """Forget the per-episode state."""
        self._latched = False
        self._latch_radius = 0.0
        self._rotating = False
        self._made_room = False
        self._room: FloatArray | None = None
        self._goal: FloatArray | None = None
        self._oscillation.reset()
        for obj in self.objectives:
            for critic, _ in obj.terms:
                critic.reset()
        if self.objective_set is not None:
            self.objective_set.reset()

    # ---- public ---------------------------------------------------------------------------
    def plan(self, ctx: PlanningContext, record: bool = False) -> PlannerResult:
        """One control cycle: a body twist ``cmd (3,)`` and a status."""
        start = time.perf_counter()
        problem = _valid_inputs(ctx)
        if problem:
            return self._result(
                ctx, _zero(), PlannerStatus.INVALID_INPUT, problem, record, None, start
            )
        if ctx.global_path.shape[0] == 0:
            return self._result(
                ctx, _zero(), PlannerStatus.NO_PATH, "empty global plan", record, None, start
            )
        if self.objective_set is not None:
            objectives, selection = self.objective_set.resolve(ctx)
            self.objectives, self.selection = tuple(objectives), selection
        cycle = _Cycle()
        self._track_goal(ctx.goal)
        xy_tol, yaw_tol = self._tolerances(ctx)
        dist = float(np.hypot(*(ctx.goal[:2] - ctx.pose[:2])))
        if self._latched and dist > self._latch_radius:
            # Moved beyond the tolerance (pushed, or backed up by a recovery): not at the goal.
            self._latched = self._rotating = False
        if not self._latched and dist <= xy_tol:
            # The latch holds while the robot brakes: tolerance + braking distance, at least 2×.
            self._latch_radius = max(2.0 * xy_tol, xy_tol + self._stopping_distance(ctx))
        if self._latched or dist <= xy_tol:
            self._latched = self.params.latch_xy_goal_tolerance
        else:
            self._rotating = False
        if self._latched or dist <= xy_tol:
            status, cmd, msg = self._at_goal(ctx, yaw_tol, cycle)
            return self._result(ctx, cmd, status, msg, record, cycle, start)
        try:
            status, cmd, msg, chosen = self._sample_and_select(ctx, cycle)
        except CriticUnavailable as exc:
            return self._result(
                ctx, _zero(), PlannerStatus.CRITIC_UNAVAILABLE, str(exc), record, cycle, start
            )
        return self._result(ctx, cmd, status, msg, record, cycle, start, chosen)

    # ---- stages ---------------------------------------------------------------------------
    def _track_goal(self, goal: FloatArray) -> None:
        if self._goal is None or np.any(np.abs(goal - self._goal) > 1e-6):
            self._goal = np.array(goal, dtype=float)
            self._latched = False
            self._rotating = False
            self._made_room = False
            self._room = None
            self._oscillation.reset()

    def _stopping_distance(self, ctx: PlanningContext) -> float:
        """Braking distance (m) from the measured speed at the acceleration limits, plus one
        control period of travel: how far a latched robot may still overshoot."""
        v = np.asarray(ctx.velocity, dtype=float)
        r, dt = self.robot, self.params.controller_period
        speed = float(np.hypot(v[0], v[1]))
        acc = max(min(r.acc_lim_x, r.acc_lim_y) if r.holonomic else r.acc_lim_x, 1e-6)
        return speed * speed / (2.0 * acc) + speed * dt + 1e-6

    def _tolerances(self, ctx: PlanningContext) -> tuple[float, float]:
        sg = ctx.social_goal
        xy, yaw = self.params.xy_goal_tolerance, self.params.yaw_goal_tolerance
        if sg is not None and np.allclose(np.asarray(sg.pose, dtype=float), ctx.goal):
            xy, yaw = float(sg.position_tolerance), float(sg.yaw_tolerance)
        return xy, yaw

    def _at_goal(
        self, ctx: PlanningContext, yaw_tol: float, cycle: _Cycle
    ) -> tuple[PlannerStatus, FloatArray, str]:
        p, r = self.params, self.robot
        err = float(wrap_angle(ctx.goal[2] - ctx.pose[2]))
        if abs(err) <= yaw_tol:
            xy_tol = self._tolerances(ctx)[0]
            if self._made_room and np.hypot(*(ctx.goal[:2] - ctx.pose[:2])) > xy_tol:
                # Turned after making room: drive back into the tolerance, now facing right.
                self._latched = self._rotating = self._made_room = False
                status, cmd, msg, _ = self._sample_and_select(ctx, cycle)
                return status, cmd, msg
            return PlannerStatus.GOAL_REACHED, _zero(), ""
        v = np.asarray(ctx.velocity, dtype=float)
        moving = np.hypot(v[0], v[1]) > p.trans_stopped_vel or abs(v[2]) > p.theta_stopped_vel
        dt = p.controller_period
        if moving and not self._rotating:  # brake at the acceleration limits before turning
            acc = np.array([r.acc_lim_x, r.acc_lim_y, r.acc_lim_theta]) * dt
            cmd = v - np.sign(v) * np.minimum(np.abs(v), acc)
            return PlannerStatus.ROTATING_TO_GOAL, cmd, "stopping at the goal"
        self._rotating = True  # ROS rotating_to_goal_: do not brake again once turning
        # ROS rotateToGoal: in-place speed within limits, acceleration and stopping distance.
        w = min(r.max_vel_theta, max(r.min_in_place_vel_theta, abs(err)))
        w = min(max(w, abs(v[2]) - r.acc_lim_theta * dt), abs(v[2]) + r.acc_lim_theta * dt)
        w = min(w, float(np.sqrt(2.0 * r.acc_lim_theta * abs(err))))
        cmd = np.array([0.0, 0.0, np.copysign(w, err)])
        twists = cmd[None]
        if ctx.cache.reach is None:
            ctx.cache.reach = 2.0 * ctx.costmap.resolution
        # Checked up to the goal yaw only (ROS checks sim_time): the turn stops there, and
        # what lies beyond it (a person beside the spot) must not forbid the last few degrees.
        turn = replace(
            p, sim_time=max(min(p.sim_time, abs(err) / max(w, 1e-6)), p.controller_period)
        )
        trajs = rollout(ctx.pose, ctx.velocity, twists, r, turn)
        try:
            ev = evaluate(self.objectives, trajs, ctx)
        except CriticUnavailable as exc:
            return PlannerStatus.CRITIC_UNAVAILABLE, _zero(), str(exc)
        cycle.twists, cycle.trajs, cycle.evaluation = twists, trajs, ev
        end_yaw = float(trajs.poses[0, -1, 2])
        if not ev.legal[0] or turn_clearance(ctx.pose, end_yaw, r, ctx) < TURN_CLEARANCE:
            room = self._make_room(ctx, err)
            if room is not None:
                self._made_room = True
                return PlannerStatus.ROTATING_TO_GOAL, room, "making room to turn"
            why = "in-place rotation to goal is illegal"
            return PlannerStatus.NO_LEGAL_TRAJECTORY, _zero(), why
        self._room = None
        return PlannerStatus.ROTATING_TO_GOAL, cmd, ""

    def _make_room(self, ctx: PlanningContext, err: float) -> FloatArray | None:
        """A slow translation ``(3,)`` (body frame) after which the whole in-place turn by
        ``err`` rad is legal: the shortest such move (``MAKE_ROOM_STEPS`` s), then the one
        ending nearest the goal; kept while it stays legal. None when there is none."""
        r, p = self.robot, self.params
        first = replace(p, sim_time=MAKE_ROOM_STEPS[0])
        try:
            if self._room is not None:
                trajs = rollout(ctx.pose, ctx.velocity, self._room[None], r, first)
                if evaluate(self.objectives, trajs, ctx).legal[0]:
                    return self._room.copy()
            if r.holonomic:
                ang = np.arange(8) * (np.pi / 4)
                vx = np.clip(MAKE_ROOM_SPEED * np.cos(ang), r.min_vel_x, r.max_vel_x)
                vy = np.clip(MAKE_ROOM_SPEED * np.sin(ang), -r.max_vel_y, r.max_vel_y)
            else:
                vx = np.clip(
                    np.array([MAKE_ROOM_SPEED, -MAKE_ROOM_SPEED]), r.min_vel_x, r.max_vel_x
                )
                vy = np.zeros(2)
            twists = np.column_stack([vx, vy, np.zeros_like(vx)])
            twists = twists[np.hypot(twists[:, 0], twists[:, 1]) > 1e-9]
            w = np.copysign(min(r.max_vel_theta, max(r.min_in_place_vel_theta, abs(err))), err)
            whole = replace(p, sim_time=max(abs(err) / abs(w), p.controller_period))
            for duration in MAKE_ROOM_STEPS:
                trajs = rollout(ctx.pose, ctx.velocity, twists, r, replace(p, sim_time=duration))
                ends = trajs.end_poses.astype(float)
                ok = evaluate(self.objectives, trajs, ctx).legal.copy()
                for j in np.flatnonzero(ok):
                    spin = rollout(ends[j], np.zeros(3), np.array([[0.0, 0.0, w]]), r, whole)
                    ok[j] = bool(evaluate(self.objectives, spin, ctx).legal[0]) and (
                        turn_clearance(ends[j], ends[j][2] + err, r, ctx) >= TURN_CLEARANCE
                    )
                if ok.any():
                    reach = np.hypot(ends[:, 0] - ctx.goal[0], ends[:, 1] - ctx.goal[1])
                    k = int(np.argmin(np.where(ok, reach, np.inf)))
                    # Stay latched while making room: the robot turns there, then drives back.
                    self._latch_radius = max(self._latch_radius, float(reach[k]) + 1e-3)
                    self._room = twists[k].copy()
                    return self._room.copy()
        except CriticUnavailable:
            return None
        return None

    def _sample_and_select(
        self, ctx: PlanningContext, cycle: _Cycle
    ) -> tuple[PlannerStatus, FloatArray, str, Selection | None]:
        p, t = self.params, cycle.timing
        t0 = time.perf_counter()
        twists = sample_twists(self.robot, ctx.velocity, p)
        t1 = time.perf_counter()
        t["sample"] = t1 - t0
        cycle.twists = twists
        if twists.shape[0] == 0:
            return PlannerStatus.NO_LEGAL_TRAJECTORY, _zero(), "no velocity samples", None
        reach = float(np.hypot(twists[:, 0], twists[:, 1]).max()) * p.sim_time
        if ctx.cache.reach is None:
            ctx.cache.reach = reach + 2.0 * ctx.costmap.resolution
        trajs = rollout(
            ctx.pose, ctx.velocity, twists, self.robot, p, dtype=np.dtype(p.rollout_dtype).type
        )
        # Arrival at a waypoint must not stand for the real end points (its tolerance is 0.5 m,
        # and the real poses matter to the social critics).
        if p.stop_at_goal and not ctx.steers_to_waypoint():
            trajs = stop_at_goal(trajs, ctx.goal, self._tolerances(ctx)[0])
        t2 = time.perf_counter()
        t["rollout"] = t2 - t1
        cycle.trajs = trajs
        ev = evaluate(self.objectives, trajs, ctx)
        t.update(ev.timing)
        t3 = time.perf_counter()
        legal, F = ev.legal, ev.F
        osc = self._oscillation.illegal(twists) & legal
        if osc.any():
            ev.rejected[("oscillation", "reversal")] = int(np.count_nonzero(osc))
            if (legal & ~osc).any():
                legal = legal & ~osc
                F = F.copy()
                F[osc] = np.inf
            else:
                self._oscillation.reset()
        cycle.evaluation = Evaluation(F, legal, ev.raw, ev.rejected, ev.names, ev.timing)
        t3 = time.perf_counter()
        selection = self.selection.select(F, legal)
        t["select"] = time.perf_counter() - t3
        if selection.index is None or not legal.any():
            return PlannerStatus.NO_LEGAL_TRAJECTORY, _zero(), "no legal trajectory", selection
        cmd = twists[int(selection.index)].copy()
        self._oscillation.update(ctx.pose, cmd, self.robot.min_vel_trans)
        return PlannerStatus.OK, cmd, "", selection

    def _result(
        self,
        ctx: PlanningContext,
        cmd: FloatArray,
        status: PlannerStatus,
        message: str,
        record: bool,
        cycle: _Cycle | None,
        start: float,
        selection: Selection | None = None,
    ) -> PlannerResult:
        if not record:
            return PlannerResult(cmd, status, None, message, ctx.goal)
        timing = dict(cycle.timing) if cycle else {}
        timing["total"] = time.perf_counter() - start
        ev = cycle.evaluation if cycle else None
        rec = EvaluationRecord(
            time=float(ctx.time),
            pose=np.array(ctx.pose, dtype=float),
            velocity=np.array(ctx.velocity, dtype=float),
            goal=np.array(ctx.goal, dtype=float),
            status=status.value,
            message=message,
            twists=cycle.twists if cycle and cycle.twists is not None else np.zeros((0, 3)),
            end_poses=(
                cycle.trajs.end_poses.astype(float)
                if cycle and cycle.trajs is not None
                else np.zeros((0, 3))
            ),
            F=ev.F if ev else np.zeros((0, len(self.objectives))),
            objective_names=tuple(o.name for o in self.objectives),
            legal=ev.legal if ev else np.zeros(0, dtype=bool),
            raw=ev.raw if ev else {},
            rejected=ev.rejected if ev else {},
            fitness=None if selection is None else selection.fitness,
            chosen=None if selection is None else selection.index,
            selection={} if selection is None else dict(selection.details),
            timing=timing,
        )
        return PlannerResult(cmd, status, rec, message, ctx.goal)

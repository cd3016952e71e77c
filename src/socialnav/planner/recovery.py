"""The control loop's behaviours around a local planner: progress, waiting, evasion, recoveries.

The paper (Banisetty et al.) runs the ROS navigation stack, whose ``move_base`` recoveries and
``base_local_planner`` escape (back up at -0.1 m/s) take over when no trajectory is legal; Nav2
adds a progress checker and a "give up" that the behaviour tree reports. This is a planner
wrapper with the same ``plan(ctx, record)`` / ``reset()`` signature. People are temporary
obstacles: nothing here is final, every cycle evaluates the wrapped planner again.

Behaviour (parameters in :class:`RecoveryParams`, ROS/Nav2 names, budgets in seconds of
:class:`~socialnav.planner.limits.CycleClock` time):

- **Progress** (Nav2 ``SimpleProgressChecker``): the robot must move ``required_movement_radius``
  m within ``movement_time_allowance`` s. Only translation counts, so recovery steps that do not
  move (rotations, blocked back-ups) are not progress. At-goal statuses (``GOAL_REACHED``,
  ``ROTATING_TO_GOAL``) are progress.
- **Evasion** (status ``EVADING``): when a person's time to collision with the
  robot, both at constant velocity (the robot at the planner's chosen command), is below
  ``evasion_ttc`` s and
  the person walks faster than ``evasion_min_person_speed``, the robot takes the evasive twist
  of :mod:`socialnav.planner.evasion` that keeps the largest gap over ``evasion_horizon`` s —
  when it keeps a larger gap than the planner's own command. Four additions (off by default:
  the ROS stack has none of them; the ``paccet`` preset turns them on):
  (1) the same evasion when a walker's closest approach under the chosen command (both at
  constant velocity) comes within ``evasion_personal_distance`` m (the 1.2 m personal space)
  inside ``evasion_personal_time`` s;
  (2) *giving way* (``evasion_hold_step`` > 0): each evasive twist is also tried driven for
  1, 2, … ``evasion_hold_step`` s and then held still, over the encounter (until the
  triggering walkers pass the robot standing still, ``evasion_horizon`` to
  ``evasion_max_horizon`` s), against everyone in view (bystanders too). The gap to each
  person saturates at the personal distance, so every move that keeps everyone clear ties
  and the one ending nearest the goal wins — the planner's own command when it is clear,
  which ends the evasion. A robot thus leaves a walker's lane and waits beside it, instead of
  backing up in it or stepping aside only as far as 3 s of constant twist show.
  (3) *timed passing* (``passing_distance`` > 0), tried before giving way whenever (1) or
  the time-to-collision rule fires and until the triggering walkers have passed the robot,
  while at most ``passing_max_people`` people are within ``passing_count_range`` m and none
  of them is already nearer than ``passing_distance`` (it plans on constant-velocity forecasts
  of everyone near, which hold for a few people walking through a corridor, not in a crowd;
  measurements at ``presets.PASSING_DISTANCE``):
  :func:`~socialnav.planner.passing.timed_pass` searches command *sequences* over
  ``passing_horizon`` s that keep every person's centre ``passing_distance`` m from the
  robot's (people at constant velocity) and end where the robot can stop without being
  touched; the first twist of the one with the least plan still to go is commanded. It is
  searched again every period (0.5 s) and between searches followed while it still holds
  (:func:`~socialnav.planner.passing.follow_plan`). A sequence that ends more than
  ``passing_retreat`` m of plan farther from the goal than the encounter began is refused
  (keeping the distance by fleeing is not the robot's job), and giving way takes over.
  (3b) *passing clear of contact* (``passing_contact_fallback``; part of giving way, so it
  needs ``evasion_hold_step`` > 0 and ``passing_distance`` > 0, and it is under timed
  passing's few-people gate): in a corridor — the walls across a triggering walker's path
  (rays from the robot at right angles to the walker's velocity, people not counted:
  :func:`clearance` with ``walls_only``) leave the robot's centre less than
  ``passing_contact_corridor`` m (3.0) from side to side — where giving way's best move is
  forecast to come nearer than ``evasion_personal_distance`` too, timed passing searches again
  keeping every centre
  at the largest person radius + the circumscribed radius (where the robot's circumscribed
  circle meets a person's disc: contact is possible from there, in the worst orientation)
  instead of ``passing_distance``, while nobody is nearer than that; its plan is commanded
  unless it retreats (``passing_retreat``, from the plan still to go when the encounter
  began; the encounter lasts until the triggering walkers have passed the robot standing
  still). The search still maximises the closest approach (``PassingParams.comfort``). In a
  corridor that leaves no 1.2 m beside a walker closing from behind, giving way's constant
  twists (then held) fell short: it chose a different one nearly every cycle and the robot
  never got out of the lane, while a timed sequence (drive on and sidestep, wait, cross after
  the walker) keeps clear. Head-on, it can do worse than giving way (CHANGELOG).
  (4) *no fleeing* (``evasion_max_retreat`` > 0), under timed passing's gate on the number
  of people near: at each giving-way decision, the moves that end more than
  ``evasion_max_retreat`` m farther from the goal (straight line) than the robot is now are
  left out while another move keeps clear of contact over the encounter. A walker who takes
  the whole lane can be let past beside a wall, at less than the personal distance; driving
  ahead of them keeps the distance only until the corridor ends, where they stop and block
  the way back. In a crowd, whose constant-velocity forecasts do not hold, moving away stays
  allowed.
- **Rotation shim after an evasion** (status ``ROTATING_TO_PLAN``; ``rotation_shim_threshold``
  > 0, differential drive only; Nav2's ``RotationShimController``, ``angular_dist_threshold``
  and ``forward_sampling_distance`` = ``rotation_shim_lookahead``): in the first cycle after
  an evasion (``EVADING``) ends, if the robot faces more than the threshold away from the plan
  (the direction to the plan's point ``rotation_shim_lookahead`` m on from its nearest
  vertex), it turns in place toward the plan, down to ``rotate_tolerance``, before the local
  planner takes over again. A differential-drive robot cannot back up at speed, and a local
  planner left facing away keeps driving that way while walkers follow (its interpersonal
  objective rewards the distance). It does not act within ``rotation_shim_goal_distance`` m
  (straight line) of the goal (the goal handling turns the robot there) or at the plan's end
  (its point within 0.2 m). Where the in-place turn is unsafe (checked as the recoveries' steps
  are: a corner would sweep into a wall), it turns out on a forward arc instead, as a driver
  leaves a parking space: the tightest of ``TURN_OUT_ARCS`` that is safe until it faces the plan
  (at most ``TURN_OUT_CHECK`` s) and keeps everyone farther than ``evasion_personal_distance``
  and out of contact, turning toward the plan first, else the other way round; with none, the
  shim tries again in the next cycles, until the robot faces the plan or another evasion begins.
  An arc is followed while the robot faces more than ``rotation_shim_threshold`` away (it turns
  the robot at speed); within it, the local planner takes over, as after a turn on the spot that
  stays unsafe. Without the arc, a Pioneer left facing back along a wall only inched forward and
  back until the time limit, since every arc away from the wall also drives away from the goal
  (generated hallway dev seeds 38, 129 and 169).
- **Waiting** (status ``WAITING``, zero command; the navigator decelerates it within the
  acceleration limits and replans): when no trajectory is legal, or the legal ones make no
  progress, and a person blocks: within ``person_blocking_distance`` m (footprint circle to
  person disc) of the robot, or standing on the next ``person_blocking_lookahead`` m of the
  global plan (their disc within the robot's circumscribed radius of it). No recovery runs
  then, so the robot never backs into someone.
- **Recoveries** (status ``RECOVERING``) otherwise, up to ``max_recoveries`` in a row: (1) rotate
  in place toward the freest direction — the heading, among ``num_headings``, whose ray from
  the robot stays clear of INSCRIBED/LETHAL/UNKNOWN cells the longest (up to
  ``clearance_range``); (2) back up at ``backup_speed`` for ``backup_distance`` instead when the
  free space is behind, when the robot already faces the freest ray, or when turning is unsafe.
  Each command is checked for footprint collision over its own rollout; an unsafe step ends it.
- **Give up** (status ``STUCK`` with the reason in ``message``) when there was no progress for
  ``controller_patience`` s (move_base's name). It is a status, not a latch: the wrapped planner
  runs every cycle, and the first legal command leaves ``STUCK`` (and starts a new progress
  window). While ``STUCK`` with a legal command that makes no progress (an oscillation), that
  command is passed on under ``STUCK``, so the caller hears about it and the robot keeps trying.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from numbers import Integral

import numpy as np

from socialnav.core.errors import ConfigurationError, is_non_negative_number
from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.group import GroupCritic
from socialnav.planner.critics.interpersonal import (
    footprint_approaches,
    people_unblocked,
)
from socialnav.planner.critics.map_grid import densify_path, plan_ahead
from socialnav.planner.critics.occupancy import OccupancyCritic
from socialnav.planner.evasion import (
    closest_approach,
    evasion_gaps,
    evasion_twists,
    move_and_hold,
    person_gap_minima,
    squared_distance_minima,
    time_to_collision,
)
from socialnav.planner.limits import CycleClock
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.planner.passing import PassingParams, PassingPlan, follow_plan, timed_pass
from socialnav.planner.protocols import LocalPlannerProtocol
from socialnav.planner.record import EvaluationRecord
from socialnav.planner.rollout import RolloutParams, rollout
from socialnav.world.grid import FREE, INSCRIBED, LETHAL

_ACTIVE = (PlannerStatus.OK, PlannerStatus.NO_LEGAL_TRAJECTORY)
_AT_GOAL = (PlannerStatus.GOAL_REACHED, PlannerStatus.ROTATING_TO_GOAL)
#: closing speed (m/s) on a touched person that rules an evasive move out (as the critic's)
APPROACH_SPEED = 0.02
#: how far ahead (s) an evasive move is checked for closing on a touched person
APPROACH_HORIZON = 1.0
#: the rotation shim's plan point nearer than this (m): the robot is at the plan's end
PLAN_END = 0.2
#: the rotation shim's turn-out arcs, in the order tried: (fraction of max_vel_x, fraction of
#: max_vel_theta), the tightest first
TURN_OUT_ARCS = ((0.5, 1.0), (1.0, 1.0), (1.0, 0.5))
#: how long (s) a turn-out arc is checked for safety at most
TURN_OUT_CHECK = 2.0


@dataclass(frozen=True)
class RecoveryParams:
    """Progress, waiting, evasion and recovery parameters (m, s, rad, m/s); module docstring.

    Defaults: Nav2 ``SimpleProgressChecker`` (0.25 m in 10 s), ``base_local_planner``'s escape
    (0.1 m/s), ``controller_patience`` 30 s (longer than move_base's 15 s: waiting for a person
    to clear a corridor is normal), evasion below 3 s to collision (a person at 1.5 m/s is then
    4.5 m away: time for a 0.3 m/s sidestep).

    The control loop's additions (module docstring), each off at 0 and on in ``paccet``
    (``presets.RECOMMENDED_RECOVERY``):
    ``evasion_personal_distance`` (m; 1.2), ``evasion_personal_time`` (s), ``evasion_hold_step``
    (s; 1.0), ``passing_distance`` (m; 1.25) with ``passing_horizon`` (s),
    ``passing_retreat`` (m of plan), ``passing_max_people`` within ``passing_count_range`` (m);
    ``passing_contact_fallback`` (bool; ``paccet``: True): timed passing clear of contact in a
    corridor where giving way cannot keep the personal distance either, one that leaves the
    robot's centre less than ``passing_contact_corridor`` (m; 3.0 in every preset, only used
    with the fallback on; 0 never counts as a corridor) across a walker's path;
    ``evasion_max_retreat`` (m of straight-line distance to the goal; 0.5): no fleeing, under
    timed passing's gate; ``rotation_shim_threshold`` (rad, at most pi; pi/2): the rotation shim
    after an evasion, differential drive only, toward the plan's point
    ``rotation_shim_lookahead`` m on (> 0.2 m), not within ``rotation_shim_goal_distance`` m
    (straight line) of the goal. Raises ``ConfigurationError`` naming the field for a value
    that is not a number (an integer for the counts), negative, NaN or out of range.
    """

    backup_speed: float = 0.1
    backup_distance: float = 0.15
    num_headings: int = 16
    clearance_range: float = 1.5
    rotate_tolerance: float = 0.2
    max_rotate_time: float = 6.0
    required_movement_radius: float = 0.25
    movement_time_allowance: float = 10.0
    controller_patience: float = 30.0
    max_recoveries: int = 5
    person_blocking_distance: float = 1.0
    person_blocking_lookahead: float = 3.0
    evasion_ttc: float = 3.0
    evasion_horizon: float = 3.0
    evasion_min_person_speed: float = 0.3
    evasion_personal_distance: float = 0.0  # off (the ROS stack has no such rule); paccet 1.2
    evasion_personal_time: float = 4.0
    evasion_hold_step: float = 0.0  # off: constant twists over evasion_horizon; paccet 1.0
    evasion_max_horizon: float = 8.0
    passing_distance: float = 0.0  # off (no timed passing); paccet 1.25
    passing_horizon: float = 6.0
    passing_retreat: float = 0.5
    passing_max_people: int = 3
    passing_count_range: float = 10.0
    passing_contact_fallback: bool = False  # off; paccet on (needs passing_distance > 0)
    passing_contact_corridor: float = 3.0
    evasion_max_retreat: float = 0.0
    rotation_shim_threshold: float = 0.0
    rotation_shim_lookahead: float = 0.5
    rotation_shim_goal_distance: float = 1.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "passing_contact_fallback":
                if not isinstance(value, bool):
                    raise ConfigurationError(
                        f"recovery parameter {f.name} must be True or False, got {value!r}"
                    )
            elif f.name in ("num_headings", "max_recoveries", "passing_max_people"):
                if isinstance(value, bool) or not isinstance(value, Integral) or value < 1:
                    raise ConfigurationError(
                        f"recovery parameter {f.name} must be an integer >= 1, got {value!r}"
                    )
            elif not is_non_negative_number(value):
                raise ConfigurationError(
                    f"recovery parameter {f.name} must be a finite number >= 0, got {value!r}"
                )
        if self.rotation_shim_threshold > math.pi:
            raise ConfigurationError(
                "recovery parameter rotation_shim_threshold must be at most pi (rad), got"
                f" {self.rotation_shim_threshold!r}"
            )
        if self.rotation_shim_threshold > 0 and self.rotation_shim_lookahead <= PLAN_END:
            raise ConfigurationError(
                f"recovery parameter rotation_shim_lookahead must be > {PLAN_END} m (nearer"
                f" points give no direction), got {self.rotation_shim_lookahead!r}"
            )
        if self.passing_distance > 0 and self.passing_horizon <= 0:
            raise ConfigurationError("recovery parameter passing_horizon must be positive")
        for name in ("required_movement_radius", "movement_time_allowance", "evasion_horizon"):
            if getattr(self, name) <= 0:
                raise ConfigurationError(f"recovery parameter {name} must be positive")


def clearance(
    ctx: PlanningContext, headings: FloatArray, max_range: float, walls_only: bool = False
) -> FloatArray:
    """Free distance (m) the robot's centre can move along rays ``(H,)`` world headings: to the
    last sample (every cell, up to ``max_range`` rounded up to a cell) before the first
    INSCRIBED/LETHAL/UNKNOWN cell; off the map reads LETHAL. ``walls_only``: people do not
    stop a ray (the local costmap marks them, inflated like walls): a blocked place near
    someone stops it only with a LETHAL cell that is no person's own within the inscribed
    radius (``critics.interpersonal.people_unblocked``), so a wall beside them still does (a
    thin wall a person touches can read up to a cell or two farther: its cells within their
    radius + a cell count as theirs); off the costmap reads free (the navigator's cropped
    window marks cells off the static map UNKNOWN, which stop a ray); at most ``max_range``."""
    cm = ctx.costmap
    res = cm.resolution
    d = np.arange(1, int(np.ceil(max_range / res)) + 1) * res  # (R,)
    if d.size == 0:
        return np.zeros(np.shape(headings))
    pts = (
        ctx.pose[:2]
        + d[None, :, None] * np.stack([np.cos(headings), np.sin(headings)], 1)[:, None, :]
    )
    blocked = cm.cost_at(pts, outside=FREE if walls_only else LETHAL) >= INSCRIBED  # (H, R)
    if walls_only and ctx.social.people and blocked.any():
        social, inscribed = ctx.social, ctx.robot.inscribed_radius
        blocked = people_unblocked(cm, pts, blocked, social.positions(), social.radii(), inscribed)
    first = np.where(blocked.any(axis=1), blocked.argmax(axis=1), d.size)
    free = np.where(first > 0, d[np.maximum(first - 1, 0)], 0.0)
    return np.minimum(free, max_range) if walls_only else free


def person_gaps(ctx: PlanningContext) -> FloatArray:
    """``(K,)`` gap (m) from the robot's circumscribed circle to each person's disc."""
    if not ctx.social.people:
        return np.zeros(0)
    d = np.hypot(*(ctx.social.positions() - ctx.pose[:2]).T)
    return d - ctx.social.radii() - ctx.robot.circumscribed_radius


def body_to_world_velocity(pose: FloatArray, twist: FloatArray) -> FloatArray:
    """World-frame ``(vx, vy)`` of a body twist ``(3,)`` at ``pose (3,)``."""
    c, s = np.cos(pose[2]), np.sin(pose[2])
    return np.array([c * twist[0] - s * twist[1], s * twist[0] + c * twist[1]])


class RecoveringPlanner:
    """Wraps any :class:`LocalPlannerProtocol` (and is one): evasion, waiting, recoveries and a
    non-latching ``STUCK`` (module docstring). Never raises on a well-typed context. Its
    commands keep the velocity limits, not the acceleration limits: the
    :class:`~socialnav.planner.navigator.Navigator` around it applies those. Raises
    ``ConfigurationError`` when ``params`` is not a :class:`RecoveryParams`."""

    def __init__(self, planner: LocalPlannerProtocol, params: RecoveryParams | None = None) -> None:
        if params is not None and not isinstance(params, RecoveryParams):
            raise ConfigurationError(
                f"recovery parameters must be a RecoveryParams, got {type(params).__name__}"
            )
        self.planner = planner
        self.params = params or RecoveryParams()
        self._occupancy = OccupancyCritic()
        self._ospace = GroupCritic(illegal_inside=True)
        self._clock = CycleClock()
        self.reset()

    @property
    def robot(self) -> RobotModel:
        """The wrapped planner's robot model."""
        return self.planner.robot

    def reset(self) -> None:
        """Forget recoveries, the progress anchor and the STUCK latch."""
        self.planner.reset()
        self._clock.reset()
        self._phase: str | None = None
        self._phase_start = 0.0
        self._target_yaw = 0.0
        self._backup_from: FloatArray | None = None
        self._recoveries = 0
        self._anchor: FloatArray | None = None
        self._anchor_time = 0.0
        self._goal: FloatArray | None = None
        self._blocked = False  # the previous cycle had no legal command
        self._pass_until = -math.inf  # timed passing stays on until the walkers have passed
        self._pass_ref = math.nan  # plan still to go when the encounter began (m)
        self._pass_plan: PassingPlan | None = None
        self._pass_t0 = 0.0
        self._pass_distance = 0.0  # the distance the followed plan keeps (m)
        self._shim_armed = False  # an evasion ended: the rotation shim may run once
        self._shim_turning = False

    def _out(
        self, cmd: FloatArray, status: PlannerStatus, record: EvaluationRecord | None, message: str
    ) -> PlannerResult:
        """A result toward this cycle's goal (the navigator's resolved target)."""
        return PlannerResult(cmd, status, record, message, self._goal)

    def plan(self, ctx: PlanningContext, record: bool = False) -> PlannerResult:
        """One cycle: the wrapped planner, or a recovery step, or STUCK; never raises."""
        pose = np.asarray(ctx.pose, dtype=float)
        if pose.shape != (3,) or not np.all(np.isfinite(pose)) or not np.isfinite(ctx.time):
            return self.planner.plan(ctx, record)  # INVALID_INPUT from the planner
        now = self._clock.tick(float(ctx.time))
        p = self.params
        goal = np.asarray(ctx.goal, dtype=float)
        if self._goal is None or goal.shape != self._goal.shape or np.any(goal != self._goal):
            self._goal = goal.copy()
            self._phase, self._recoveries, self._anchor = None, 0, None
        if (
            self._anchor is None
            or np.hypot(*(pose[:2] - self._anchor[:2])) >= p.required_movement_radius
        ):
            self._anchor, self._anchor_time = pose.copy(), now
        if self._phase is not None:
            cmd = self._recovery_cmd(ctx, now)
            if cmd is not None:
                return self._out(cmd, PlannerStatus.RECOVERING, None, f"recovery: {self._phase}")
        result = self.planner.plan(ctx, record)
        if result.status in _AT_GOAL:
            self._anchor, self._anchor_time, self._recoveries = pose.copy(), now, 0
            self._blocked = False
            return result
        if result.status not in _ACTIVE:
            return result  # INVALID_INPUT, NO_PATH, CRITIC_UNAVAILABLE: the navigator reports
        legal = result.status == PlannerStatus.OK
        if legal and self._blocked:
            self._anchor, self._anchor_time = pose.copy(), now  # the way opened: a new window
        self._blocked = not legal
        evade = self._evasion(ctx, result)
        if evade is not None:
            self._shim_armed, self._shim_turning = True, False
            return evade
        if legal and self._shim_armed:
            turn = self._rotation_shim(ctx, result)
            if turn is not None:
                return turn
        stalled = now - self._anchor_time
        if legal and stalled <= p.movement_time_allowance:
            self._recoveries = 0
            return result
        if stalled > p.controller_patience:
            why = f"no {p.required_movement_radius} m progress in {stalled:.1f} s"
            if legal:
                return self._out(result.cmd, PlannerStatus.STUCK, result.record, why)
            return self._out(np.zeros(3), PlannerStatus.STUCK, result.record, why)
        blocker = self._blocking_person(ctx)
        if blocker is not None:
            k, gap = blocker
            who = ctx.social.people[k].id
            why = f"waiting for person {who} ({gap:.2f} m away): {result.message or 'blocked'}"
            return self._out(np.zeros(3), PlannerStatus.WAITING, result.record, why)
        if self._recoveries >= p.max_recoveries:
            if legal:
                return result
            return self._out(
                np.zeros(3),
                PlannerStatus.NO_LEGAL_TRAJECTORY,
                result.record,
                f"{self._recoveries} recoveries without progress; {result.message}",
            )
        self._recoveries += 1
        self._start(ctx, now)
        cmd = self._recovery_cmd(ctx, now)
        if cmd is None:
            cmd = np.zeros(3)
        why = f"recovery after: {result.message or 'no progress'}"
        return self._out(cmd, PlannerStatus.RECOVERING, result.record, why)

    def _rotation_shim(self, ctx: PlanningContext, result: PlannerResult) -> PlannerResult | None:
        """An in-place turn toward the plan after an evasion (module docstring), or None; it
        disarms unless the turn was only unsafe this cycle."""
        p, r = self.params, self.robot
        path = np.asarray(ctx.global_path, dtype=float).reshape(-1, 2)
        to_goal = float(np.hypot(*(ctx.pose[:2] - np.asarray(ctx.goal, dtype=float)[:2])))
        if p.rotation_shim_threshold <= 0 or r.holonomic:
            self._shim_armed = False
            return None
        if path.shape[0] < 2 or to_goal < p.rotation_shim_goal_distance:
            self._shim_armed = self._shim_turning = False
            return None
        ahead, arc = plan_ahead(path, ctx.pose[:2])
        j = min(int(np.searchsorted(arc, p.rotation_shim_lookahead)), arc.size - 1)
        dx, dy = ahead[j] - ctx.pose[:2]
        err = float(wrap_angle(math.atan2(dy, dx) - ctx.pose[2]))
        if math.hypot(dx, dy) < PLAN_END:
            self._shim_armed = self._shim_turning = False
            return None
        if abs(err) <= (p.rotate_tolerance if self._shim_turning else p.rotation_shim_threshold):
            self._shim_armed = self._shim_turning = False
            return None
        w = math.copysign(min(r.max_vel_theta, max(r.min_in_place_vel_theta, abs(err))), err)
        twist = np.array([0.0, 0.0, w])
        if not self._safe(ctx, twist, min(abs(err) / abs(w), 1.0)):
            self._shim_turning = False  # armed still: the turn may become safe
            out_arc = self._turn_out(ctx, err)
            if out_arc is None:
                return None
            why = f"turning out toward the plan ({err:+.2f} rad off) after evading"
            return self._out(out_arc, PlannerStatus.ROTATING_TO_PLAN, result.record, why)
        self._shim_turning = True
        why = f"rotating to the plan ({err:+.2f} rad off) after evading"
        return self._out(twist, PlannerStatus.ROTATING_TO_PLAN, result.record, why)

    def _turn_out(self, ctx: PlanningContext, err: float) -> FloatArray | None:
        """A forward arc toward the plan (``err`` rad off) where turning in place is unsafe:
        the first of ``TURN_OUT_ARCS`` turning toward the plan, then away, that is safe until
        it faces the plan (at most ``TURN_OUT_CHECK`` s) and keeps everyone's distance
        (:meth:`_keeps_space`); None when none is."""
        r = self.robot
        toward = math.copysign(1.0, err)
        for sign in (toward, -toward):
            angle = abs(err) if sign == toward else 2.0 * math.pi - abs(err)
            for speed, rate in TURN_OUT_ARCS:
                w = rate * r.max_vel_theta
                twist = np.array([speed * r.max_vel_x, 0.0, sign * w])
                duration = min(angle / w, TURN_OUT_CHECK)
                if self._safe(ctx, twist, duration) and self._keeps_space(ctx, twist, duration):
                    return twist
        return None

    def _keeps_space(self, ctx: PlanningContext, twist: FloatArray, duration: float) -> bool:
        """Whether ``twist`` held for ``duration`` s keeps everyone (forecast at constant
        velocity) beyond ``evasion_personal_distance`` (centre to centre) and out of contact:
        with someone nearer, the evasion or the local planner decides, not a turn-out that
        drives on (recorded crowds: a turn-out beside someone touching the robot became an
        active contact)."""
        if not ctx.social.people:
            return True
        pos, vel, radii = ctx.social.positions(), ctx.social.velocities(), ctx.social.radii()
        trajs = rollout(ctx.pose, ctx.velocity, twist[None], self.robot, RolloutParams(duration))
        gaps = person_gap_minima(trajs, self.robot, pos, vel, radii)[0]
        r = self.robot.circumscribed_radius
        space = np.maximum(self.params.evasion_personal_distance - radii - r, 0.0)
        return bool(np.all(gaps > space))

    def _blocking_person(self, ctx: PlanningContext) -> tuple[int, float] | None:
        """``(index, gap m)`` of the person blocking the robot (module docstring), or None."""
        gaps = person_gaps(ctx)
        if not gaps.size:
            return None
        p, r = self.params, self.robot
        blocking = gaps <= p.person_blocking_distance
        path = np.asarray(ctx.global_path, dtype=float).reshape(-1, 2)
        if path.shape[0] and not blocking.all():
            s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))])
            ahead = path[s <= p.person_blocking_lookahead]
            d = np.hypot(*(ahead[None] - ctx.social.positions()[:, None]).transpose(2, 0, 1))
            blocking |= d.min(axis=1) <= ctx.social.radii() + r.circumscribed_radius
        if not blocking.any():
            return None
        k = int(np.argmin(np.where(blocking, gaps, np.inf)))
        return k, float(gaps[k])

    # ---- evasion --------------------------------------------------------------------------
    def _evasion(self, ctx: PlanningContext, result: PlannerResult) -> PlannerResult | None:
        p, r = self.params, self.robot
        people = ctx.social.people
        if not people or p.evasion_ttc <= 0:
            return None
        pos, vel, radii = ctx.social.positions(), ctx.social.velocities(), ctx.social.radii()
        fast = np.hypot(vel[:, 0], vel[:, 1]) >= p.evasion_min_person_speed
        # Within 6 m. Measured and not adopted: 10 m, so that a fast oncoming walker sets off
        # evasion seconds earlier (generated dev seeds 0–59 of hallway, crowdnav,
        # crowdnav_visible and mixed, both robots: 455 passes against 456); 9 m, hallway dev
        # seeds 0-199, both robots: 381 -> 379 passes.
        centre = np.hypot(*(pos - ctx.pose[:2]).T)
        near = centre <= r.circumscribed_radius + radii + 6.0
        sel = fast & near
        if not sel.any():
            return None
        # timed passing plans on constant-velocity forecasts of everyone near: only where they
        # are few, and before anyone is inside the distance it keeps (module docstring)
        few = int((centre <= p.passing_count_range + radii).sum()) <= p.passing_max_people
        passing = p.passing_distance > 0 and few and bool((centre >= p.passing_distance).all())
        pos, vel, radii = pos[sel], vel[sel], radii[sel]
        own = body_to_world_velocity(ctx.pose, result.cmd)
        ttc = time_to_collision(ctx.pose[:2], own, pos, vel, radii + r.circumscribed_radius)
        # Personal-space trigger (an addition to time-to-collision methods): a walker whose
        # closest approach under this command falls inside evasion_personal_distance within
        # evasion_personal_time s.
        trigger = ttc < p.evasion_ttc
        if p.evasion_personal_distance > 0:
            cpa, t_cpa = closest_approach(ctx.pose[:2], own, pos, vel)
            trigger |= (cpa < p.evasion_personal_distance) & (t_cpa < p.evasion_personal_time)
        if not trigger.any():
            if passing and float(ctx.time) < self._pass_until:
                return self._timed_pass(ctx, result)
            return None
        if passing:
            _, t_pass = closest_approach(ctx.pose[:2], np.zeros(2), pos[trigger], vel[trigger])
            if float(ctx.time) >= self._pass_until:
                self._pass_ref = math.nan  # a new encounter: its reference is set below
            self._pass_until = max(self._pass_until, float(ctx.time) + float(t_pass.max()))
            passed = self._timed_pass(ctx, result)
            if passed is not None:
                return passed
        if p.evasion_hold_step > 0:
            return self._give_way(ctx, result, sel, trigger, ttc, few)
        horizon = p.evasion_horizon
        if float(ttc.min()) >= p.evasion_ttc:
            horizon = max(horizon, p.evasion_personal_time)
        twists = np.concatenate([result.cmd[None], np.zeros((1, 3)), evasion_twists(r)])
        gaps, trajs = evasion_gaps(ctx.pose, twists, r, pos, vel, radii, horizon)
        static = self._static_ok(ctx, trajs)
        if not static[1:].any():
            return None
        # Never an evasive move that closes on anyone it touches (people forecast, standing
        # ones included): an evasion must not turn a passive contact into an active one.
        closing = self._approaching(ctx, trajs)
        if not (static & ~closing)[1:].any():
            return None
        gaps = np.where(static & ~closing, gaps, -np.inf)
        # Progress toward the local goal breaks near-ties (within 5 cm of the best gap).
        progress = -np.hypot(*(trajs.end_poses[:, :2] - ctx.goal[:2]).T)
        best_gap = float(gaps.max())
        tied = gaps >= best_gap - 0.05
        k = int(np.argmax(np.where(tied, progress, -np.inf)))
        if k == 0 or gaps[k] <= gaps[0] + 1e-3:
            return None  # the planner's own command keeps as much clearance
        who = int(np.flatnonzero(sel)[int(np.argmin(ttc))])
        why = f"evading person {people[who].id} (time to collision {float(ttc.min()):.2f} s)"
        return self._out(twists[k].copy(), PlannerStatus.EVADING, result.record, why)

    def _timed_pass(
        self, ctx: PlanningContext, result: PlannerResult, distance: float | None = None
    ) -> PlannerResult | None:
        """The first command of :func:`~socialnav.planner.passing.timed_pass` keeping
        ``distance`` m (default ``passing_distance``), or None. Between searches, the plan
        found last is followed with the distance it was found with."""
        p = self.params
        if distance is None:
            distance = p.passing_distance
        path = np.asarray(ctx.global_path, dtype=float).reshape(-1, 2)
        if path.shape[0] >= 2:
            dense = densify_path(path, 0.1)
            arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(dense, axis=0).T))])
            total = float(arc[-1])
            # the search reaches top speed x horizon; plan beyond that (+2 m) is never nearest
            reach = np.hypot(self.robot.max_vel_x, self.robot.max_vel_y) * p.passing_horizon
            cut = max(int(np.searchsorted(arc, reach + 2.0, side="right")), 1)
            dense, arc = dense[:cut], arc[:cut]

            def to_go(xy: FloatArray) -> FloatArray:
                i = kernels.nearest_vertex(xy, dense)
                return np.asarray(total - arc[i] + np.hypot(*(xy - dense[i]).T))
        else:

            def to_go(xy: FloatArray) -> FloatArray:
                return np.asarray(np.hypot(*(xy - ctx.goal[:2]).T))

        def static_ok(cmd: FloatArray, poses: FloatArray, t: FloatArray) -> np.ndarray:
            return self._static_ok(ctx, Trajectories(cmd, poses, t))

        args = (
            np.asarray(ctx.pose, dtype=float),
            np.asarray(ctx.velocity, dtype=float),
            self.robot,
            ctx.social.positions(),
            ctx.social.velocities(),
        )
        params = PassingParams(distance=distance, horizon=p.passing_horizon)
        contact = ctx.social.radii() + self.robot.circumscribed_radius + 0.1
        now = float(ctx.time)
        if self._pass_plan is not None and now - self._pass_t0 < params.period - 1e-6:
            kept = replace(params, distance=self._pass_distance)
            cmd = follow_plan(self._pass_plan, now - self._pass_t0, *args, static_ok, kept, contact)
            if cmd is not None:
                return self._passing_out(cmd, self._pass_plan, result)
        self._pass_plan = None
        plan = timed_pass(*args, to_go, static_ok, params, contact=contact)
        here = float(to_go(ctx.pose[None, :2])[0])
        if not math.isfinite(self._pass_ref):
            self._pass_ref = here
        if plan is None or plan.to_go > self._pass_ref + p.passing_retreat:
            return None  # none, or only by retreating: the distance is not the robot's to keep
        self._pass_plan, self._pass_t0, self._pass_distance = plan, now, distance
        return self._passing_out(plan.command.copy(), plan, result)

    def _passing_out(
        self, cmd: FloatArray, plan: PassingPlan, result: PlannerResult
    ) -> PlannerResult:
        """``EVADING`` with ``cmd``, on ``plan``."""
        why = f"timed pass (closest {plan.closest:.2f} m over {self.params.passing_horizon:.1f} s)"
        return self._out(cmd, PlannerStatus.EVADING, result.record, why)

    def _give_way(
        self,
        ctx: PlanningContext,
        result: PlannerResult,
        sel: np.ndarray,
        trigger: np.ndarray,
        ttc: FloatArray,
        few: bool,
    ) -> PlannerResult | None:
        """Give way to the walkers ``sel`` (``trigger`` among them set it off): move out of
        their lanes and hold there, judged over the whole encounter against everyone
        (standing people included: the lane beside a walker may be beside a bystander too).
        ``few``: at most ``passing_max_people`` people are near (the no-fleeing rule's gate)."""
        p, r = self.params, self.robot
        pos, vel = ctx.social.positions(), ctx.social.velocities()
        radii = ctx.social.radii()
        # The encounter lasts until the triggering walkers pass the robot standing still.
        walkers = np.flatnonzero(sel)[trigger]
        _, t_pass = closest_approach(ctx.pose[:2], np.zeros(2), pos[walkers], vel[walkers])
        horizon = float(
            np.clip(t_pass.max() + p.evasion_hold_step, p.evasion_horizon, p.evasion_max_horizon)
        )
        twists = np.concatenate([result.cmd[None], np.zeros((1, 3)), evasion_twists(r, arcs=True)])
        base = rollout(ctx.pose, np.zeros(3), twists, r, RolloutParams(horizon, 0.05, 0.1))
        taus = np.append(np.arange(p.evasion_hold_step, horizon, p.evasion_hold_step), horizon)
        trajs = move_and_hold(base, taus)
        own = np.tile(np.arange(len(twists)) == 0, taus.size)
        # Saturated at the personal distance: every move that keeps every walker clear ties,
        # and the one with the most progress wins, so evasion ends as soon as the walkers'
        # closest approach is clear (the planner's own command wins the tie: no evasion).
        clear = max(p.evasion_personal_distance, 0.0) - radii - r.circumscribed_radius
        gaps = np.minimum(person_gap_minima(trajs, r, pos, vel, radii), clear[None]).min(axis=1)
        legal = self._static_ok(ctx, trajs) & ~self._approaching(ctx, trajs)
        if not legal[~own].any():
            return None
        gaps = np.where(legal, gaps, -np.inf)
        progress = -np.hypot(*(trajs.end_poses[:, :2] - ctx.goal[:2]).T)
        if p.evasion_max_retreat > 0 and few:
            # no fleeing (module docstring), unless only fleeing stays clear of contact
            here = float(np.hypot(*(ctx.pose[:2] - ctx.goal[:2])))
            flees = -progress - here > p.evasion_max_retreat
            if ((gaps > 0) & ~flees).any():
                gaps = np.where(flees, -np.inf, gaps)
        # Measured and not kept: a 0.15 m tie (generated dev seeds 0-59 of crowdnav,
        # crowdnav_visible, hallway and mixed, both robots: 472 -> 469 passes, collision runs
        # 2 -> 4, time ratio to hl -0.02 to +0.01). A Pioneer giving way to a walker who keeps
        # coming can circle on the spot at full speed: each cycle's best move is an arc driven
        # for a few seconds, and the next cycle chooses again before the hold (crowdnav dev 10).
        tied = gaps >= float(gaps.max()) - 0.05
        k = int(np.argmax(np.where(tied, progress, -np.inf)))
        short = gaps[k] < float(clear.min()) - 1e-6  # nearer than the personal distance
        fallback = p.passing_contact_fallback and p.passing_distance > 0 and few and short
        if fallback and self._walled_in(ctx, vel[walkers]):
            passed = self._pass_clear_of_contact(ctx, result, float(ctx.time) + float(t_pass.max()))
            if passed is not None:
                return passed
        if own[k] or gaps[k] <= float(gaps[own].max()) + 1e-3:
            return None  # the planner's own command keeps as much clearance
        who = ctx.social.people[int(walkers[int(np.argmin(ttc[trigger]))])]
        why = f"giving way to person {who.id} (gap {float(gaps[k]):.2f} m over {horizon:.1f} s)"
        return self._out(trajs.twists[k].copy(), PlannerStatus.EVADING, result.record, why)

    def _walled_in(self, ctx: PlanningContext, velocities: FloatArray) -> bool:
        """Whether the walls across the path of any of the walkers (``velocities (W, 2)`` m/s,
        world frame) leave the robot's centre less than ``passing_contact_corridor`` m from one
        side to the other (people not counted): a corridor too narrow to keep the personal
        distance beside a walker in its middle, or little wider."""
        width = self.params.passing_contact_corridor
        velocities = velocities[np.hypot(velocities[:, 0], velocities[:, 1]) > 1e-9]
        if not velocities.size:
            return False  # nobody walking: no path to be walled in across
        heading = np.arctan2(velocities[:, 1], velocities[:, 0])
        free = clearance(
            ctx, np.concatenate([heading + np.pi / 2, heading - np.pi / 2]), width, True
        )
        return bool((free[: len(heading)] + free[len(heading) :] < width).any())

    def _pass_clear_of_contact(
        self, ctx: PlanningContext, result: PlannerResult, until: float
    ) -> PlannerResult | None:
        """Timed passing at the contact distance (module docstring, (3b)), or None; the
        encounter lasts at least ``until`` (s: the triggering walkers have passed the robot),
        and its retreat reference is kept until then."""
        radii = ctx.social.radii()
        touch = float(radii.max()) + self.robot.circumscribed_radius
        centre = np.hypot(*(ctx.social.positions() - ctx.pose[:2]).T)
        if not bool((centre >= touch).all()):
            return None  # someone is already nearer: giving way moves away first
        if float(ctx.time) >= self._pass_until:
            self._pass_ref = math.nan  # a new encounter: its retreat reference is set now
        self._pass_until = max(self._pass_until, until)
        return self._timed_pass(ctx, result, touch)

    def _approaching(self, ctx: PlanningContext, trajs: Trajectories) -> np.ndarray:
        """``(N,)`` rollouts whose footprint moves toward a person it touches, turning
        included (``critics.interpersonal.footprint_approaches``), within the first
        ``APPROACH_HORIZON`` s: the loop replans every cycle, and beyond that the
        constant-velocity forecast carries people through the robot, after which nearly every
        move "closes" on someone and no evasion would be left."""
        keep = trajs.t <= APPROACH_HORIZON
        trajs = Trajectories(trajs.twists, trajs.poses[:, keep], trajs.t[keep])
        forecast = ctx.people_at(trajs.t)  # (T, K, 2)
        d2 = squared_distance_minima(trajs, forecast)
        return footprint_approaches(trajs, ctx, d2, ctx.social.radii(), APPROACH_SPEED)

    def _static_ok(self, ctx: PlanningContext, trajs: Trajectories) -> np.ndarray:
        """Legal against the local costmap (people discs included: moving away is allowed) and
        outside the groups' o-spaces (``GroupCritic.illegal_inside``, with its escape): giving
        way once stepped into a group's o-space, where no trajectory of the planner was legal."""
        ok = np.isfinite(self._occupancy.score(trajs, ctx).cost)
        if ctx.social.groups:
            inside = self._ospace.score(trajs, ctx).illegal.get("ospace_intrusion")
            if inside is not None:  # walking groups have no o-space, and no such mask
                ok &= ~np.asarray(inside, dtype=bool)
        return ok

    # ---- recoveries -----------------------------------------------------------------------
    def _start(self, ctx: PlanningContext, now: float) -> None:
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
        self._phase_start = now
        self._backup_from = ctx.pose[:2].copy()

    def _safe(self, ctx: PlanningContext, twist: FloatArray, duration: float) -> bool:
        params = RolloutParams(sim_time=max(duration, 0.1))
        trajs = rollout(ctx.pose, ctx.velocity, twist[None], self.robot, params)
        if not bool(self._static_ok(ctx, trajs)[0]):
            return False
        if not ctx.social.people:
            return True
        # Never toward a person's forecast position (people are in the costmap only where they
        # are now).
        gaps, _ = evasion_gaps(
            ctx.pose,
            twist[None],
            self.robot,
            ctx.social.positions(),
            ctx.social.velocities(),
            ctx.social.radii(),
            max(duration, 0.1),
        )
        return bool(gaps[0] > 0.0 or gaps[0] >= float(person_gaps(ctx).min()))

    def _recovery_cmd(self, ctx: PlanningContext, now: float) -> FloatArray | None:
        """The current recovery step's twist, or ``None`` when the recovery is over."""
        p, r = self.params, self.robot
        if self._phase == "rotate":
            err = float(wrap_angle(self._target_yaw - ctx.pose[2]))
            timed_out = now - self._phase_start > p.max_rotate_time
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
            timed_out = now - self._phase_start > p.max_rotate_time
            if speed > 0 and moved < p.backup_distance and not timed_out:
                twist = np.array([-speed, 0.0, 0.0])
                if self._safe(ctx, twist, 1.0):
                    return twist
        self._phase = None
        return None

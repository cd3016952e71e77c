"""Navigator: global plan + local window + local planner, one call per control cycle.

Banisetty et al., "Trajectory Planning": a global planner over the map, "regenerated every few
seconds", and a local planner that follows it; move_base's role in ROS.

Decisions:
- A standing group that fails the sanity limits of :mod:`socialnav.social.plausibility` (an
  implausible circle, a far member, two members on one spot) is dropped from the context each
  cycle (:func:`~socialnav.social.plausibility.plausible_context`): it is neither a join
  target nor an o-space to keep out of, and its members are planned around as people.
- The target is the social goal when ``social_goal_fn`` returns one. A *waypoint* social goal
  (``is_waypoint``) is driven to first; once the robot is within its ``position_tolerance``
  (at least the planner's ``xy_goal_tolerance``) it is remembered as passed and the given goal
  becomes the target again.
- One resolved target everywhere: a target inside an obstacle (or not reachable) is replaced by
  the nearest point *reachable from the robot* within ``goal_tolerance`` on the static map
  (navfn ``default_tolerance``); without one, ``NO_PATH`` "goal unreachable" at once, never a
  drive toward it. The global plan, the local planner's goal check and progress check all use
  :attr:`resolved_goal` (also what a caller should measure success against). People are not
  part of that decision: a plan blocked only by people keeps the static plan, and the local
  planner waits (``WAITING``) for them to move.
- Replans every ``replan_period`` s (clock of :class:`~socialnav.planner.limits.CycleClock`: a
  timestamp jumping forward or back cannot stop periodic replanning), whenever the target
  moves by more than 5 cm / 0.05 rad, at once when the pose is more than ``max_path_deviation``
  m off the plan (a relocalization), and every ``waiting_replan_period`` s while ``WAITING``.
- Rate-separated replanning (``replan_mode``, as Nav2 separates its planner and controller
  servers): ``"inline"`` (default) computes a due replan inside the step that needs it.
  ``"deferred"`` is the deterministic mode for simulation: the replan requested at step ``k``
  (from that step's pose, target and people) runs on a worker thread and is applied at step
  ``k + replan_delay`` exactly (joined there, waiting if it is late), so the same inputs give
  the same run whatever the machine's load; ``"threaded"`` (the real loop, e.g. the ROS node)
  applies it at the first step after it finished. Until then the previous plan is followed.
  A periodic (or waiting) replan is requested ``replan_delay`` steps before it is due, from the
  pose the robot will have then (its twist held) and with the people where they will be
  (constant velocity), so it takes effect when an inline replan would: applied late, the plan
  through an oncoming person made a Pioneer brake, back off and intrude (paper suite,
  hallway_oncoming), and one from the older pose stalled it beside a standing person
  (hallway_stationary). A new target, a pose off the plan, or no plan (the first plan, or
  after a failed plan left none) replans inline, as the step must react at once. With
  ``global_search="compiled"`` the search runs without the GIL, so the worker does not stall
  the control step (SciPy's Dijkstra holds it).
- Replan hysteresis (``replan_hysteresis``, default 0: off; in the spirit of Nav2's
  replanning, which keeps a valid path): a periodic replan keeps the current plan (pruned,
  joined to the pose) unless the new one costs that fraction less on the *new* costmap
  (:func:`~socialnav.planner.global_planner.path_costs`) and its highest cell cost is no
  higher than the new plan's (never nearer anyone), so a plan around crossing people stops
  flipping sides; a kept plan that became blocked costs ``inf`` and is replaced. Never
  after a new target or a moved plan end, off the plan, while ``WAITING`` (that replan looks
  for another way), or within ``prune_lookahead`` of the target (the final approach).
- Detour limit (``detour_limit``, default 0: off; with ``detour_layer``): walkers are
  temporary obstacles, so a plan that goes the long way round (or back) to keep clear of
  their personal space is not worth following. Each plan is also searched on the costmap
  with ``detour_layer`` alone (``paccet``: people slower than 0.3 m/s and the o-spaces, no
  walkers; ``presets.standing_space_layer``), and when the social plan is more than
  ``1 + detour_limit`` times as long, that plan is followed instead;
  the local planner, evasion and timed passing deal with the walkers. Generated crowdnav
  (five people crossing a 4 m circle): the plan around their forecast lanes was 2–2.5 times
  as long, and the robot turned round to follow it; in generated hallways the social plan is
  mostly within 1.25 times as long (``presets.DETOUR_LIMIT``: 0.5 in ``paccet``).
- ``meeting_layer``: a global layer that also reads the plan's start pose (e.g. walkers'
  personal space where the robot can meet them), applied after ``global_layer``.
- Interaction partners (``partner_spacing``, default off): while the robot steers to a
  stopping social goal, ``global_layer`` and ``detour_layer`` are called with
  ``partners=`` (person id → distance in m, :func:`~socialnav.social.goals.interaction_distances`
  with the ID objective's threshold and margin): the people it joins, queues behind or presents
  to are drawn at the interaction's own distance, as the local planner's ID scores them
  (``InterpersonalCritic.partner_distance``). Both layers must take that keyword.
- The plan is pruned behind the robot: it starts at the plan vertex nearest the robot among the
  next ``prune_lookahead`` m of the plan (so a plan looping back is not skipped ahead).
- The local window is ``window_size`` m square around the robot (``world.costmap.crop``; off-map
  cells read UNKNOWN). The local planner sees the people within ``people_range`` m of the robot
  (farther ones cannot reach the window within a rollout; groups and queues keep the members
  in view); the global layers see the people on the map.
- Every command of every status is within the robot's velocity box and acceleration window
  (:func:`~socialnav.planner.limits.enforce_limits`; zero commands therefore decelerate).
- ``contact_guard`` (default None: off): every command goes through
  :func:`~socialnav.planner.contact_guard.guard_contact` after the limits, so no command of
  any status (a decelerating zero command included) closes the footprint on a person it
  touches when a reachable one does not.
- ``step`` never raises: invalid input (of any type) gives ``INVALID_INPUT`` naming the field,
  any internal failure too, its ``message`` then beginning "internal error" with the exception's
  text (unless it is an ``InvalidInputError``), and the first failure of each kind (exception
  type and raising line) in an episode (until ``reset``) logged with its traceback on the
  ``socialnav.planner.navigator`` logger (Python's ``logging``; with no handler configured,
  stderr): such a failure is a defect of this library or of a callable given to it (a layer, a
  social-goal function), not of the input, and the status alone hid one (giving way beside a
  walking group, ``INVALID_INPUT`` every cycle). A deferred replan that fails is logged the same
  way (the plan is kept). No input changes the navigator's state unless it is valid.
"""

from __future__ import annotations

import inspect
import logging
import math
from collections.abc import Callable, Mapping
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.ndimage import distance_transform_edt

from socialnav.core.errors import InvalidInputError, checked_bool, is_non_negative_number
from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.contact_guard import ContactGuardParams, guard_contact
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.interpersonal import InterpersonalCritic
from socialnav.planner.global_planner import (
    GlobalPlan,
    GlobalSearch,
    path_costs,
    path_length,
    plan_path,
)
from socialnav.planner.limits import CycleClock, enforce_limits
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.planner.protocols import LocalPlannerProtocol
from socialnav.social.goals import SocialGoal, interaction_distances
from socialnav.social.plausibility import plausible_context
from socialnav.world.costmap import add_obstacle_discs, crop
from socialnav.world.grid import INSCRIBED, LETHAL, Costmap

_LOG = logging.getLogger(__name__)


def _read3(value: Any) -> FloatArray | None:
    """``value`` as a finite float ``(3,)`` array, or None when it is not one (whatever it is)."""
    try:
        out = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return None
    return out if out.shape == (3,) and bool(np.all(np.isfinite(out))) else None


#: (people and structures, given goal (3,), robot pose (3,)) -> the social goal or None
SocialGoalFn = Callable[[SocialContext, FloatArray, FloatArray], SocialGoal | None]
# Per-cycle layer on the local window (e.g. a proxemic layer): (local costmap, people) -> costmap.
CostmapLayer = Callable[[Costmap, SocialContext], Costmap]
#: A global layer that reads where the plan starts: (global costmap, people, start pose (3,) m,
#: rad) -> costmap (e.g. walkers' personal space where the robot can meet them).
MeetingLayer = Callable[[Costmap, SocialContext, FloatArray], Costmap]
#: How a due global replan runs (module docstring): in the step, deferred by a fixed number
#: of steps (deterministic), or threaded (applied when done).
ReplanMode = Literal["inline", "deferred", "threaded"]


@dataclass(frozen=True)
class _PendingPlan:
    future: Future[GlobalPlan]
    apply_at: int  # step index at which a deferred plan is applied
    time: float
    pose: FloatArray
    target: FloatArray
    changed: bool
    off_plan: bool


#: The ID objective's partner rule (threshold and margin, m) that ``partner_spacing`` mirrors.
_PARTNER_RULE = InterpersonalCritic()


def _takes_partners(layer: Callable[..., Costmap]) -> bool:
    """Whether ``layer`` accepts a ``partners=`` keyword (by name or through ``**kwargs``)."""
    params = inspect.signature(layer).parameters.values()
    return any(
        p.kind is inspect.Parameter.VAR_KEYWORD
        or (p.name == "partners" and p.kind is not inspect.Parameter.POSITIONAL_ONLY)
        for p in params
    )


def _drawn(
    layer: CostmapLayer,
    costmap: Costmap,
    social: SocialContext,
    partners: Mapping[int, float] | None,
) -> Costmap:
    """``layer`` applied to ``costmap``, with ``partners=`` when there are any (a layer of a
    ``partner_spacing`` navigator takes it; module docstring)."""
    if not partners:
        return layer(costmap, social)
    fn: Callable[..., Costmap] = layer
    return fn(costmap, social, partners=partners)


def _advanced(social: SocialContext, dt: float) -> SocialContext:
    """``social`` with every person moved ``dt`` s along their velocity (constant velocity)."""
    if dt <= 0.0 or not social.people:
        return social
    return social.with_people(
        tuple(
            replace(
                p,
                position=(
                    float(p.position[0]) + float(p.velocity[0]) * dt,
                    float(p.position[1]) + float(p.velocity[1]) * dt,
                ),
            )
            for p in social.people
        )
    )


class Navigator:
    """Holds the static inflated ``costmap`` and the given ``goal (3,)``; ``step`` returns the
    body twist for the current state. ``local_planner``: any :class:`LocalPlannerProtocol` (a
    ``LocalPlanner`` or a wrapper such as ``RecoveringPlanner``)."""

    def __init__(
        self,
        robot: RobotModel,
        local_planner: LocalPlannerProtocol,
        costmap: Costmap,
        goal: ArrayLike,
        social_goal_fn: SocialGoalFn | None = None,
        replan_period: float = 2.0,
        predict_people: bool = True,
        window_size: float = 10.0,
        prune_lookahead: float = 2.0,
        straight_line_fallback: bool = True,
        record: bool = False,
        costmap_layer: CostmapLayer | None = None,
        people_as_obstacles: bool = True,
        global_layer: CostmapLayer | None = None,
        goal_tolerance: float = 1.0,
        controller_period: float | None = None,
        max_path_deviation: float = 1.0,
        waiting_replan_period: float = 1.0,
        people_range: float | None = None,
        global_search: GlobalSearch = "scipy",
        replan_mode: ReplanMode = "inline",
        replan_delay: int = 2,
        meeting_layer: MeetingLayer | None = None,
        replan_hysteresis: float = 0.0,
        detour_layer: CostmapLayer | None = None,
        detour_limit: float = 0.0,
        contact_guard: ContactGuardParams | None = None,
        partner_spacing: bool = False,
    ) -> None:
        g = np.asarray(goal, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise ValueError(f"goal must be a finite (x, y, yaw), got {goal!r}")
        for name, value in (
            ("replan_period", replan_period),
            ("window_size", window_size),
            ("max_path_deviation", max_path_deviation),
            ("waiting_replan_period", waiting_replan_period),
        ):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be positive")
        if not (np.isfinite(goal_tolerance) and goal_tolerance >= 0):
            raise ValueError("goal_tolerance must be finite and >= 0")
        for name, value in (
            ("replan_hysteresis", replan_hysteresis),
            ("detour_limit", detour_limit),
        ):
            if not is_non_negative_number(value):
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        if detour_limit > 0 and detour_layer is None:
            raise ValueError("detour_limit needs a detour_layer (the plan it is compared with)")
        partner_spacing = checked_bool(partner_spacing, "partner_spacing")  # a ValueError
        if partner_spacing:
            for name, layer in (("global_layer", global_layer), ("detour_layer", detour_layer)):
                if layer is not None and not _takes_partners(layer):
                    raise ValueError(
                        f"partner_spacing needs a {name} that takes partners= (or set"
                        " partner_spacing=False)"
                    )
        self.partner_spacing = partner_spacing
        self.contact_guard = contact_guard
        self.meeting_layer = meeting_layer
        self.replan_hysteresis = float(replan_hysteresis)
        self.detour_layer = detour_layer
        self.detour_limit = float(detour_limit)
        self.robot = robot
        self.local_planner = local_planner
        self.costmap = costmap
        self.goal = g
        self.social_goal_fn = social_goal_fn
        self.replan_period = float(replan_period)
        self.predict_people = predict_people
        self.window_size = float(window_size)
        self.prune_lookahead = float(prune_lookahead)
        self.straight_line_fallback = straight_line_fallback
        self.record = record
        self.costmap_layer = costmap_layer
        self.people_as_obstacles = people_as_obstacles
        self.global_layer = global_layer
        self.goal_tolerance = float(goal_tolerance)
        if controller_period is None:
            params = getattr(local_planner, "params", None)
            inner = getattr(local_planner, "planner", None)
            params = getattr(inner, "params", params) if inner is not None else params
            controller_period = float(getattr(params, "controller_period", 0.1))
        self.controller_period = float(controller_period)
        self.max_path_deviation = float(max_path_deviation)
        self.waiting_replan_period = float(waiting_replan_period)
        if global_search not in ("scipy", "compiled"):
            raise ValueError(f"global_search must be 'scipy' or 'compiled', got {global_search!r}")
        self.global_search: GlobalSearch = global_search
        if replan_mode not in ("inline", "deferred", "threaded"):
            raise ValueError(
                f"replan_mode must be 'inline', 'deferred' or 'threaded', got {replan_mode!r}"
            )
        if not (isinstance(replan_delay, int) and replan_delay >= 1):
            raise ValueError(f"replan_delay must be an int >= 1 (steps), got {replan_delay!r}")
        self.replan_mode: ReplanMode = replan_mode
        self.replan_delay = replan_delay
        self._executor: ThreadPoolExecutor | None = None
        # People farther than this cannot touch the window's rollouts: half the window's
        # diagonal plus 5 m of walking.
        self.people_range = (
            float(people_range) if people_range is not None else self.window_size * 0.75 + 5.0
        )
        geo = costmap.geometry
        self._bounds = (
            geo.origin[0],
            geo.origin[1],
            geo.origin[0] + geo.shape[1] * geo.resolution,
            geo.origin[1] + geo.shape[0] * geo.resolution,
        )
        # Substitute goals need room for the footprint in any orientation (circumscribed
        # radius from every LETHAL/UNKNOWN cell), so the robot can actually stop there.
        free = costmap.costs < LETHAL
        room = distance_transform_edt(free) * geo.resolution if not free.all() else None
        self._roomy = (
            None if room is None else room >= robot.circumscribed_radius + 0.5 * geo.resolution
        )
        self._clock = CycleClock()
        self.reset()

    def reset(self) -> None:
        """Forget the plan, latches and passed waypoints (a new episode)."""
        self.local_planner.reset()
        self._clock.reset()
        self._path: FloatArray | None = None
        self._path_target: FloatArray | None = None
        self._plan_time = -np.inf
        self._passed_waypoints: list[FloatArray] = []
        self._waiting = False
        self._resolved: dict[tuple[float, float], FloatArray | None] = {}
        self.resolved_goal: FloatArray | None = None
        self.last_plan_status = ""
        if getattr(self, "_pending", None) is not None:
            self._discard_pending()
        self._pending: _PendingPlan | None = None
        self._step_index = 0
        self._seen: frozenset[int] | None = None  # ids in view last cycle (contact guard)
        self._failures: set[str] = set()  # kinds of internal error logged already

    # ---- public ---------------------------------------------------------------------------
    def step(
        self, time: float, pose: ArrayLike, velocity: ArrayLike, social: SocialContext
    ) -> PlannerResult:
        """One control cycle: the body twist ``cmd (3,)`` (m/s, rad/s) and a status.

        Valid input: ``time`` a finite float (s; it may repeat or go backwards, see the module
        docstring); ``pose (3,)`` finite world ``(x, y, yaw)`` (m, rad) inside the costmap's
        bounds; ``velocity (3,)`` the finite measured body twist (any magnitude: the command is
        brought within the limits); ``social`` a :class:`SocialContext` (people anywhere,
        any finite velocities). Anything else returns ``INVALID_INPUT`` with a message naming
        the field, a stopping command, and leaves the navigator's state untouched.
        """
        try:
            problem = self._invalid(time, pose, velocity, social)
            if problem:
                stop = PlannerResult(np.zeros(3), PlannerStatus.INVALID_INPUT, None, problem)
                limited = self._limited(stop, velocity)
                return self._guarded(limited, pose, velocity, social, track=False)
            self._step_index += 1
            pose_a, vel_a = np.asarray(pose, float), np.asarray(velocity, float)
            result = self._step(float(time), pose_a, vel_a, social)
            self._waiting = result.status == PlannerStatus.WAITING
            return self._guarded(self._limited(result, velocity), pose_a, vel_a, social)
        except Exception as exc:  # the control loop must survive anything
            return self._failed(exc)

    def _failed(self, exc: Exception) -> PlannerResult:
        """``INVALID_INPUT`` and a zero command for an exception raised inside :meth:`step`:
        an ``InvalidInputError`` (the input's) keeps its text; anything else, a
        ``ConfigurationError`` of a layer included, is an internal error, said so and logged
        once per kind (module docstring)."""
        text = f"{type(exc).__name__}: {exc}"
        if not isinstance(exc, InvalidInputError):
            self._log_once(exc, "Navigator.step, reported as INVALID_INPUT")
            text = f"internal error, {text}"
        return PlannerResult(np.zeros(3), PlannerStatus.INVALID_INPUT, None, text)

    def _log_once(self, exc: Exception, where: str) -> None:
        """Log ``exc`` with its traceback unless its kind (type and raising line) was logged
        in this episode."""
        tb = exc.__traceback__
        while tb is not None and tb.tb_next is not None:
            tb = tb.tb_next
        line = "" if tb is None else f"{tb.tb_frame.f_code.co_filename}:{tb.tb_lineno}"
        kind = f"{type(exc).__name__} at {line}"
        if kind not in self._failures:
            self._failures.add(kind)
            _LOG.error("internal error in %s: %s: %s", where, type(exc).__name__, exc, exc_info=exc)

    @property
    def global_path(self) -> FloatArray | None:
        """The global plan ``(P, 2)`` (m, world frame) the last ``step`` followed, pruned behind
        the robot; ``None`` before the first plan or when planning failed (ROS ``/plan``)."""
        return self._path

    # ---- internals ------------------------------------------------------------------------
    def _invalid(self, time: Any, pose_in: Any, vel_in: Any, social: Any) -> str:
        try:
            t = float(time)
        except (TypeError, ValueError):
            t = math.nan
        if not np.isfinite(t):
            return f"time must be a finite number (s), got {time!r}"
        pose, velocity = _read3(pose_in), _read3(vel_in)
        if pose is None:
            return f"pose must be a finite (3,) array (x, y, yaw), got {pose_in!r}"
        if velocity is None:
            return f"velocity must be a finite (3,) body twist, got {vel_in!r}"
        x0, y0, x1, y1 = self._bounds
        if not (x0 <= pose[0] <= x1 and y0 <= pose[1] <= y1):
            return (
                f"pose ({pose[0]:.6g}, {pose[1]:.6g}) m is outside the map "
                f"[{x0:.6g}, {x1:.6g}] × [{y0:.6g}, {y1:.6g}]"
            )
        if not isinstance(social, SocialContext):
            return f"social must be a SocialContext, got {type(social).__name__}"
        return ""

    def _limited(self, result: PlannerResult, velocity: Any) -> PlannerResult:
        v = _read3(velocity)
        v = np.zeros(3) if v is None else v
        cmd = enforce_limits(result.cmd, v, self.robot, self.controller_period)
        if np.array_equal(cmd, result.cmd):
            return result
        return replace(result, cmd=cmd)

    def _guarded(
        self, result: PlannerResult, pose: Any, velocity: Any, social: Any, track: bool = True
    ) -> PlannerResult:
        """``result`` with its command through the contact guard (module docstring); as it is
        when there is no guard or the pose, velocity or people cannot be read."""
        q, v = _read3(pose), _read3(velocity)
        guard = self.contact_guard
        if guard is None or q is None or v is None or not isinstance(social, SocialContext):
            return result
        ids = frozenset(int(p.id) for p in social.people)
        # nobody has "appeared" beside the robot on the first cycle; an invalid cycle
        # (``track`` False) leaves the navigator's state as it was
        appeared = frozenset() if self._seen is None else ids - self._seen
        if track:
            self._seen = ids
        local = social.within(q[:2], self.people_range)
        cmd, _ = guard_contact(
            result.cmd,
            q,
            v,
            self.robot,
            local,
            self.controller_period,
            guard,
            self.costmap,
            appeared,
        )
        if np.array_equal(cmd, result.cmd):
            return result
        why = "contact guard: no push into a person in contact"
        return replace(
            result, cmd=cmd, message=f"{result.message}; {why}" if result.message else why
        )

    def _step(
        self, time: float, pose: FloatArray, velocity: FloatArray, social: SocialContext
    ) -> PlannerResult:
        now = self._clock.tick(time)
        # a group no conversation could form (socialnav.social.plausibility) is neither a join
        # target nor an o-space to keep out of: its members are planned around as people
        social = plausible_context(social)
        social_goal = self._social_goal(social, pose)
        target = self._target(social_goal, pose)
        if target is self.goal:
            social_goal = None  # a passed waypoint no longer pulls the robot back
        resolved = self._resolve(target, pose)
        if resolved is None:
            self.resolved_goal = None
            why = (
                "goal unreachable: no point reachable from the robot within "
                f"{self.goal_tolerance} m"
            )
            return PlannerResult(np.zeros(3), PlannerStatus.NO_PATH, None, why)
        self.resolved_goal = resolved
        partners = self._partners(social, social_goal)
        path = self._global_path(now, pose, resolved, social, velocity, partners)
        if path is None:
            return PlannerResult(
                np.zeros(3), PlannerStatus.NO_PATH, None, f"global planner: {self.last_plan_status}"
            )
        local_social = social.within(pose[:2], self.people_range)
        local = crop(self.costmap, pose[:2], self.window_size)
        local = self._with_people(local, local_social)
        if self.costmap_layer is not None:
            local = self.costmap_layer(local, local_social)
        ctx = PlanningContext(
            pose=pose,
            velocity=velocity,
            goal=resolved,
            global_path=path,
            costmap=local,
            robot=self.robot,
            social=local_social,
            social_goal=social_goal,
            predict_people=self.predict_people,
            time=time,
        )
        return self.local_planner.plan(ctx, record=self.record)

    def _social_goal(self, social: SocialContext, pose: FloatArray) -> SocialGoal | None:
        if self.social_goal_fn is None:
            return None
        return self.social_goal_fn(social, self.goal, pose)

    def _partners(self, social: SocialContext, sg: SocialGoal | None) -> dict[int, float]:
        """Person id → the interaction's own distance (m) of the stopping social goal's
        partners (``partner_spacing``; module docstring); empty otherwise."""
        if not self.partner_spacing or sg is None or sg.is_waypoint or not social.people:
            return {}
        own = interaction_distances(
            social, sg.pose, _PARTNER_RULE.threshold, _PARTNER_RULE.partner_margin
        )
        return {
            p.id: float(d)
            for p, d in zip(social.people, own, strict=True)
            if d < _PARTNER_RULE.threshold
        }

    def _target(self, sg: SocialGoal | None, pose: FloatArray) -> FloatArray:
        if sg is None:
            return self.goal
        sg_pose = np.asarray(sg.pose, dtype=float)
        if not sg.is_waypoint:
            return sg_pose
        tol = max(float(sg.position_tolerance), 0.1)
        if any(np.hypot(*(sg_pose[:2] - w[:2])) <= max(tol, 0.3) for w in self._passed_waypoints):
            return self.goal
        if np.hypot(*(sg_pose[:2] - pose[:2])) <= tol:
            self._passed_waypoints.append(sg_pose)
            return self.goal
        return sg_pose

    def _resolve(self, target: FloatArray, pose: FloatArray) -> FloatArray | None:
        """The target, or its reachable substitute on the static map (cached per target and
        the robot's connected region; module docstring)."""
        geo = self.costmap.geometry
        cell = geo.world_to_cell(target[:2])
        row, col = int(cell[0]), int(cell[1])
        free_target = bool(geo.in_bounds(cell)) and int(self.costmap.costs[row, col]) < INSCRIBED
        key = (round(float(target[0]), 3), round(float(target[1]), 3))
        if key in self._resolved:
            hit = self._resolved[key]
            if hit is None or np.array_equal(hit[:2], target[:2]):
                return None if hit is None else target
            return np.array([hit[0], hit[1], target[2]])
        plan = plan_path(
            self.costmap,
            pose[:2],
            target[:2],
            tolerance=self.goal_tolerance,
            substitutes=self._roomy,
            search=self.global_search,
        )
        if plan.status != "OK" or plan.goal is None:
            if plan.status == "START_BLOCKED":
                return target  # the robot's cell is an obstacle: no verdict on the goal
            self._resolved[key] = None
            return None
        if free_target and np.allclose(plan.goal, target[:2]):
            out = target
        else:
            out = np.array([plan.goal[0], plan.goal[1], target[2]])
        if len(self._resolved) > 64:
            self._resolved.clear()
        self._resolved[key] = out
        return out

    def _with_people(
        self, costmap: Costmap, social: SocialContext, static: bool = False
    ) -> Costmap:
        """People as obstacles, as a laser-fed obstacle layer shows them to every planner
        (``static``: ``costmap`` is the fixed map, whose own inflation is kept across calls)."""
        if not (self.people_as_obstacles and social.people):
            return costmap
        # Grown by half a cell diagonal: a cell is marked when its centre is inside the disc, so
        # a footprint point up to that far inside the true disc could land on an unmarked cell
        # (a PR2 corner grazed a queue member it turned beside by 4 cm).
        grown = social.radii() + costmap.resolution * np.sqrt(2.0) / 2.0
        discs = np.column_stack([social.positions(), grown])
        return add_obstacle_discs(costmap, discs, self.robot.inscribed_radius, reuse_static=static)

    def _on_map(self, social: SocialContext) -> SocialContext:
        """The people on the map (1 m margin): the only ones a global layer can draw."""
        x0, y0, x1, y1 = self._bounds
        center = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
        return social.within(center, float(np.hypot(x1 - x0, y1 - y0)) / 2 + 1.0)

    def _off_plan(self, pose: FloatArray) -> bool:
        path = self._path
        if path is None or path.shape[0] == 0:
            return False
        if path.shape[0] == 1:
            return bool(np.hypot(*(path[0] - pose[:2])) > self.max_path_deviation)
        a, b = path[:-1], path[1:]
        ab = b - a
        denom = np.maximum((ab * ab).sum(axis=1), 1e-12)
        s = np.clip(((pose[:2] - a) * ab).sum(axis=1) / denom, 0.0, 1.0)
        d = np.hypot(*(a + s[:, None] * ab - pose[:2]).T)
        return bool(d.min() > self.max_path_deviation)

    def _global_path(
        self,
        now: float,
        pose: FloatArray,
        target: FloatArray,
        social: SocialContext,
        velocity: FloatArray | None = None,
        partners: Mapping[int, float] | None = None,
    ) -> FloatArray | None:
        changed = self._path_target is None or (
            np.hypot(*(target[:2] - self._path_target[:2])) > 0.05
            or abs(float(wrap_angle(target[2] - self._path_target[2]))) > 0.05
        )
        self._collect(now)
        age = now - self._plan_time
        off_plan = self._off_plan(pose)
        # A periodic (or waiting) replan is known in advance: off-line modes request it
        # ``replan_delay`` steps early so it takes effect at the step an inline replan would.
        lead = 0.0 if self.replan_mode == "inline" else self._lead()
        scheduled = age >= self.replan_period - lead or (
            self._waiting and age >= self.waiting_replan_period - lead
        )
        urgent = changed or self._path is None or off_plan  # react now, as inline does
        if scheduled and not urgent and self.replan_mode != "inline":
            if self._pending is None:  # one replan in flight at a time
                self._request(now, pose, target, social, changed, off_plan, velocity, partners)
        elif urgent or scheduled:
            self._discard_pending()
            # A waiting robot replans to find another way: no hysteresis then.
            kept = None if (changed or off_plan or self._waiting) else self._path
            fresh = changed or self._path is None
            plan = self._compute_plan(pose, target, social, fresh, kept, partners)
            self._apply_plan(now, pose, target, plan, changed, off_plan)
        if self._path is None:
            return None
        self._path = self._prune(self._path, pose)
        return self._path

    def _compute_plan(
        self,
        pose: FloatArray,
        target: FloatArray,
        social: SocialContext,
        fresh: bool,
        previous: FloatArray | None = None,
        partners: Mapping[int, float] | None = None,
    ) -> GlobalPlan:
        """The global plan from ``pose`` to ``target`` around the people on the map (pure: it
        reads only its arguments and the navigator's fixed configuration, so it may run on
        the replanning worker). ``fresh``: no plan to this target yet. ``previous (P, 2)``:
        the plan followed so far to the same target, kept when the new one is not clearly
        cheaper (``replan_hysteresis``)."""
        on_map = self._on_map(social)
        static_people = self._with_people(self.costmap, on_map, static=True)
        costmap = static_people
        if self.global_layer is not None:
            costmap = _drawn(self.global_layer, costmap, on_map, partners)
        if self.meeting_layer is not None:
            costmap = self.meeting_layer(costmap, on_map, pose)
        plan = plan_path(
            costmap,
            pose[:2],
            target[:2],
            tolerance=0.5 * self.robot.circumscribed_radius,
            search=self.global_search,
        )
        if self.detour_limit > 0.0 and self.detour_layer is not None and on_map.people:
            plan, costmap = self._limit_detour(
                plan, costmap, self.detour_layer, static_people, on_map, pose, target, partners
            )
        if plan.status != "OK" and costmap is not self.costmap and fresh:
            # Blocked only by people: follow the static plan; the local planner waits.
            # (With a plan to this target already, it is kept below.)
            static = plan_path(self.costmap, pose[:2], target[:2], search=self.global_search)
            plan = static if static.status == "OK" else plan
        if (
            self.replan_hysteresis > 0.0
            and previous is not None
            and previous.shape[0] >= 2
            and plan.status == "OK"
            and plan.path is not None
            # Only a plan to the very same end point: a target that drifts (a queue's tail
            # moving up by less than the 5 cm that counts as a new target) is followed.
            and np.array_equal(previous[-1], plan.path[-1])
            # Near the target the plan is the final approach, always fresh (a kept stale
            # vertex beside the goal kept a PR2 circling its queue slot: dev queue seed 10).
            and float(np.hypot(*(plan.path[-1] - pose[:2]))) > self.prune_lookahead
        ):
            kept = np.concatenate([pose[None, :2], self._prune(previous, pose)])
            old, old_peak = path_costs(costmap, kept, pose[:2])
            new, new_peak = path_costs(costmap, plan.path, pose[:2])
            # Kept only if not clearly dearer and never nearer anyone at its worst point (a
            # whole-path margin let an overtaking plan stay 1.17 m beside the walker: paper
            # suite hallway_overtake).
            if old <= (1.0 + self.replan_hysteresis) * new and old_peak <= new_peak:
                return GlobalPlan(kept, "OK", old, plan.goal)
        return plan

    def _limit_detour(
        self,
        plan: GlobalPlan,
        costmap: Costmap,
        layer: CostmapLayer,
        static_people: Costmap,
        on_map: SocialContext,
        pose: FloatArray,
        target: FloatArray,
        partners: Mapping[int, float] | None = None,
    ) -> tuple[GlobalPlan, Costmap]:
        """``(plan, costmap)``, or the plan on ``plain`` (``static_people`` with ``layer``
        alone) and ``plain`` when ``plan`` is more than ``1 + detour_limit`` times as long as
        that one (module docstring)."""
        if plan.path is None:
            return plan, costmap
        tolerance = 0.5 * self.robot.circumscribed_radius
        # No plan is shorter than the straight line to within the tolerance of the target: a
        # plan within the limit of that needs neither the layer nor a second search (most).
        floor = max(float(np.hypot(*(target[:2] - pose[:2]))) - tolerance, 0.0)
        length = path_length(plan.path)
        if length <= (1.0 + self.detour_limit) * floor:
            return plan, costmap
        plain = _drawn(layer, static_people, on_map, partners)
        if np.array_equal(plain.costs, costmap.costs):
            return plan, costmap  # no walker left out
        short = plan_path(
            plain, pose[:2], target[:2], tolerance=tolerance, search=self.global_search
        )
        if short.path is None:
            return plan, costmap
        if length <= (1.0 + self.detour_limit) * path_length(short.path):
            return plan, costmap
        return short, plain  # the long way round walkers

    def _apply_plan(
        self,
        now: float,
        pose: FloatArray,
        target: FloatArray,
        plan: GlobalPlan,
        changed: bool,
        off_plan: bool,
    ) -> None:
        self.last_plan_status = plan.status
        self._plan_time = now
        if plan.path is not None and plan.path.shape[0] > 0:
            self._path = np.asarray(plan.path, dtype=float)
        elif changed or self._path is None or off_plan:
            self._path = np.stack([pose[:2], target[:2]]) if self.straight_line_fallback else None
        self._path_target = target.copy()

    # ---- rate-separated replanning ----------------------------------------------------------
    def _request(
        self,
        now: float,
        pose: FloatArray,
        target: FloatArray,
        social: SocialContext,
        changed: bool,
        off_plan: bool,
        velocity: FloatArray | None = None,
        partners: Mapping[int, float] | None = None,
    ) -> None:
        """Start the replan of this step on the worker (module docstring, ``replan_mode``)."""
        if self._executor is None:
            self._executor = ThreadPoolExecutor(1, thread_name_prefix="socialnav-replan")
        pose, target = pose.copy(), target.copy()
        # The plan is used from ``lead`` s on: it starts where the robot will be then (its
        # current twist held) and goes around people where they will be (constant velocity),
        # as an inline replan at that step would, not through someone's new place.
        lead = self._lead()
        start = pose if velocity is None else self._predicted(pose, velocity, lead)
        ahead = _advanced(social, lead)
        keep = not (changed or off_plan or self._waiting or self._path is None)
        kept = self._path.copy() if keep and self._path is not None else None
        future = self._executor.submit(
            self._compute_plan, start, target, ahead, changed, kept, partners
        )
        self._pending = _PendingPlan(
            future, self._step_index + self.replan_delay, now, pose, target, changed, off_plan
        )

    def _predicted(self, pose: FloatArray, velocity: FloatArray, dt: float) -> FloatArray:
        """``pose (3,)`` after ``dt`` s at the body twist ``velocity (3,)`` (midpoint heading),
        kept on the map."""
        yaw = float(pose[2]) + 0.5 * float(velocity[2]) * dt
        c, s = np.cos(yaw), np.sin(yaw)
        x = float(pose[0]) + (c * float(velocity[0]) - s * float(velocity[1])) * dt
        y = float(pose[1]) + (s * float(velocity[0]) + c * float(velocity[1])) * dt
        x0, y0, x1, y1 = self._bounds
        return np.array([min(max(x, x0), x1), min(max(y, y0), y1), float(pose[2])])

    def _lead(self) -> float:
        """Seconds between a replan's request and its use (``replan_delay`` control periods;
        for ``"threaded"`` the expected delay)."""
        return self.replan_delay * self.controller_period

    def _collect(self, now: float) -> None:
        """Apply the pending plan when its step has come (deferred: joined, waiting if late)
        or, threaded, as soon as it is done."""
        pending = self._pending
        if pending is None:
            return
        if self.replan_mode == "deferred":
            if self._step_index < pending.apply_at:
                return
        elif not pending.future.done():
            return
        self._pending = None
        try:
            plan = pending.future.result()
        except Exception as exc:  # a failed replan keeps the current plan
            self.last_plan_status = f"replan failed: {type(exc).__name__}: {exc}"
            if not isinstance(exc, InvalidInputError):
                self._log_once(exc, "a deferred replan, the current plan kept")
            return
        # The period counts from when the plan took effect, as for an inline replan.
        self._apply_plan(now, pending.pose, pending.target, plan, pending.changed, pending.off_plan)

    def _discard_pending(self) -> None:
        if self._pending is not None:
            self._pending.future.cancel()
            self._pending = None

    def __getstate__(self) -> dict[str, Any]:
        # The worker and an in-flight plan stay with the process (a copy replans anew).
        state = self.__dict__.copy()
        state["_executor"] = None
        state["_pending"] = None
        return state

    def close(self) -> None:
        """Stop the replanning worker (it is started again when needed)."""
        self._discard_pending()
        if self._executor is not None:
            self._executor.shutdown(wait=True)
            self._executor = None

    def _prune(self, path: FloatArray, pose: FloatArray) -> FloatArray:
        if path.shape[0] < 2:
            return path
        seg = np.linalg.norm(np.diff(path, axis=0), axis=1)
        s = np.concatenate([[0.0], np.cumsum(seg)])
        candidates = np.flatnonzero(s <= self.prune_lookahead)
        d = np.hypot(*(path[candidates] - pose[:2]).T)
        i = int(candidates[np.argmin(d)])
        return path[i:]

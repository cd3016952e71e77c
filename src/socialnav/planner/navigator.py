"""Navigator: global plan + local window + local planner, one call per control cycle.

Banisetty et al., "Trajectory Planning": a global planner over the map, "regenerated every few
seconds", and a local planner that follows it; move_base's role in ROS.

Decisions:
- The target is the social goal when ``social_goal_fn`` returns one. A *waypoint* social goal
  (``is_waypoint``) is driven to first; once the robot is within its ``position_tolerance``
  (at least the planner's ``xy_goal_tolerance``) it is remembered as passed and the given goal
  becomes the target again.
- Replans every ``replan_period`` s and whenever the target moves by more than 5 cm / 0.05 rad.
  When the global planner fails, the previous plan to the same target is kept; failing that, a
  straight line to the target is used when ``straight_line_fallback`` (the local critics still
  judge it; recoveries handle dead ends), else the status is ``NO_PATH``.
- The plan is pruned behind the robot: it starts at the plan vertex nearest the robot among the
  next ``prune_lookahead`` m of the plan (so a plan looping back is not skipped ahead).
- The local window is ``window_size`` m square around the robot (``world.costmap.crop``; off-map
  cells read UNKNOWN).
- ``step`` never raises: bad input gives ``INVALID_INPUT``, any internal failure too (with the
  exception text in ``message``).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.context import PlanningContext
from socialnav.planner.global_planner import nearest_free, plan_path
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.planner.protocols import LocalPlannerProtocol
from socialnav.social.goals import SocialGoal
from socialnav.world.costmap import add_obstacle_discs, crop
from socialnav.world.grid import Costmap

#: (people and structures, given goal (3,), robot pose (3,)) -> the social goal or None
SocialGoalFn = Callable[[SocialContext, FloatArray, FloatArray], SocialGoal | None]
# Per-cycle layer on the local window (e.g. a proxemic layer): (local costmap, people) -> costmap.
CostmapLayer = Callable[[Costmap, SocialContext], Costmap]


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
    ) -> None:
        g = np.asarray(goal, dtype=float)
        if g.shape != (3,) or not np.all(np.isfinite(g)):
            raise ValueError(f"goal must be a finite (x, y, yaw), got {goal!r}")
        if not (np.isfinite(replan_period) and replan_period > 0):
            raise ValueError("replan_period must be positive")
        if not (np.isfinite(window_size) and window_size > 0):
            raise ValueError("window_size must be positive")
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
        self.reset()

    def reset(self) -> None:
        """Forget the plan, latches and passed waypoints (a new episode)."""
        self.local_planner.reset()
        self._path: FloatArray | None = None
        self._path_target: FloatArray | None = None
        self._plan_time = -np.inf
        self._passed_waypoints: list[FloatArray] = []
        self.last_plan_status = ""

    # ---- public ---------------------------------------------------------------------------
    def step(
        self, time: float, pose: ArrayLike, velocity: ArrayLike, social: SocialContext
    ) -> PlannerResult:
        """The body twist for ``pose (3,)``, ``velocity (3,)`` at ``time`` (s); never raises."""
        try:
            return self._step(float(time), pose, velocity, social)
        except Exception as exc:  # the control loop must survive anything
            return PlannerResult(
                np.zeros(3), PlannerStatus.INVALID_INPUT, None, f"{type(exc).__name__}: {exc}"
            )

    @property
    def global_path(self) -> FloatArray | None:
        """The global plan ``(P, 2)`` (m, world frame) the last ``step`` followed, pruned behind
        the robot; ``None`` before the first plan or when planning failed (ROS ``/plan``)."""
        return self._path

    # ---- internals ------------------------------------------------------------------------
    def _step(
        self, time: float, pose_in: ArrayLike, vel_in: ArrayLike, social: SocialContext
    ) -> PlannerResult:
        pose = np.asarray(pose_in, dtype=float)
        velocity = np.asarray(vel_in, dtype=float)
        if (
            pose.shape != (3,)
            or velocity.shape != (3,)
            or not np.isfinite(time)
            or not np.all(np.isfinite(pose))
            or not np.all(np.isfinite(velocity))
        ):
            return PlannerResult(
                np.zeros(3),
                PlannerStatus.INVALID_INPUT,
                None,
                "pose, velocity and time must be finite; pose/velocity (3,)",
            )
        social_goal = self._social_goal(social, pose)
        target = self._target(social_goal, pose)
        if target is self.goal:
            social_goal = None  # a passed waypoint no longer pulls the robot back
        path = self._global_path(time, pose, target, social)
        if path is None:
            return PlannerResult(
                np.zeros(3), PlannerStatus.NO_PATH, None, f"global planner: {self.last_plan_status}"
            )
        local = crop(self.costmap, pose[:2], self.window_size)
        local = self._with_people(local, social)
        if self.costmap_layer is not None:
            local = self.costmap_layer(local, social)
        ctx = PlanningContext(
            pose=pose,
            velocity=velocity,
            goal=target,
            global_path=path,
            costmap=local,
            robot=self.robot,
            social=social,
            social_goal=social_goal,
            predict_people=self.predict_people,
            time=time,
        )
        return self.local_planner.plan(ctx, record=self.record)

    def _social_goal(self, social: SocialContext, pose: FloatArray) -> SocialGoal | None:
        if self.social_goal_fn is None:
            return None
        return self.social_goal_fn(social, self.goal, pose)

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

    def _with_people(self, costmap: Costmap, social: SocialContext) -> Costmap:
        """People as obstacles, as a laser-fed obstacle layer shows them to every planner."""
        if not (self.people_as_obstacles and social.people):
            return costmap
        discs = np.column_stack([social.positions(), social.radii()])
        return add_obstacle_discs(costmap, discs, self.robot.inscribed_radius)

    def _global_path(
        self, time: float, pose: FloatArray, target: FloatArray, social: SocialContext
    ) -> FloatArray | None:
        changed = self._path_target is None or (
            np.hypot(*(target[:2] - self._path_target[:2])) > 0.05
            or abs(float(wrap_angle(target[2] - self._path_target[2]))) > 0.05
        )
        if changed or time - self._plan_time >= self.replan_period or self._path is None:
            costmap = self._with_people(self.costmap, social)
            if self.global_layer is not None:
                costmap = self.global_layer(costmap, social)
            plan = plan_path(costmap, pose[:2], target[:2])
            if plan.status == "GOAL_BLOCKED" and self.goal_tolerance > 0:
                # navfn default_tolerance: plan to the nearest free point instead
                substitute = nearest_free(costmap, target[:2], self.goal_tolerance)
                if substitute is not None:
                    plan = plan_path(costmap, pose[:2], substitute)
            self.last_plan_status = plan.status
            self._plan_time = time
            if plan.path is not None and plan.path.shape[0] > 0:
                self._path = np.asarray(plan.path, dtype=float)
            elif changed or self._path is None:
                self._path = (
                    np.stack([pose[:2], target[:2]]) if self.straight_line_fallback else None
                )
            self._path_target = target.copy()
        if self._path is None:
            return None
        self._path = self._prune(self._path, pose)
        return self._path

    def _prune(self, path: FloatArray, pose: FloatArray) -> FloatArray:
        if path.shape[0] < 2:
            return path
        seg = np.linalg.norm(np.diff(path, axis=0), axis=1)
        s = np.concatenate([[0.0], np.cumsum(seg)])
        candidates = np.flatnonzero(s <= self.prune_lookahead)
        d = np.hypot(*(path[candidates] - pose[:2]).T)
        i = int(candidates[np.argmin(d)])
        return path[i:]

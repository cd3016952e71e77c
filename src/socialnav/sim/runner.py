"""Run one episode: scenario × controller (or navground behaviour) × robot × seed × human model.

``run_episode`` is a pure function of its arguments (names or picklable specs in, an
:class:`EpisodeResult` out), so batch runners can ship it to worker processes. The scenario's
jitter is drawn from ``numpy.random.default_rng(seed)``; the same arguments give an identical
record.

Timing: one sample per control period ``dt`` (0.1 s, the paper's). Sample ``k`` holds the state
at ``t = k·dt`` and the command applied for the following ``dt``. The episode ends at the first
sample where the controller reports ``GOAL_REACHED`` with a zero command (commands act
instantly, so the robot is stopped), or at the time limit (sample ``t = time_limit`` included).
Every controller, navground behaviours included, runs through the same loop body.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from navground import core

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.robot import ROBOT_MODELS, RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.record import EvaluationRecord
from socialnav.sim import baselines as _baselines  # noqa: F401  (registers navground, go_to_goal)
from socialnav.sim import stack as _stack  # noqa: F401  (registers the planner presets)
from socialnav.sim.controller import GOAL_REACHED, Controller, ControllerFactory, make_controller
from socialnav.sim.engine import ControllerBehavior, SimWorld, build_world, pose_of
from socialnav.sim.recorder import EpisodeRecorder, StaticGeometry, context_at
from socialnav.sim.scenario import Scenario, load_scenario
from socialnav.sim.target import Target, resolve_target

__all__ = ["EpisodeResult", "Target", "resolve_target", "run_episode", "simulate_world"]

#: a controller counts as stopped below these speeds (m/s, rad/s)
STOP_EPS = 1e-3


@dataclass
class EpisodeResult:
    """``record``; ``diagnostics`` one evaluation record (or ``None``) per sample when asked;
    ``wall_time`` (s); ``step_seconds`` the wall time of each control step (s), controller
    included (timing: not part of the deterministic record)."""

    record: EpisodeRecord
    diagnostics: list[EvaluationRecord | None] = field(default_factory=list)
    wall_time: float = 0.0
    step_seconds: list[float] = field(default_factory=list)

    @property
    def step_ms_median(self) -> float:
        """Median control-step time (ms), NaN for an empty episode."""
        return float(np.median(self.step_seconds) * 1e3) if self.step_seconds else float("nan")


def _robot_model(robot: RobotModel | str) -> RobotModel:
    if isinstance(robot, RobotModel):
        return robot
    if robot not in ROBOT_MODELS:
        raise ConfigurationError(f"unknown robot {robot!r}; known: {', '.join(ROBOT_MODELS)}")
    return ROBOT_MODELS[robot]


def _controller(
    spec: Controller | str | ControllerFactory, params: dict[str, Any] | None
) -> tuple[Controller, str]:
    if isinstance(spec, str):
        return make_controller(spec, **(params or {})), spec
    if not isinstance(spec, type) and isinstance(spec, Controller):
        return spec, type(spec).__name__
    if callable(spec):
        ctrl = spec(**(params or {}))
        return ctrl, getattr(spec, "__name__", type(ctrl).__name__)
    raise ConfigurationError(f"not a controller, controller name or factory: {spec!r}")


CONTEXTS = ("given", "detected")


def check_context(context: str) -> None:
    """Raise :class:`ConfigurationError` unless ``context`` is one of :data:`CONTEXTS`."""
    if context not in CONTEXTS:
        raise ConfigurationError(f"unknown context {context!r}; use given or detected")


#: Detected context: the robot watches the scene this long (s) before it starts to move, so the
#: estimator's hysteresis has settled (a robot is switched on before it is sent somewhere).
WARMUP = 1.0


class DetectedContext:
    """The robot's view in ``--context detected``: true people → :class:`PerceptionModel`
    tracks → :class:`~socialnav.social.perception.ContextEstimator` → :class:`SocialContext`.

    The map knowledge is what a semantic map holds: the artworks and the queues' service points
    (desks) of the scenario — never who stands where or with whom. Detected F-formations get
    the mode of the scenario's groups (``lead`` when the task is to lead a group): the mode is
    the robot's task, not something to perceive.
    """

    def __init__(self, scn: Scenario, seed: int, noise: Any = None) -> None:
        from socialnav.core.scene import Artwork
        from socialnav.sim.perception import DEFAULT_PERCEPTION, PerceptionModel
        from socialnav.social.perception import ContextEstimator, EstimatorParams, MapKnowledge

        knowledge = MapKnowledge(
            artworks=tuple(
                Artwork(tuple(a.center), a.width, a.facing)  # type: ignore[arg-type]
                for a in scn.artworks
            ),
            service_points=np.array([q.service_point for q in scn.queues], dtype=float),
        )
        mode = "lead" if any(g.mode == "lead" for g in scn.groups) else "join"
        self.estimator = ContextEstimator(knowledge, EstimatorParams(group_mode=mode))
        # a seed stream of its own, so perception noise never shifts the scenario's jitter
        self.perception = PerceptionModel(
            DEFAULT_PERCEPTION if noise is None else noise, scn.bounds(), seed=10_007 + seed
        )
        self.ids = np.array([p.id for p in scn.people], dtype=np.int64)
        self.radii = np.array([p.radius for p in scn.people], dtype=float)
        self.seconds: list[float] = []

    def observe(
        self,
        t: float,
        pos: FloatArray,
        vel: FloatArray,
        yaw: FloatArray,
        ids: np.ndarray | None = None,
        radii: FloatArray | None = None,
    ) -> SocialContext:
        """The context the robot perceives at ``t`` (s) of true people ``pos``, ``vel`` ``(K,
        2)`` and ``yaw (K,)``: the scenario's people, or those of ``ids (K,)`` with ``radii
        (K,)`` (a recorded crowd, whose people come and go)."""
        who = self.ids if ids is None else np.asarray(ids, dtype=np.int64)
        size = self.radii if radii is None else np.asarray(radii, dtype=float)
        tracks = self.perception.observe(who, pos, vel, yaw, size)
        started = _time.perf_counter()  # the estimator runs on the robot; the sensor model not
        context = self.estimator.update(t, tracks).context
        self.seconds.append(_time.perf_counter() - started)
        return context

    def warm_up(self, social0: SocialContext, dt: float) -> SocialContext:
        pos, vel, yaw = social0.positions(), social0.velocities(), social0.yaws()
        steps = max(1, round(WARMUP / dt))
        context = social0
        for k in range(steps):
            t = (k - steps) * dt
            # walkers are seen where they were: their recent past, at constant velocity
            context = self.observe(t, pos + vel * t, vel, yaw)
        return context


def _reset(ctrl: Controller, scn: Scenario, model: RobotModel, social: SocialContext) -> None:
    """Reset, handing the initial context to controllers that accept one."""
    import inspect

    try:
        takes_social = "social" in inspect.signature(ctrl.reset).parameters
    except (TypeError, ValueError):
        takes_social = False
    if takes_social:
        ctrl.reset(scn, model, social=social)  # type: ignore[call-arg]
    else:
        ctrl.reset(scn, model)


def run_episode(
    scenario: Scenario | str,
    controller: Controller | str | ControllerFactory,
    robot: RobotModel | str = "pr2",
    seed: int = 0,
    humans: str = "scripted",
    record_diagnostics: bool = False,
    *,
    controller_params: dict[str, Any] | None = None,
    reactive_behavior: str = "HL",
    vary_group_sizes: bool = False,
    context: str = "given",
    perception: Any = None,
) -> EpisodeResult:
    """Simulate one episode and record it.

    ``controller``: a :class:`Controller`, a factory, or a name registered in ``CONTROLLERS``
    (built with ``controller_params``; navground behaviours are registered as ``orca``, ``hl``,
    ``social_force``). ``humans``: ``"scripted"`` (the paper) or ``"reactive"`` (navground
    ``reactive_behavior``, default ``HL``). Success is measured against the target the
    controller recorded last (``PlannerResult.target``) when it resolved one other than the
    given goal, else the scenario's (:func:`~socialnav.sim.target.resolve_target`); the record's
    ``meta["target_source"]`` says which. ``diagnostics`` (when
    ``record_diagnostics``) holds each sample's evaluation record or ``None``.

    ``context``: ``"given"`` (the scenario's groups, queues and viewers, exact people) or
    ``"detected"`` (the controller sees only noisy tracks from
    :class:`~socialnav.sim.perception.PerceptionModel` with ``perception`` noise, default
    :data:`~socialnav.sim.perception.DEFAULT_PERCEPTION`, and the structures the estimator finds
    in them; see :class:`DetectedContext`). With the context detected, success is measured at
    the social goal of the *true* context seen from the robot's final pose (the controller's own
    target may be wrong: that is what is measured), ``meta["target_source"]`` =
    ``"true context"``.
    """
    check_context(context)
    wall_start = _time.perf_counter()
    scn = load_scenario(scenario) if isinstance(scenario, str) else scenario
    scn = scn.randomize(seed, vary_group_sizes=vary_group_sizes)
    if scn.humans is not None:  # the scene needs its own human model (CrowdNav's ORCA crowd)
        humans = scn.humans
        reactive_behavior = scn.reactive_behavior or reactive_behavior
    model = _robot_model(robot)
    social0 = scn.social_context(scn.start)
    target = resolve_target(scn, social0)
    detector = DetectedContext(scn, seed, perception) if context == "detected" else None
    seen0 = social0 if detector is None else detector.warm_up(social0, float(scn.control_period))

    ctrl, planner_name = _controller(controller, controller_params)
    _reset(ctrl, scn, model, seen0)
    ctrl_behavior = ControllerBehavior()
    ctrl_behavior.controller = ctrl
    ctrl_behavior.robot_model = model
    simw = build_world(scn, model, ctrl_behavior, humans, reactive_behavior, seed=seed)

    static = StaticGeometry(scn.walls_array(), tuple(scn.obstacle_polygons()), scn.discs_array())
    recorder = EpisodeRecorder(
        model.polygon,
        simw.people_ids,
        np.array([p.radius for p in scn.people], dtype=float),
        static,
    )
    diagnostics: list[EvaluationRecord | None] = []
    step_seconds: list[float] = []
    driven_to: FloatArray | None = None
    dt = float(scn.control_period)
    last = round(scn.time_limit / dt)
    reason = "time_limit"
    for k in range(last + 1):
        t = k * dt
        pose = pose_of(simw.robot)
        pos, vel, yaw = simw.people_state()
        if detector is None:
            social = context_at(social0, pos, vel, yaw)
        else:
            social = detector.observe(t, pos, vel, yaw)
        ctrl_behavior.observe = lambda _dt, t=t, social=social: (t, social)
        started = _time.perf_counter()
        simw.world.update(dt)
        step_seconds.append(_time.perf_counter() - started)
        if detector is not None:  # the estimator's time counts toward the control step
            step_seconds[-1] += detector.seconds[-1]
        out = ctrl_behavior.last_output
        cmd = ctrl_behavior.last_cmd
        status = out.status.value if out is not None else "NO_CONTROLLER"
        if out is not None and out.target is not None and np.all(np.isfinite(out.target)):
            driven_to = out.target
        if record_diagnostics:
            diagnostics.append(None if out is None else out.record)
        done = status == GOAL_REACHED and bool(np.all(np.abs(cmd) < STOP_EPS))
        recorder.add(t, pose, cmd, pos, vel, status, people_yaw=yaw)
        if done:
            reason = "goal_reached"
            break

    # Success is measured at the target the controller drove to when it resolved one itself (its
    # social goal, a reachable substitute for a blocked goal); a controller that drove to the
    # given goal is still measured at the scenario's social goal, which it may have ignored.
    own = driven_to is not None and not np.allclose(driven_to, np.asarray(scn.goal, dtype=float))
    measured = driven_to if own and target.waypoint is None else target.pose
    source = "controller" if own and target.waypoint is None else "scenario"
    extra: dict[str, Any] = {"context": context}
    if detector is not None:
        # the true context's social goal, seen from where the robot ended
        # resolved with the controller's own rule options (e.g. its robot's presenter
        # clearance): what is measured is perception, not a different rule
        options = getattr(ctrl, "social_goal_options", None)
        truth = resolve_target(
            scn,
            context_at(social0, pos, vel, yaw),
            robot_pose=pose,
            **(options() if callable(options) else {}),
        )
        measured = truth.pose if target.waypoint is None else target.pose
        source = "true context"
        extra["estimator_ms_median"] = float(np.median(detector.seconds) * 1e3)
        extra["detected_social_goal"] = resolve_target(scn, seen0).meta.get("social_goal")
    record = recorder.build(
        dt=dt,
        robot_radius=model.circumscribed_radius,
        start=np.asarray(scn.start, dtype=float),
        goal=np.asarray(scn.goal, dtype=float),
        target=np.array(measured, dtype=float),
        waypoint=target.waypoint,
        goal_tolerance=float(scn.goal_tolerance),
        time_limit=float(scn.time_limit),
        family=scn.family,
        success=scn.success_spec(model.name),
        scenario=scn.name,
        context=social0,
        meta={
            "planner": planner_name,
            "robot": model.name,
            **model.kinematic_limits(),
            "seed": int(seed),
            "humans": humans,
            "reactive_behavior": reactive_behavior if humans == "reactive" else None,
            "termination": reason,
            "engine": f"navground {core.get_build_info().version_string}",
            "target_source": source,
            **target.meta,
            **extra,
        },
    )
    return EpisodeResult(record, diagnostics, _time.perf_counter() - wall_start, step_seconds)


def simulate_world(simw: SimWorld, steps: int, dt: float) -> None:
    """Advance a world ``steps`` updates of ``dt`` (tests and benchmarks)."""
    for _ in range(steps):
        simw.world.update(dt)

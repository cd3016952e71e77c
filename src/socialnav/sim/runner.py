"""Run one episode: scenario × controller (or navground behaviour) × robot × seed × human model.

``run_episode`` is a pure function of its arguments (names or picklable specs in, an
:class:`EpisodeResult` out), so batch runners can ship it to worker processes. The scenario's
jitter is drawn from ``numpy.random.default_rng(seed)``; the same arguments give an identical
record.

Timing: one sample per control period ``dt`` (0.1 s, the paper's). Sample ``k`` holds the state
at ``t = k·dt`` and the command applied for the following ``dt``. The episode ends at the first
sample where the controller reports ``GOAL_REACHED`` with a zero command (commands act
instantly, so the robot is stopped), where a navground baseline's task is done, or at the time
limit (sample ``t = time_limit`` included).
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
from socialnav.sim.baselines import NAVGROUND_BEHAVIORS, make_baseline
from socialnav.sim.controller import CONTROLLERS, GOAL_REACHED, Controller
from socialnav.sim.engine import ControllerBehavior, SimWorld, build_world, pose_of
from socialnav.sim.recorder import EpisodeRecorder, StaticGeometry, context_at
from socialnav.sim.scenario import Scenario, load_scenario
from socialnav.sim.stack import StackController  # noqa: F401  (registers the presets by name)

#: a controller counts as stopped below these speeds (m/s, rad/s)
STOP_EPS = 1e-3


@dataclass
class EpisodeResult:
    """``record``; ``diagnostics`` one entry per sample when asked; ``wall_time`` (s)."""

    record: EpisodeRecord
    diagnostics: list[Any] = field(default_factory=list)
    wall_time: float = 0.0


@dataclass(frozen=True)
class Target:
    """Where success is measured: ``pose (3,)``, optional ``waypoint (2,)``, and why."""

    pose: FloatArray
    waypoint: FloatArray | None
    meta: dict[str, Any]


def resolve_target(scenario: Scenario, social: SocialContext) -> Target:
    """The social goal when one resolves (``socialnav.social.resolve``), else the given goal.

    A social goal of kind ``waypoint`` (gallery activity) keeps the given goal as the target and
    becomes the waypoint to pass.
    """
    goal = np.asarray(scenario.goal, dtype=float)
    start = np.asarray(scenario.start, dtype=float)
    try:
        from socialnav.social.resolve import resolve_social_goal
    except ModuleNotFoundError as exc:  # the social package is not there (partial install)
        if exc.name is None or not exc.name.startswith("socialnav.social"):
            raise
        return Target(goal, None, {"social_goal": None, "social_goal_note": "unavailable"})
    sg = resolve_social_goal(social, goal, start)
    if sg is None:
        return Target(goal, None, {"social_goal": None})
    meta = {
        "social_goal": sg.kind,
        "social_goal_fallback": sg.fallback,
        "social_goal_reason": sg.reason,
    }
    pose = np.asarray(sg.pose, dtype=float)
    if sg.is_waypoint:
        return Target(goal, pose[:2].copy(), meta)
    return Target(pose, None, meta)


def _robot_model(robot: RobotModel | str) -> RobotModel:
    if isinstance(robot, RobotModel):
        return robot
    if robot not in ROBOT_MODELS:
        raise ConfigurationError(f"unknown robot {robot!r}; known: {', '.join(ROBOT_MODELS)}")
    return ROBOT_MODELS[robot]


def _controller(spec: Any, params: dict[str, Any] | None) -> tuple[Controller, str]:
    if isinstance(spec, str):
        return CONTROLLERS.get(spec)(**(params or {})), spec
    if not isinstance(spec, type) and isinstance(spec, Controller):
        return spec, type(spec).__name__
    if callable(spec):
        ctrl = spec(**(params or {}))
        return ctrl, getattr(spec, "__name__", type(ctrl).__name__)
    raise ConfigurationError(f"not a controller, controller name or factory: {spec!r}")


def run_episode(
    scenario: Scenario | str,
    controller: Controller | str | Any,
    robot: RobotModel | str = "pr2",
    seed: int = 0,
    humans: str = "scripted",
    record_diagnostics: bool = False,
    *,
    controller_params: dict[str, Any] | None = None,
    reactive_behavior: str = "HL",
    vary_group_sizes: bool = False,
) -> EpisodeResult:
    """Simulate one episode and record it.

    ``controller``: a :class:`Controller`, a factory, a name registered in ``CONTROLLERS``
    (built with ``controller_params``), or a navground behaviour name (``ORCA``, ``HL``,
    ``SocialForce``, ``HRVO``, ``Dummy``). ``humans``: ``"scripted"`` (the paper) or
    ``"reactive"`` (navground ``reactive_behavior``, default ``HL``).
    """
    wall_start = _time.perf_counter()
    scn = load_scenario(scenario) if isinstance(scenario, str) else scenario
    scn = scn.randomize(seed, vary_group_sizes=vary_group_sizes)
    if scn.humans is not None:  # the scene needs its own human model (CrowdNav's ORCA crowd)
        humans = scn.humans
        reactive_behavior = scn.reactive_behavior or reactive_behavior
    model = _robot_model(robot)
    social0 = scn.social_context(scn.start)
    target = resolve_target(scn, social0)

    baseline = isinstance(controller, str) and controller in NAVGROUND_BEHAVIORS
    if baseline:
        waypoints = [] if target.waypoint is None else [target.waypoint]
        waypoints.append(target.pose[:2])
        behavior, task = make_baseline(
            controller, model, waypoints, float(target.pose[2]), tolerance=0.5 * scn.goal_tolerance
        )
        simw = build_world(
            scn,
            model,
            behavior,
            humans,
            reactive_behavior,
            robot_task=task,
            sensing=True,
            seed=seed,
        )
        planner_name = controller
        ctrl_behavior = None
    else:
        ctrl, planner_name = _controller(controller, controller_params)
        ctrl.reset(scn, model)
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
    diagnostics: list[Any] = []
    dt = float(scn.control_period)
    last = round(scn.time_limit / dt)
    reason = "time_limit"
    for k in range(last + 1):
        t = k * dt
        pose = pose_of(simw.robot)
        pos, vel, yaw = simw.people_state()
        if ctrl_behavior is not None:
            social = context_at(social0, pos, vel, yaw)
            ctrl_behavior.observe = lambda _dt, t=t, social=social: (t, social)
            simw.world.update(dt)
            out = ctrl_behavior.last_output
            cmd = ctrl_behavior.last_cmd
            status = out.status if out is not None else "NO_CONTROLLER"
            if record_diagnostics:
                diagnostics.append(None if out is None else out.diagnostics)
            done = status == GOAL_REACHED and bool(np.all(np.abs(cmd) < STOP_EPS))
        else:
            done = bool(simw.robot.task.done())
            simw.world.update(dt)
            last_cmd = simw.robot.get_last_cmd(core.Frame.relative)
            cmd = np.array(
                [last_cmd.velocity[0], last_cmd.velocity[1], last_cmd.angular_speed], dtype=float
            )
            status = GOAL_REACHED if done else "OK"
            if record_diagnostics:
                diagnostics.append(None)
        recorder.add(t, pose, cmd, pos, vel, status)
        if done:
            reason = "goal_reached"
            break

    record = recorder.build(
        dt=dt,
        robot_radius=model.circumscribed_radius,
        start=np.asarray(scn.start, dtype=float),
        goal=np.asarray(scn.goal, dtype=float),
        target=target.pose,
        waypoint=target.waypoint,
        goal_tolerance=float(scn.goal_tolerance),
        time_limit=float(scn.time_limit),
        family=scn.family,
        scenario=scn.name,
        context=social0,
        meta={
            "planner": planner_name,
            "robot": model.name,
            "seed": int(seed),
            "humans": humans,
            "reactive_behavior": reactive_behavior if humans == "reactive" else None,
            "termination": reason,
            "success_options": scn.success.model_dump(),
            "engine": f"navground {core.get_build_info().version_string}",
            **target.meta,
        },
    )
    return EpisodeResult(record, diagnostics, _time.perf_counter() - wall_start)


def simulate_world(simw: SimWorld, steps: int, dt: float) -> None:
    """Advance a world ``steps`` updates of ``dt`` (tests and benchmarks)."""
    for _ in range(steps):
        simw.world.update(dt)

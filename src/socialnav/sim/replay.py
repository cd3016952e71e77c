"""Replay a recorded crowd in the simulator: people follow their recorded tracks, appear and
disappear as recorded, and do not react to the robot (SocNavBench's and CrowdNav's replay).

Each person of the recording who is present at some time of the episode is a navground agent
driven by :class:`ReplayedHuman`: at every control period it commands the velocity that puts it
exactly on its recorded position at the next sample (the track interpolated to the control
period, ``socialnav.crowds.Recording``). Absent people are *parked* far outside every sensing
range (navground keeps disabled agents as neighbours, so they cannot simply be switched off);
the episode record stores NaN for them and the planner's social context leaves them out.

``switch_distance`` (m) turns on the reactive option: once the robot comes within that distance
of a present replayed person, that person leaves their track and walks with navground's ``HL``
toward their recorded destination (the last point of their track), at their recorded speed
(at least :data:`SWITCHED_MIN_SPEED`); they disappear on arrival.

Walking groups of the recording are *not* passed to the planner as groups: the planner's groups
are standing conversational groups (join targets), and a walking group is not one.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import Any, SupportsFloat

import numpy as np
from navground import core, sim

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.scene import HUMAN_RADIUS, Person, SocialContext
from socialnav.crowds.recording import Recording
from socialnav.crowds.space import GRID_MARGIN, area_walls
from socialnav.sim.controller import GOAL_REACHED
from socialnav.sim.engine import ControllerBehavior, build_world, pose_of
from socialnav.sim.humans import SENSING_RANGE
from socialnav.sim.recorder import EpisodeRecorder, StaticGeometry
from socialnav.sim.runner import (
    STOP_EPS,
    DetectedContext,
    EpisodeResult,
    _controller,
    _robot_model,
    check_context,
)
from socialnav.sim.scenario import PersonSpec, Scenario

#: where absent people wait (m), spaced so nobody is ever within sensing range of the scene
PARKING_ORIGIN = 1.0e5
PARKING_SPACING = 3.0 * SENSING_RANGE
#: kinematic speed limit (m/s) of a replayed person: never binds
REPLAY_MAX_SPEED = 1.0e3
#: slowest walking speed (m/s) of a person switched to HL
SWITCHED_MIN_SPEED = 0.6
#: HL's arrival tolerance (m) at a switched person's destination
SWITCHED_TOLERANCE = 0.3


@dataclass(frozen=True)
class CrowdTask:
    """What the robot is asked to do in a recorded crowd: start at ``t0`` (s, recording time)
    from ``start (x, y, yaw)`` to ``goal (x, y, yaw)`` within ``time_limit`` (s)."""

    t0: float
    start: tuple[float, float, float]
    goal: tuple[float, float, float]
    time_limit: float = 60.0
    goal_tolerance: float = 0.3
    control_period: float = 0.1


class ReplayedHuman(core.Behavior):
    """Follows ``positions (N, 2)`` sampled every control period: the command at call ``k``
    moves the agent onto ``positions[k + 1]`` (absolute frame; NaN → stay where it is)."""

    def __init__(self, kinematics: core.Kinematics | None = None, radius: float = 0.0) -> None:
        core.Behavior.__init__(self, kinematics, radius)
        self.positions = np.zeros((0, 2))
        self.step_index = 0

    def compute_cmd_internal(self, time_step: SupportsFloat) -> core.Twist2:
        k = self.step_index + 1
        self.step_index = k
        dt = float(time_step)
        if k >= len(self.positions) or dt <= 0.0 or not np.isfinite(self.positions[k]).all():
            return core.Twist2((0.0, 0.0), 0.0, frame=core.Frame.absolute)
        v = (self.positions[k] - np.asarray(self.position, dtype=float)) / dt
        return core.Twist2((float(v[0]), float(v[1])), 0.0, frame=core.Frame.absolute)


def crowd_scenario(recording: Recording, task: CrowdTask, people: tuple[Person, ...]) -> Scenario:
    """The :class:`Scenario` of a crowd episode: open space whose border is the annotated area
    (the same walls as ``open_space_costmap``), the robot's task, and the people present at
    ``t0`` standing where they are (what a planner built at ``t0`` is told)."""
    walls = area_walls(recording.area)
    return Scenario(
        name=f"{recording.name}@{task.t0:.1f}",
        family="custom",
        map={"walls": [(tuple(a), tuple(b)) for a, b in walls], "margin": GRID_MARGIN},
        start=task.start,
        goal=task.goal,
        goal_tolerance=task.goal_tolerance,
        time_limit=task.time_limit,
        control_period=task.control_period,
        people=[
            PersonSpec(id=p.id, position=p.position, yaw=p.yaw, radius=p.radius) for p in people
        ],
    )


def _context(ids: np.ndarray, pos: FloatArray, vel: FloatArray, yaw: FloatArray) -> SocialContext:
    present = np.isfinite(pos).all(axis=1)
    return SocialContext(
        tuple(
            Person(
                int(ids[j]),
                (float(pos[j, 0]), float(pos[j, 1])),
                (float(vel[j, 0]), float(vel[j, 1])),
                float(yaw[j]),
                HUMAN_RADIUS,
            )
            for j in np.flatnonzero(present)
        )
    )


def _parking(j: int) -> tuple[float, float]:
    return (PARKING_ORIGIN + PARKING_SPACING * j, PARKING_ORIGIN)


def _person_agent(j: int, pid: int, positions: FloatArray) -> sim.Agent:
    behavior = ReplayedHuman()
    behavior.positions = positions
    agent = sim.Agent(
        radius=HUMAN_RADIUS,
        behavior=behavior,
        # Far above any walking speed: navground must never rescale a replayed step.
        kinematics=core.kinematics.OmnidirectionalKinematics(REPLAY_MAX_SPEED, 1.0),
        control_period=0.0,
        id=int(pid),
    )
    agent.type = "human"
    start = positions[0] if np.isfinite(positions[0]).all() else _parking(j)
    agent.pose = core.Pose2((float(start[0]), float(start[1])), 0.0)
    return agent


def _switch_to_hl(agent: sim.Agent, destination: FloatArray, speed: float) -> None:
    behavior = core.Behavior.make_type("HL")
    if behavior is None:  # pragma: no cover - navground always has HL
        raise ConfigurationError("navground has no HL behaviour")
    cruise = max(float(speed), SWITCHED_MIN_SPEED)
    behavior.optimal_speed = cruise
    behavior.max_speed = cruise
    behavior.radius = HUMAN_RADIUS
    agent.behavior = behavior
    agent.kinematics = core.kinematics.OmnidirectionalKinematics(cruise, np.pi)
    agent.task = sim.tasks.WaypointsTask(
        waypoints=[np.asarray(destination, dtype=float)], loop=False, tolerance=SWITCHED_TOLERANCE
    )
    agent.state_estimations = [sim.state_estimations.BoundedStateEstimation(range=SENSING_RANGE)]


def humans_label(switch_distance: float | None) -> str:
    """How the people of a crowd run behave, as the ``humans`` column and meta say it:
    ``replayed`` (they follow their tracks and never react), or ``replayed+HL@<d>m`` (each
    switches to navground's HL toward their recorded destination once the robot is within
    ``d`` m)."""
    return "replayed" if switch_distance is None else f"replayed+HL@{switch_distance:g}m"


def run_crowd_episode(
    recording: Recording,
    task: CrowdTask,
    controller: Any,
    robot: Any = "pr2",
    seed: int = 0,
    record_diagnostics: bool = False,
    *,
    switch_distance: float | None = None,
    controller_params: dict[str, Any] | None = None,
    context: str = "given",
    perception: Any = None,
) -> EpisodeResult:
    """Drive ``controller`` (a registered controller name, a Controller or a factory, as in
    ``run_episode``; navground behaviours are the ``orca``, ``hl``, ``social_force``
    controllers) through ``recording`` from ``task.t0``.

    The record has family ``crowd``; its people are everyone present at some sample, in the
    recording's order, NaN where absent (``people_present`` is the mask). ``switch_distance``:
    see the module docstring (``None``: people never react). ``context``: ``given`` (the
    controller sees the people present, exactly) or ``detected`` (noisy tracks from
    :class:`~socialnav.sim.perception.PerceptionModel` with ``perception`` noise, default
    :data:`~socialnav.sim.perception.DEFAULT_PERCEPTION`, and the context estimator's
    structures, as :class:`~socialnav.sim.runner.DetectedContext`; the robot watches for
    ``runner.WARMUP`` s first). Metrics always use the true people.
    """
    check_context(context)
    wall_start = _time.perf_counter()
    model = _robot_model(robot)
    dt = float(task.control_period)
    last = round(task.time_limit / dt)
    # One sample beyond the end: where the last step aims.
    times: FloatArray = task.t0 + dt * np.arange(last + 2, dtype=float)
    ids = recording.active_ids(float(times[0]), float(times[-1]))
    crowd = recording.states(times, ids)
    keep = crowd.present.any(axis=0)
    ids = ids[keep]
    pos, vel, head = crowd.positions[:, keep], crowd.velocities[:, keep], crowd.headings[:, keep]
    social0 = _context(ids, pos[0], vel[0], head[0])
    scn = crowd_scenario(recording, task, social0.people)
    empty = scn.model_copy(update={"people": []})
    detector = DetectedContext(scn, seed, perception) if context == "detected" else None
    if detector is not None:
        detector.warm_up(social0, dt)

    ctrl, planner_name = _controller(controller, controller_params)
    ctrl.reset(scn, model)
    ctrl_behavior = ControllerBehavior()
    ctrl_behavior.controller = ctrl
    ctrl_behavior.robot_model = model
    simw = build_world(empty, model, ctrl_behavior, seed=seed)
    agents = [_person_agent(j, int(pid), pos[:, j]) for j, pid in enumerate(ids)]
    for agent in agents:
        simw.world.add_agent(agent)
    switched = np.zeros(len(ids), dtype=bool)
    gone = np.zeros(len(ids), dtype=bool)  # switched people who reached their destination

    static = StaticGeometry(scn.walls_array(), (), np.zeros((0, 3)))
    recorder = EpisodeRecorder(model.polygon, ids, np.full(len(ids), HUMAN_RADIUS), static)
    diagnostics: list[Any] = []
    step_seconds: list[float] = []
    reason = "time_limit"
    for k in range(last + 1):
        t = k * dt
        pose = pose_of(simw.robot)
        now_pos, now_vel, now_yaw = pos[k].copy(), vel[k].copy(), head[k].copy()
        for j in np.flatnonzero(switched):
            a = agents[j]
            if gone[j] or (a.task is not None and a.task.done()):
                gone[j] = True
                now_pos[j] = now_vel[j] = np.nan
                now_yaw[j] = np.nan
                continue
            now_pos[j] = np.asarray(a.position, dtype=float)
            now_vel[j] = np.asarray(a.velocity, dtype=float)
            now_yaw[j] = float(a.orientation)
        present = np.isfinite(now_pos).all(axis=1)
        for j in np.flatnonzero(~present):  # keep absent people parked, still
            agents[j].pose = core.Pose2(_parking(int(j)), 0.0)
            agents[j].twist = core.Twist2((0.0, 0.0), 0.0, frame=core.Frame.absolute)
        for j in np.flatnonzero(present & ~switched):
            agents[j].pose = core.Pose2((float(now_pos[j, 0]), float(now_pos[j, 1])), now_yaw[j])
            agents[j].twist = core.Twist2(
                (float(now_vel[j, 0]), float(now_vel[j, 1])), 0.0, frame=core.Frame.absolute
            )
        if switch_distance is not None:
            near = (
                present & ~switched & (np.hypot(*(now_pos - pose[:2]).T) <= float(switch_distance))
            )
            for j in np.flatnonzero(near):
                switched[j] = True
                speed = float(np.nanmedian(np.hypot(*vel[:, j].T)))
                _switch_to_hl(agents[j], recording.destination(int(ids[j])), speed)
        for j in np.flatnonzero(~switched):
            replayed = agents[j].behavior
            if isinstance(replayed, ReplayedHuman):
                replayed.step_index = k
        social = _context(ids, now_pos, now_vel, now_yaw)
        if detector is not None:
            social = detector.observe(
                t,
                now_pos[present],
                now_vel[present],
                now_yaw[present],
                ids[present],
                np.full(int(present.sum()), HUMAN_RADIUS),
            )
        ctrl_behavior.observe = lambda _dt, t=t, social=social: (t, social)
        started = _time.perf_counter()
        simw.world.update(dt)
        step_seconds.append(_time.perf_counter() - started)
        out = ctrl_behavior.last_output
        cmd = ctrl_behavior.last_cmd
        status = out.status.value if out is not None else "NO_CONTROLLER"
        if record_diagnostics:
            diagnostics.append(None if out is None else out.record)
        done = status == GOAL_REACHED and bool(np.all(np.abs(cmd) < STOP_EPS))
        recorder.add(t, pose, cmd, now_pos, now_vel, status)
        if done:
            reason = "goal_reached"
            break

    record = recorder.build(
        dt=dt,
        robot_radius=model.circumscribed_radius,
        start=np.asarray(task.start, dtype=float),
        goal=np.asarray(task.goal, dtype=float),
        target=np.asarray(task.goal, dtype=float),
        waypoint=None,
        goal_tolerance=float(task.goal_tolerance),
        time_limit=float(task.time_limit),
        family="crowd",
        scenario=scn.name,
        context=social0,
        meta={
            "planner": planner_name,
            "robot": model.name,
            **model.kinematic_limits(),
            "seed": int(seed),
            "humans": humans_label(switch_distance),
            "termination": reason,
            "engine": f"navground {core.get_build_info().version_string}",
            "recording": str(recording.source) if recording.source else recording.name,
            "t0": float(task.t0),
            "switched_people": [int(i) for i in ids[switched]],
            "context": context,
            **(
                {}
                if detector is None
                else {"estimator_ms_median": float(np.median(detector.seconds) * 1e3)}
            ),
        },
    )
    return EpisodeResult(record, diagnostics, _time.perf_counter() - wall_start, step_seconds)

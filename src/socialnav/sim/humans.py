"""Human models: the paper's scripted people, and navground's reactive pedestrians.

The paper's humans "exhibit very simple motion behaviors": they stand, or walk a fixed line at a
fixed speed without reacting to the robot. :class:`ScriptedHuman` is that model as a navground
Python behaviour (navground then moves the agent and shows it to everyone else as a neighbour).
``humans="reactive"`` instead gives each person navground's ``HL`` (default), ``ORCA`` or
``SocialForce`` behaviour toward a goal (their walk's end, their ``reactive_goal``, or their
own start for people who stand): an extension beyond the paper.
"""

from __future__ import annotations

import math
from typing import SupportsFloat

import numpy as np
from navground import core, sim

from socialnav.core.errors import ConfigurationError
from socialnav.sim.scenario import PersonSpec, Track, Walk

REACTIVE_BEHAVIORS = ("HL", "ORCA", "SocialForce")
#: speed (m/s) of people who stand in scripted mode but move aside when reactive
REACTIVE_STANDING_SPEED = 0.6
#: sensing range (m) of reactive people and navground baseline robots
SENSING_RANGE = 8.0


class ScriptedHuman(core.Behavior):
    """Constant velocity along a line, then stop: ``direction (2,)`` unit vector, ``speed`` (m/s),
    ``length`` (m, may be ``inf``) from ``start (2,)``. Ignores everyone (never yields).

    The last step is shortened so the person stops exactly at the end point.
    """

    def __init__(self, kinematics: core.Kinematics | None = None, radius: float = 0.0) -> None:
        core.Behavior.__init__(self, kinematics, radius)
        self.start = np.zeros(2)
        self.direction = np.zeros(2)
        self.walk_speed = 0.0
        self.length = 0.0

    def compute_cmd_internal(self, time_step: SupportsFloat) -> core.Twist2:
        dt = float(time_step)
        if self.walk_speed <= 0.0 or dt <= 0.0:
            return core.Twist2((0.0, 0.0), 0.0, frame=core.Frame.absolute)
        walked = float(np.dot(np.asarray(self.position, dtype=float) - self.start, self.direction))
        remaining = max(self.length - walked, 0.0)
        speed = min(self.walk_speed, remaining / dt)
        v = self.direction * speed
        return core.Twist2((float(v[0]), float(v[1])), 0.0, frame=core.Frame.absolute)


class TrackHuman(core.Behavior):
    """Follows ``points (P, 2)`` sampled every ``track_dt`` seconds, then stops at the last
    point; ignores everyone. Each command is the velocity that reaches the track's position at
    the end of the step (linear interpolation), so the person is on the track at every step."""

    def __init__(self, kinematics: core.Kinematics | None = None, radius: float = 0.0) -> None:
        core.Behavior.__init__(self, kinematics, radius)
        self.points = np.zeros((1, 2))
        self.track_dt = 1.0
        self.clock = 0.0

    def position_at(self, t: float) -> np.ndarray:
        """Track position ``(2,)`` at time ``t`` (s), clamped to the track's ends."""
        s = np.clip(t / self.track_dt, 0.0, len(self.points) - 1)
        k = min(int(s), len(self.points) - 2) if len(self.points) > 1 else 0
        if len(self.points) == 1:
            return self.points[0]
        f = s - k
        return (1.0 - f) * self.points[k] + f * self.points[k + 1]

    def compute_cmd_internal(self, time_step: SupportsFloat) -> core.Twist2:
        dt = float(time_step)
        if dt <= 0.0:
            return core.Twist2((0.0, 0.0), 0.0, frame=core.Frame.absolute)
        self.clock += dt
        v = (self.position_at(self.clock) - np.asarray(self.position, dtype=float)) / dt
        return core.Twist2((float(v[0]), float(v[1])), 0.0, frame=core.Frame.absolute)


def make_person_agent(
    person: PersonSpec, humans: str = "scripted", reactive_behavior: str = "HL"
) -> sim.Agent:
    """A navground agent for one person (disc of the person's radius, omnidirectional)."""
    start = np.asarray(person.position, dtype=float)
    velocity = person.initial_velocity()
    speed = float(np.linalg.norm(velocity))
    if humans == "scripted" and isinstance(person.behavior, Track):
        track = TrackHuman()
        track.points = np.asarray(person.behavior.points, dtype=float)
        track.track_dt = float(person.behavior.dt)
        steps = np.linalg.norm(np.diff(track.points, axis=0), axis=1)
        top = float(steps.max() / track.track_dt) if steps.size else 0.0
        agent = sim.Agent(
            radius=person.radius,
            behavior=track,
            kinematics=core.kinematics.OmnidirectionalKinematics(2.0 * top + 0.1, 1.0),
            control_period=0.0,
            id=person.id,
        )
    elif humans == "scripted":
        scripted = ScriptedHuman()
        if isinstance(person.behavior, Walk):
            direction, speed = person.behavior.direction_speed()
            scripted.start = start
            scripted.direction = direction
            scripted.walk_speed = speed
            scripted.length = person.behavior.length(person.position)
        behavior: core.Behavior = scripted
        # Kinematic limits well above the scripted speed: navground must never rescale it.
        kinematics = core.kinematics.OmnidirectionalKinematics(2.0 * speed + 0.1, 1.0)
        agent = sim.Agent(
            radius=person.radius,
            behavior=behavior,
            kinematics=kinematics,
            control_period=0.0,
            id=person.id,
        )
    elif humans == "reactive":
        if reactive_behavior not in REACTIVE_BEHAVIORS:
            raise ConfigurationError(
                f"unknown reactive human behaviour {reactive_behavior!r}; "
                f"known: {', '.join(REACTIVE_BEHAVIORS)}"
            )
        reactive = core.Behavior.make_type(reactive_behavior)
        if reactive is None:  # pragma: no cover - REACTIVE_BEHAVIORS are navground's own
            raise ConfigurationError(f"navground has no behaviour {reactive_behavior!r}")
        behavior = reactive
        goal = person.reactive_goal
        if goal is None:
            end = person.end_point()
            goal = tuple(end) if end is not None else person.position
        cruise = speed if speed > 0 else REACTIVE_STANDING_SPEED
        kinematics = core.kinematics.OmnidirectionalKinematics(cruise, math.pi)
        behavior.optimal_speed = cruise
        behavior.max_speed = cruise
        behavior.radius = person.radius
        task = sim.tasks.WaypointsTask(
            waypoints=[np.asarray(goal, dtype=float)], loop=False, tolerance=0.1
        )
        agent = sim.Agent(
            radius=person.radius,
            behavior=behavior,
            kinematics=kinematics,
            task=task,
            state_estimations=[sim.state_estimations.BoundedStateEstimation(range=SENSING_RANGE)],
            control_period=0.0,
            id=person.id,
        )
    else:
        raise ConfigurationError(f"humans must be 'scripted' or 'reactive', got {humans!r}")
    agent.pose = core.Pose2((float(start[0]), float(start[1])), person.heading)
    agent.twist = core.Twist2(
        (float(velocity[0]), float(velocity[1])), 0.0, frame=core.Frame.absolute
    )
    agent.type = "human"
    return agent

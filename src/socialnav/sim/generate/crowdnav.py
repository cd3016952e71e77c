"""CrowdNav's test bank (Chen et al., "Crowd-Robot Interaction", ICRA 2019; ``crowd_sim``).

``circle_crossing``: 5 people (radius 0.3 m, preferred speed 1 m/s) start on a circle of
radius 4 m at uniform random angles, each coordinate perturbed by U(−0.5, 0.5) m, and cross to
the antipodal point of their start; a person closer than the two radii + 0.2 m (CrowdNav's
discomfort distance) to another's start or goal, or to the robot's start or goal, is drawn
again. The robot drives from (0, −4) to (0, 4). Open space (no walls). 500 seeded cases per
split are what CrowdNav reports (``--seeds 10000:10500``).

Two variants, as in CrowdNav:
- ``crowdnav`` — *robot invisible*: the crowd's ORCA paths are computed with navground's ORCA
  among the people only (0.1 s steps) and replayed as tracks: nobody reacts to the robot;
- ``crowdnav_visible`` — people run navground ORCA toward their goals, the robot among them.

Deviation: CrowdNav's time limit is 25 s for its 1 m/s holonomic robot; our robots drive at
0.5–0.55 m/s, so the limit is 40 s. Success: arrival at the goal (0.10 m) without collision.
Reported also in CrowdNav's terms (``report.generated``): success, collision, timeout, mean
time to goal of the successes, discomfort = share of steps with a body gap below 0.2 m.

Feasibility facts: ``min_start_gap`` (m) between the robot's start and any person's body; no
condition is ever marked not required (every crossing can be waited out in open space).
"""

from __future__ import annotations

import math

import numpy as np

from socialnav.sim.generate.common import (
    GENERATORS,
    ROBOTS,
    Generator,
    Infeasible,
    r3,
    robot_model,
    success_options,
    xy,
)
from socialnav.sim.scenario import MapSpec, PersonSpec, Scenario, Track, Walk

CIRCLE_RADIUS = 4.0
PEOPLE = 5
HUMAN_RADIUS = 0.3
V_PREF = 1.0
DISCOMFORT = 0.2
ROBOT_RADIUS = 0.3  # CrowdNav's robot, for the placement rule only
START, GOAL = (0.0, -4.0), (0.0, 4.0)
TIME_LIMIT = 40.0
DT = 0.1


def circle_crossing(rng: np.random.Generator) -> list[tuple[np.ndarray, np.ndarray]]:
    """CrowdNav's ``generate_circle_crossing_human`` for ``PEOPLE`` people: (start, goal)."""
    placed: list[tuple[np.ndarray, np.ndarray, float]] = [
        (np.array(START), np.array(GOAL), ROBOT_RADIUS)
    ]
    out = []
    for _ in range(PEOPLE):
        for _ in range(1000):
            angle = rng.random() * 2 * math.pi
            noise = (rng.random(2) - 0.5) * V_PREF
            p = CIRCLE_RADIUS * np.array([math.cos(angle), math.sin(angle)]) + noise
            ok = all(
                np.linalg.norm(p - s) >= HUMAN_RADIUS + r + DISCOMFORT
                and np.linalg.norm(p - g) >= HUMAN_RADIUS + r + DISCOMFORT
                for s, g, r in placed
            )
            if ok:
                break
        else:
            raise Infeasible("circle crossing placement failed")
        placed.append((p, -p, HUMAN_RADIUS))
        out.append((p, -p))
    return out


def orca_tracks(pairs: list[tuple[np.ndarray, np.ndarray]], seed: int) -> list[np.ndarray]:
    """The people's paths ``(T, 2)`` under navground ORCA among themselves (no robot)."""
    from navground import core, sim

    world = sim.World()
    world.seed = int(seed)
    agents = []
    for k, (start, goal) in enumerate(pairs):
        behavior = core.Behavior.make_type("ORCA")
        if behavior is None:  # pragma: no cover - ORCA is navground's own
            raise RuntimeError("navground has no ORCA behaviour")
        behavior.optimal_speed = V_PREF
        behavior.max_speed = V_PREF
        behavior.radius = HUMAN_RADIUS
        agent = sim.Agent(
            radius=HUMAN_RADIUS,
            behavior=behavior,
            kinematics=core.kinematics.OmnidirectionalKinematics(V_PREF, math.pi),
            task=sim.tasks.WaypointsTask(waypoints=[goal], loop=False, tolerance=0.05),
            state_estimations=[sim.state_estimations.BoundedStateEstimation(range=8.0)],
            control_period=0.0,
            id=k + 1,
        )
        agent.pose = core.Pose2(
            tuple(float(v) for v in start), float(np.arctan2(*(goal - start)[::-1]))
        )
        world.add_agent(agent)
        agents.append(agent)
    steps = round(TIME_LIMIT / DT)
    tracks = np.zeros((steps + 1, len(agents), 2))
    tracks[0] = [a.position for a in agents]
    for t in range(1, steps + 1):
        world.update(DT)
        tracks[t] = [a.position for a in agents]
    # Trim the still tail: a track stops at its last point.
    moving = np.any(np.linalg.norm(np.diff(tracks, axis=0), axis=2) > 1e-6, axis=1)
    last = int(np.flatnonzero(moving)[-1]) + 2 if moving.any() else 2
    return [tracks[:last, k] for k in range(len(agents))]


def _draw(rng: np.random.Generator, name: str, visible: bool) -> Scenario:
    pairs = circle_crossing(rng)
    people: list[PersonSpec] = []
    if visible:
        for k, (start, goal) in enumerate(pairs):
            v = (goal - start) / np.linalg.norm(goal - start) * V_PREF
            people.append(
                PersonSpec(
                    id=k + 1,
                    position=xy(start),
                    radius=HUMAN_RADIUS,
                    behavior=Walk(velocity=(r3(v[0]), r3(v[1])), until=xy(goal)),
                    reactive_goal=xy(goal),
                )
            )
    else:
        for k, track in enumerate(orca_tracks(pairs, int(rng.integers(0, 2**31)))):
            points = [xy(p) for p in track]
            people.append(
                PersonSpec(
                    id=k + 1,
                    position=points[0],
                    radius=HUMAN_RADIUS,
                    behavior=Track(dt=DT, points=points),
                )
            )
    facts: dict[str, dict[str, float | bool | str]] = {}
    for robot_name in ROBOTS:
        r = robot_model(robot_name).circumscribed_radius
        gap = min(np.linalg.norm(np.asarray(p.position) - START) - r - p.radius for p in people)
        if gap <= 0.05:
            raise Infeasible("a person starts on the robot")
        facts[robot_name] = {"min_start_gap": r3(float(gap))}
    return Scenario(
        name=name,
        family="crowdnav",
        description="CrowdNav circle crossing, robot " + ("visible" if visible else "invisible"),
        map=MapSpec(margin=3.0),
        start=(*START, math.pi / 2),
        goal=(*GOAL, math.pi / 2),
        people=people,
        time_limit=TIME_LIMIT,
        humans="reactive" if visible else "scripted",
        reactive_behavior="ORCA" if visible else None,
        success=success_options("crowdnav", False),
        feasibility=facts,
    )


def draw_invisible(rng: np.random.Generator, name: str) -> Scenario:
    return _draw(rng, name, visible=False)


def draw_visible(rng: np.random.Generator, name: str) -> Scenario:
    return _draw(rng, name, visible=True)


GENERATORS.add("crowdnav", Generator("crowdnav", __doc__ or "", draw_invisible))
GENERATORS.add("crowdnav_visible", Generator("crowdnav_visible", __doc__ or "", draw_visible))

"""Generated queues: a line of people at a desk; the robot joins at the tail.

Ranges: a room 9–14 m × 9–14 m; a 1.6 × 0.6 m desk anywhere at least 2 m from the walls, in any
orientation; 2–8 people queueing in front of it (head 0.6 m from the desk's front), spacing
0.6–1.1 m, the line bending sideways by up to 0.4 m at the tail (quadratic bend); the whole
line and its tail slot at least 1.2 m from the walls. The robot starts at least 2.5 m from
everyone and from the desk, and is given the desk's front as its goal (the paper's setup).
Success: arrival at the tail slot (0.10 m, 0.2 rad), facing the line, never cutting in.

Feasibility facts per robot: the tail slot (``social.goals.queue_tail_pose``) is clear for the
footprint and reachable without crossing the line (every band between consecutive members
blocked); otherwise the scene is drawn again.
"""

from __future__ import annotations

import math

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.sim.generate._rooms import draw_room, inside_room, random_free_point
from socialnav.sim.generate.common import (
    GENERATORS,
    Generator,
    Infeasible,
    face,
    r3,
    room_walls,
    spot_facts,
    success_options,
    time_limit_for,
    uniform,
    xy,
)
from socialnav.sim.scenario import PersonSpec, QueueSpec, Rectangle, Scenario
from socialnav.social.spaces import queue_band_polygons

MEMBERS = (2, 8)
SPACING = (0.6, 1.1)
BEND = 0.4
DESK = (1.6, 0.6)
HEAD_GAP = 0.6


def draw_queue(
    rng: np.random.Generator, width: float, height: float, first_id: int = 1
) -> tuple[Rectangle, QueueSpec, list[PersonSpec], FloatArray]:
    """Desk, queue spec, its members (ids from ``first_id``) and the given goal (desk front)."""
    yaw = uniform(rng, -math.pi, math.pi)
    center = np.array([uniform(rng, 2.0, width - 2.0), uniform(rng, 2.0, height - 2.0)])
    front = np.array([math.cos(yaw - math.pi / 2), math.sin(yaw - math.pi / 2)])  # desk −y side
    side = np.array([-front[1], front[0]])
    service = center + front * DESK[1] / 2
    n = int(rng.integers(MEMBERS[0], MEMBERS[1] + 1))
    spacing = uniform(rng, *SPACING)
    bend = uniform(rng, -BEND, BEND)
    people: list[PersonSpec] = []
    points = []
    for k in range(n + 1):  # k == n: the tail slot, checked against the walls too
        frac = (k / max(n - 1, 1)) ** 2
        p = service + front * (HEAD_GAP + k * spacing) + side * bend * frac
        if not inside_room(p, width, height, 1.2):
            raise Infeasible("the queue runs into a wall")
        points.append(p)
    for k in range(n):
        ahead = points[k - 1] if k > 0 else service
        people.append(
            PersonSpec(id=first_id + k, position=xy(points[k]), yaw=r3(face(points[k], ahead)))
        )
    desk = Rectangle(center=xy(center), size=DESK, yaw=r3(yaw))
    queue = QueueSpec(
        members=[p.id for p in people], service_point=xy(service), spacing=r3(spacing)
    )
    return desk, queue, people, service + front * 0.5


def bands(people: list[PersonSpec]) -> list[FloatArray]:
    return queue_band_polygons(np.array([p.position for p in people], dtype=float))


def draw(rng: np.random.Generator, name: str) -> Scenario:
    width, height = draw_room(rng)
    desk, queue, people, goal_xy = draw_queue(rng, width, height)
    avoid = [(np.asarray(p.position), 2.5) for p in people] + [(np.asarray(desk.center), 2.5)]
    start_xy = random_free_point(rng, width, height, avoid)
    yaw = face(start_xy, goal_xy)
    scn = Scenario(
        name=name,
        family="queue",
        description=f"generated queue: {len(people)} people, spacing {queue.spacing:.2f} m",
        map={"walls": room_walls(width, height), "rectangles": [desk]},
        start=(*xy(start_xy), r3(yaw)),
        goal=(*xy(goal_xy), r3(yaw)),
        people=people,
        queues=[queue],
        time_limit=time_limit_for(float(np.linalg.norm(goal_xy - start_xy)) * 2.0),
        success=success_options("queue", True),
    )
    facts, _ = spot_facts(scn, blocked_polygons=bands(people))
    return scn.model_copy(update={"feasibility": facts})


GENERATORS.add("queue", Generator("queue", __doc__ or "", draw))

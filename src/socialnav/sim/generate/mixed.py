"""Generated mixed rooms: a group to join or a queue to join, plus people walking through.

Ranges: the group of :mod:`group_join` (half the scenes) or the queue and desk of
:mod:`queue`, and 1–3 walkers crossing the room at 0.3–1.5 m/s between two points near opposite
walls, their lines at least 1.5 m from every group or queue member and their starts at least
2.5 m from the robot. Success: the conditions of the structure (group or queue), with the
generated suite's tolerance. Feasibility: as for the structure alone (the walkers pass).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from socialnav.core.geometry import point_segment_distance
from socialnav.sim.generate import queue as queue_gen
from socialnav.sim.generate._groups import RADIUS, draw_group
from socialnav.sim.generate._rooms import draw_room, random_free_point
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
from socialnav.sim.scenario import PersonSpec, Scenario, Walk
from socialnav.social.spaces import o_space

WALKERS = (1, 3)
SPEED = (0.3, 1.5)


def draw(rng: np.random.Generator, name: str) -> Scenario:
    width, height = draw_room(rng)
    use_group = rng.random() < 0.5
    extra: dict[str, Any] = {}
    if use_group:
        margin = RADIUS[1] + 2.0
        center = np.array(
            [uniform(rng, margin, width - margin), uniform(rng, margin, height - margin)]
        )
        group, members, radius = draw_group(rng, center, "join")
        goal_xy = center
        extra["groups"] = [group]
        avoid = [(center, radius + 3.0)]
        walls = room_walls(width, height)
        mapspec: dict[str, Any] = {"walls": walls}
    else:
        desk, queue, members, goal_xy = queue_gen.draw_queue(rng, width, height)
        extra["queues"] = [queue]
        avoid = [(np.asarray(p.position), 2.5) for p in members]
        avoid.append((np.asarray(desk.center), 2.5))
        mapspec = {"walls": room_walls(width, height), "rectangles": [desk]}
    start_xy = random_free_point(rng, width, height, avoid)
    member_xy = np.array([p.position for p in members], dtype=float)
    walkers: list[PersonSpec] = []
    next_id = max(p.id for p in members) + 1
    for k in range(int(rng.integers(WALKERS[0], WALKERS[1] + 1))):
        for _ in range(50):
            a = np.array([uniform(rng, 0.6, width - 0.6), uniform(rng, 0.6, height - 0.6)])
            b = np.array([width, height]) - a + rng.normal(0.0, 1.0, 2)
            b = np.clip(b, 0.6, [width - 0.6, height - 0.6])
            if np.linalg.norm(b - a) < 4.0 or np.linalg.norm(a - start_xy) < 2.5:
                continue
            d = point_segment_distance(member_xy, a[None], b[None])
            if (
                np.min(d) >= 1.5
                and point_segment_distance(goal_xy[None], a[None], b[None])[0, 0] >= 1.0
            ):
                break
        else:
            raise Infeasible("no walker line clear of the structure")
        speed = uniform(rng, *SPEED)
        v = (b - a) / np.linalg.norm(b - a) * speed
        walkers.append(
            PersonSpec(
                id=next_id + k,
                position=xy(a),
                behavior=Walk(velocity=(r3(v[0]), r3(v[1])), until=xy(b)),
            )
        )
    yaw = face(start_xy, goal_xy)
    scn = Scenario(
        name=name,
        family="mixed",
        description=f"generated mixed: {'group' if use_group else 'queue'} + "
        f"{len(walkers)} walkers",
        map=mapspec,
        start=(*xy(start_xy), r3(yaw)),
        goal=(*xy(goal_xy), r3(yaw)),
        people=members + walkers,
        time_limit=time_limit_for(float(np.linalg.norm(goal_xy - start_xy)) * 2.0),
        success=success_options("mixed", True, has_queue=not use_group),
        **extra,
    )
    if use_group:
        facts, _ = spot_facts(scn, blocked_discs=[o_space(member_xy)])
    else:
        facts, _ = spot_facts(scn, blocked_polygons=queue_gen.bands(members))
    return scn.model_copy(update={"feasibility": facts})


GENERATORS.add("mixed", Generator("mixed", __doc__ or "", draw))

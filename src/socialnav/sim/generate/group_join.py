"""Generated groups, "join": the robot joins an O-formation at its free spot.

Ranges: a room 9–14 m × 9–14 m; 2–6 members on a circle of radius 0.6–1.5 m (a pair face to
face), at uneven angles (Dirichlet shares, neighbours at least 0.6 m apart), facing the
centre; the group at least radius + 2 m from the walls; the robot starts at least radius + 3 m
from the centre and is given the group's centre as its goal (the paper's setup). Success:
arrival at the free spot (0.10 m, 0.2 rad), facing the centre, the robot centre never inside
the o-space (radius − 0.3 m).

Feasibility facts per robot: the spot (``social.goals.o_formation_join_pose``) is clear for the
footprint and reachable without entering the o-space; otherwise the scene is drawn again.
"""

from __future__ import annotations

import numpy as np

from socialnav.sim.generate._groups import RADIUS, draw_group
from socialnav.sim.generate._rooms import draw_room, random_free_point
from socialnav.sim.generate.common import (
    GENERATORS,
    Generator,
    face,
    r3,
    room_walls,
    spot_facts,
    success_options,
    time_limit_for,
    uniform,
    xy,
)
from socialnav.sim.scenario import Scenario
from socialnav.social.spaces import o_space


def draw_group_scene(rng: np.random.Generator, name: str, mode: str, arc: float) -> Scenario:
    width, height = draw_room(rng)
    margin = RADIUS[1] + 2.0
    center = np.array([uniform(rng, margin, width - margin), uniform(rng, margin, height - margin)])
    group, people, radius = draw_group(rng, center, mode, arc=arc)
    start_xy = random_free_point(rng, width, height, [(center, radius + 3.0)])
    yaw = face(start_xy, center)
    scn = Scenario(
        name=name,
        family="group",
        description=f"generated group ({mode}): {len(people)} members, radius {radius:.2f} m",
        map={"walls": room_walls(width, height)},
        start=(*xy(start_xy), r3(yaw)),
        goal=(*xy(center), r3(yaw)),
        people=people,
        groups=[group],
        time_limit=time_limit_for(float(np.linalg.norm(center - start_xy)) * 2.0),
        success=success_options("group", True),
    )
    disc = o_space(np.array([p.position for p in people], dtype=float))
    facts, _ = spot_facts(scn, blocked_discs=[disc])
    return scn.model_copy(update={"feasibility": facts})


def draw(rng: np.random.Generator, name: str) -> Scenario:
    return draw_group_scene(rng, name, "join", 2 * np.pi)


GENERATORS.add("group_join", Generator("group_join", __doc__ or "", draw))

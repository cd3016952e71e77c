"""Generated galleries, "present": the robot presents an artwork to its viewers.

Ranges: a room 9–14 m × 9–14 m; an artwork 0.8–2.0 m wide on any of the four walls, its
centre at least 1.5 m + half its width from the corners; 1–3 viewers 1.0–2.5 m in front of it,
laterally within its width, at least 0.7 m apart, facing the artwork (±0.3 rad); the robot
starts anywhere at least 3 m from the artwork and 1.5 m from every viewer, facing its given
goal: the point 0.4 of the way from the artwork to the nearest viewer (between viewer and art,
as in the paper). Success: arrival at the presenter spot (0.10 m, 0.2 rad), facing the viewer,
never inside an activity space.

Feasibility facts per robot: the presenter spot (``social.goals.presenter_pose``) exists, the
footprint at the spot touches nobody and no wall, and the spot is reachable from the start with
every activity space blocked; otherwise the scene is drawn again.
"""

from __future__ import annotations

import math

import numpy as np

from socialnav.sim.generate._rooms import draw_room, random_free_point, wall_frame
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
from socialnav.sim.scenario import ArtworkSpec, PersonSpec, Scenario
from socialnav.social.spaces import activity_space_polygon

ART_WIDTH = (0.8, 2.0)
VIEWER_DEPTH = (1.0, 2.5)
VIEWERS = (1, 3)
VIEWER_SPACING = 0.7


def draw_gallery(rng: np.random.Generator) -> tuple[float, float, ArtworkSpec, list[PersonSpec]]:
    """Room size, the artwork and its viewers (ids 1..V)."""
    width, height = draw_room(rng)
    wall = int(rng.integers(0, 4))
    art_w = uniform(rng, *ART_WIDTH)
    side = width if wall in (0, 2) else height
    lo = (1.5 + art_w / 2) / side
    if lo >= 0.5:
        raise Infeasible("wall too short")
    center, facing, tangent = wall_frame(width, height, wall, uniform(rng, lo, 1 - lo))
    normal = np.array([math.cos(facing), math.sin(facing)])
    n_viewers = int(rng.integers(VIEWERS[0], VIEWERS[1] + 1))
    viewers: list[PersonSpec] = []
    for pid in range(1, n_viewers + 1):
        for _ in range(50):
            p = (
                center
                + normal * uniform(rng, *VIEWER_DEPTH)
                + tangent * uniform(rng, -art_w / 2, art_w / 2)
            )
            if all(np.hypot(*(p - np.asarray(v.position))) >= VIEWER_SPACING for v in viewers):
                break
        else:
            raise Infeasible("viewers do not fit")
        yaw = face(p, center) + uniform(rng, -0.3, 0.3)
        viewers.append(PersonSpec(id=pid, position=xy(p), yaw=r3(yaw)))
    art = ArtworkSpec(
        center=xy(center), width=r3(art_w), facing=r3(facing), viewers=[v.id for v in viewers]
    )
    return width, height, art, viewers


def activity_spaces(art: ArtworkSpec, viewers: list[PersonSpec]) -> list[np.ndarray]:
    return [
        activity_space_polygon(
            np.asarray(art.center), art.width, art.facing, np.asarray(v.position)
        )
        for v in viewers
    ]


def draw(rng: np.random.Generator, name: str) -> Scenario:
    width, height, art, viewers = draw_gallery(rng)
    center = np.asarray(art.center)
    avoid = [(center, 3.0)] + [(np.asarray(v.position), 1.5) for v in viewers]
    start_xy = random_free_point(rng, width, height, avoid)
    nearest = min(viewers, key=lambda v: float(np.linalg.norm(np.asarray(v.position) - center)))
    goal_xy = center + 0.4 * (np.asarray(nearest.position) - center)
    yaw = face(start_xy, goal_xy)
    scn = Scenario(
        name=name,
        family="gallery_present",
        description=f"generated gallery (present): {len(viewers)} viewers",
        map={"walls": room_walls(width, height)},
        start=(*xy(start_xy), r3(yaw)),
        goal=(*xy(goal_xy), r3(yaw)),
        people=viewers,
        artworks=[art],
        time_limit=time_limit_for(float(np.linalg.norm(goal_xy - start_xy)) * 1.5),
        success=success_options("gallery_present", True),
    )
    facts, _ = spot_facts(scn, blocked_polygons=activity_spaces(art, viewers))
    return scn.model_copy(update={"feasibility": facts})


GENERATORS.add("gallery_present", Generator("gallery_present", __doc__ or "", draw))

"""Generated galleries, "pass": the robot walks past viewers without crossing their view.

Ranges: the room, artwork and viewers of :mod:`gallery_present` (0.8–2.0 m artwork on any wall,
1–3 viewers 1.0–2.5 m in front of it); start and goal lie on a line parallel to the wall,
0.6–0.9 m from it (between viewers and art, so the straight path crosses every activity space),
2.5–4 m to either side of the artwork's centre. Success: arrival at the given goal (0.10 m),
never inside an activity space.

Feasibility facts per robot: start and goal clear of walls for the footprint, and a path from
start to goal exists with every activity space blocked (behind the viewers); otherwise the
scene is drawn again.
"""

from __future__ import annotations

import numpy as np

from socialnav.sim.generate.common import (
    GENERATORS,
    ROBOTS,
    FreeSpace,
    Generator,
    Infeasible,
    footprint_clear,
    r3,
    robot_model,
    room_walls,
    success_options,
    time_limit_for,
    uniform,
    xy,
)
from socialnav.sim.generate.gallery_present import activity_spaces, draw_gallery
from socialnav.sim.scenario import Scenario

DEPTH = (0.6, 0.9)
REACH = (2.5, 4.0)


def draw(rng: np.random.Generator, name: str) -> Scenario:
    width, height, art, viewers = draw_gallery(rng)
    center = np.asarray(art.center)
    normal = np.array([np.cos(art.facing), np.sin(art.facing)])
    tangent = np.array([-normal[1], normal[0]])
    depth = uniform(rng, *DEPTH)
    sign = 1.0 if rng.random() < 0.5 else -1.0
    start_xy = center + normal * depth - sign * tangent * uniform(rng, *REACH)
    goal_xy = center + normal * depth + sign * tangent * uniform(rng, *REACH)
    for p in (start_xy, goal_xy):
        if not (1.0 <= p[0] <= width - 1.0 and 0.5 <= p[1] <= height - 0.5):
            raise Infeasible("start or goal outside the room")
    yaw = float(np.arctan2(*(goal_xy - start_xy)[::-1]))
    scn = Scenario(
        name=name,
        family="gallery_activity",
        description=f"generated gallery (pass): {len(viewers)} viewers",
        map={"walls": room_walls(width, height)},
        start=(*xy(start_xy), r3(yaw)),
        goal=(*xy(goal_xy), r3(yaw)),
        people=viewers,
        artworks=[art],
        time_limit=time_limit_for(float(np.linalg.norm(goal_xy - start_xy)) * 2.0),
        success=success_options("gallery_activity", False),
    )
    polys = activity_spaces(art, viewers)
    facts: dict[str, dict[str, float | bool | str]] = {}
    for robot_name in ROBOTS:
        robot = robot_model(robot_name)
        space = FreeSpace(scn, robot, blocked_polygons=polys)
        for pose, what in ((scn.start, "start"), (scn.goal, "goal")):
            ok, why = footprint_clear(scn, robot, pose, space)
            if not ok:
                raise Infeasible(f"{robot_name}: {what}: {why}")
        # start and goal sit in front of the art, inside the (blocked) spaces' inflation: snap
        if not space.connected(scn.start, scn.goal, snap=0.8):
            raise Infeasible(f"{robot_name}: no way around the viewers")
        facts[robot_name] = {"pass_behind_reachable": True}
    return scn.model_copy(update={"feasibility": facts})


GENERATORS.add("gallery_pass", Generator("gallery_pass", __doc__ or "", draw))

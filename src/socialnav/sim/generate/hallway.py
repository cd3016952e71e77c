"""Generated hallways: a straight corridor, 0–3 people standing or walking.

Ranges: width 2.2–4.0 m, length 12–16 m; the robot drives from x = 3 m to 2 m before the far
end, its lateral offset within ±0.3·(half width − 0.6) m; 0–3 people, in units of one person
or two side by side (0.6–0.8 m apart), standing (30 %) or walking at 0.3–1.5 m/s, from the far
end toward the robot or from behind it (the robot's end) in its direction, on either side
(lateral offset up to half width − 0.4 m). People ignore the robot (the paper's model).

Feasibility facts per robot model (the robot drives along the corridor, so its footprint's
half width ``w`` limits it to ``|y| <= W/2 − w − 0.05``):
- ``corridor_width``: ``W`` (m);
- ``max_clearance_<id>``: the largest centre-to-centre distance from person ``id`` the corridor
  allows while passing (for a side-by-side pair, on the side that is best for both);
- ``passage``: a gap of at least the robot's width + 0.1 m exists beside every unit, and a
  way through everyone standing at once (units one behind the other can close the corridor);
- ``joint_clearance``: the largest distance from *every* person at once that a path to the goal
  can keep, walkers' timing included (:func:`~socialnav.sim.generate._passage.joint_clearance`,
  capped at 3 m; generous to the robot, so it may exceed a per-person bound by up to half a
  grid cell): two walkers passing the robot together on both sides leave less than either
  one alone;
- ``collision_free``: some command sequence within the robot's velocity and acceleration
  limits avoids every walker (:func:`~socialnav.sim.generate._passage.can_avoid_collision`:
  a walker overtaking from right behind, faster than the robot can step aside, hits it).
- ``personal_space_feasible``: whether ``no_personal_space_intrusion`` is required (below).
No passage or no collision-free way for some robot → the scene is drawn again. A joint
clearance below the 1.2 m personal space (+0.05 m) marks ``no_personal_space_intrusion`` not
required for that robot, with the reason (the per-person bound assumes the robot passes each
person, which a walker behind it that never catches up disproves). So does a start no command
sequence of the robot gets through at 1.2 m
(:func:`~socialnav.sim.generate._passage.can_keep_distance`, the first 4 s, the lattice of
``collision_free``): the joint clearance lets the robot move any way at once, and a Pioneer
that first has to turn cannot leave the lane of a fast walker closing from just behind
(development seeds 0–99: Pioneer 53, 66, 69, 97 and 99; none for the PR2, which moves
sideways at once, though its acceleration limits can bind too).
"""

from __future__ import annotations

import numpy as np

from socialnav.core.robot import RobotModel
from socialnav.core.scene import HUMAN_RADIUS
from socialnav.sim.generate._passage import (
    can_avoid_collision,
    can_keep_distance,
    joint_clearance,
)
from socialnav.sim.generate.common import (
    GENERATORS,
    POSITION_TOLERANCE,
    ROBOTS,
    FreeSpace,
    Generator,
    Infeasible,
    half_width,
    r3,
    robot_model,
    success_options,
    time_limit_for,
    uniform,
    xy,
)
from socialnav.sim.scenario import PersonSpec, RobotSuccessOverride, Scenario, Stand, Walk
from socialnav.social.proxemics import PERSONAL

WIDTH = (2.2, 4.0)
LENGTH = (12.0, 16.0)
SPEED = (0.3, 1.5)
PAIR_GAP = (0.6, 0.8)
START_X = 3.0
WALL_MARGIN = 0.4  # person centre to wall (m): radius 0.25 + a shoulder's room
CLEARANCE_MARGIN = 0.05
JOINT_CAP = 3.0  # m: clearances beyond this are reported as this
EARLY_HORIZON = 4.0  # s: the start of the episode that can_keep_distance searches


def draw(rng: np.random.Generator, name: str) -> Scenario:
    width, length = uniform(rng, *WIDTH), uniform(rng, *LENGTH)
    half = width / 2.0
    y0 = uniform(rng, -1.0, 1.0) * 0.3 * max(half - 0.6, 0.0)
    start, goal = (START_X, y0, 0.0), (length - 2.0, y0, 0.0)
    n_people = int(rng.integers(0, 4))
    units: list[list[float]] = []  # lateral offsets of each unit's members
    people: list[PersonSpec] = []
    pid = 1
    while sum(len(u) for u in units) < n_people:
        left = n_people - sum(len(u) for u in units)
        pair = left >= 2 and rng.random() < 0.4
        side = 1.0 if rng.random() < 0.5 else -1.0
        lim = half - WALL_MARGIN
        if pair:
            gap = uniform(rng, *PAIR_GAP)
            if 2 * lim < gap:
                raise Infeasible("corridor too narrow for a pair")
            inner = uniform(rng, -lim, lim - gap) * side
            lateral = sorted([inner, inner + side * gap])
        else:
            lateral = [side * uniform(rng, 0.0, lim)]
        standing = rng.random() < 0.3
        from_front = rng.random() < 0.6
        if standing:
            x = uniform(rng, START_X + 2.5, length - 4.0)
        elif from_front:
            x = uniform(rng, length - 4.0, length - 0.6)
        else:
            x = uniform(rng, 0.5, START_X - 1.6)
        speed = uniform(rng, *SPEED)
        for y in lateral:
            if standing:
                behavior: Stand | Walk = Stand()
                yaw = float(np.pi if rng.random() < 0.5 else 0.0)
            else:
                vx = -speed if from_front else speed
                end_x = 0.5 if from_front else length - 0.5
                behavior = Walk(velocity=(r3(vx), 0.0), until=(r3(end_x), r3(y)))
                yaw = None
            people.append(PersonSpec(id=pid, position=xy((x, y)), yaw=yaw, behavior=behavior))
            pid += 1
        units.append(lateral)
    ids = [p.id for p in people]
    walls = [
        ((0.0, -half), (length, -half)),
        ((0.0, half), (length, half)),
        ((0.0, -half), (0.0, half)),
        ((length, -half), (length, half)),
    ]
    scn = Scenario(
        name=name,
        family="hallway",
        description=f"generated hallway: width {width:.2f} m, {len(people)} people",
        map={"walls": walls},
        start=start,
        goal=goal,
        goal_tolerance=POSITION_TOLERANCE,
        people=people,
        time_limit=time_limit_for(goal[0] - start[0]),
    )
    feasibility: dict[str, dict[str, float | bool | str]] = {}
    per_robot: dict[str, dict[str, RobotSuccessOverride]] = {}
    for robot_name in ROBOTS:
        robot = robot_model(robot_name)
        w = half_width(robot)
        y_lim = half - w - CLEARANCE_MARGIN
        facts: dict[str, float | bool | str] = {"corridor_width": r3(width)}
        worst = np.inf
        k = 0
        for unit in units:
            best = max(min(abs(s * y_lim - y) for y in unit) for s in (1.0, -1.0))
            # free room beside the unit on its roomier side, wall to nearest member's edge
            room = max(half - max(unit) - 0.25, min(unit) + half - 0.25)
            if room < 2 * w + 0.1:
                raise Infeasible(f"{robot_name}: no passage beside a person")
            for _ in unit:
                facts[f"max_clearance_{ids[k]}"] = r3(best)
                k += 1
            worst = min(worst, best)
        space = FreeSpace(scn, robot, people=False)
        if not _standing_passage(scn, space, w, y_lim):
            raise Infeasible(f"{robot_name}: no passage through the people standing together")
        facts["passage"] = True
        joint = _joint(scn, robot, space, y_lim)
        if joint < HUMAN_RADIUS + robot.inscribed_radius or not can_avoid_collision(scn, robot):
            raise Infeasible(f"{robot_name}: no collision-free way past the people")
        facts["collision_free"] = True
        facts["joint_clearance"] = r3(min(joint, JOINT_CAP))
        # The joint clearance decides: a per-person bound assumes the robot passes that
        # person, which it need not (a slow walker behind it never catches up).
        if joint < PERSONAL + CLEARANCE_MARGIN:
            facts["personal_space_feasible"] = False
            binding = (
                f"the corridor allows at most {worst:.2f} m from a person"
                if worst < PERSONAL + CLEARANCE_MARGIN
                else f"no way keeps {PERSONAL} m from every person at once (people pass "
                f"at the same time): at most {joint:.2f} m"
            )
            reason = f"{binding} (< {PERSONAL} m + {CLEARANCE_MARGIN} m) for {robot_name}"
        elif not can_keep_distance(scn, robot, PERSONAL, EARLY_HORIZON):
            # The joint clearance lets the robot move any way at once; a differential drive
            # first has to turn, and a fast walker closing from just behind is past by then.
            facts["personal_space_feasible"] = False
            reason = (
                f"no command sequence within {robot_name}'s limits keeps {PERSONAL} m from every "
                f"person in the first {EARLY_HORIZON:g} s (someone closes in faster than it can "
                f"step aside), although the corridor allows {joint:.2f} m"
            )
        else:
            facts["personal_space_feasible"] = True
            reason = ""
        if reason:
            per_robot[robot_name] = {
                "no_personal_space_intrusion": RobotSuccessOverride(required=False, reason=reason)
            }
        feasibility[robot_name] = facts
    return scn.model_copy(
        update={
            "success": success_options("hallway", False, per_robot),
            "feasibility": feasibility,
        }
    )


def _standing_passage(scn: Scenario, space: FreeSpace, w: float, y_lim: float) -> bool:
    """The robot centre, inside the corridor's ``|y| <= y_lim`` (``W/2 - w - 0.05``) and
    ``w + 0.05`` m from everyone standing (``w``: the footprint's half width), joins start and
    goal: the per-unit rule above, for all units at once. Two units whose roomy sides do not
    line up (one near each wall, 0.4 m apart along the corridor) can each leave a passage
    alone and none together (reporting seed 10164: a PR2 waited beside them until the time
    limit). The walls are the analytic ``y_lim``, not the grid's (its cells reach 3.5 cm into
    the corridor); on the grid (``CHECK_RESOLUTION``) half a cell goes to the robot on either
    side, as in ``_joint``, so that a band of free positions narrower than a cell is not
    missed between the grid's points. ``space``: the robot's, without people."""
    xs, ys = space.geometry.cell_centers()
    half_cell = space.geometry.resolution / 2
    free = np.abs(ys) <= y_lim + half_cell
    for p in scn.people:
        if p.behavior.type == "stand":
            reach = p.radius + w + CLEARANCE_MARGIN - half_cell
            free &= np.hypot(xs - p.position[0], ys - p.position[1]) > reach
    return space.connected(scn.start, scn.goal, free=free)


def _joint(scn: Scenario, robot: RobotModel, space: FreeSpace, y_lim: float) -> float:
    """Joint clearance (m) with the robot centre inside the corridor's ``|y| <= y_lim``;
    ``space``: the robot's, without people."""
    xs, ys = space.geometry.cell_centers()
    free = space.free & (np.abs(ys) <= y_lim + space.geometry.resolution / 2)
    return joint_clearance(scn, robot, free, xs, ys, cap=JOINT_CAP)


GENERATORS.add("hallway", Generator("hallway", __doc__ or "", draw))

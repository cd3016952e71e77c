"""What every scene generator shares: the registry, seeded retries, rooms, feasibility checks."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import yaml

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.registry import Registry
from socialnav.core.robot import ROBOT_MODELS, RobotModel
from socialnav.core.success import FAMILIES, judged_family
from socialnav.sim.scenario import RobotSuccessOverride, Scenario, SuccessOverride

#: seeds from here on are the reporting split; below it, development
REPORTING_SEED = 10_000
#: the generated suite's per-run arrival tolerance (m, rad)
POSITION_TOLERANCE = 0.10
YAW_TOLERANCE = 0.2
#: robot models the feasibility facts are computed for
ROBOTS = ("pr2", "pioneer")
MAX_ATTEMPTS = 200
#: raster resolution (m) of the feasibility checks
CHECK_RESOLUTION = 0.05


class Infeasible(Exception):
    """A drawn scene cannot be done by some robot; the generator draws again."""


@dataclass(frozen=True)
class Generator:
    """``draw(rng, name) -> Scenario`` for one family; ``description`` lists its ranges."""

    family: str
    description: str
    draw: Callable[[np.random.Generator, str], Scenario]


GENERATORS: Registry[Generator] = Registry("generated family")


def generate(family: str, seed: int) -> Scenario:
    """Scene ``seed`` of ``family`` (see ``GENERATORS.names()``); deterministic.

    Draws from ``numpy.random.default_rng([crc(family), seed])`` until a feasible scene comes
    out (at most ``MAX_ATTEMPTS`` draws, else :class:`ConfigurationError`).
    """
    gen = GENERATORS.get(family)
    if seed < 0:
        raise ConfigurationError(f"seed must be >= 0, got {seed}")
    rng = np.random.default_rng([_salt(family), int(seed)])
    name = f"{family}_s{seed}"
    last = ""
    for _ in range(MAX_ATTEMPTS):
        try:
            scn = gen.draw(rng, name)
        except Infeasible as exc:
            last = str(exc)
            continue
        # One tolerance for the planner's goal, the baselines' task and the success check.
        return scn.model_copy(update={"seed": int(seed), "goal_tolerance": POSITION_TOLERANCE})
    raise ConfigurationError(
        f"{family} seed {seed}: no feasible scene in {MAX_ATTEMPTS} draws: {last}"
    )


def _salt(family: str) -> int:
    import zlib

    return zlib.crc32(family.encode())


def scenario_yaml(scn: Scenario) -> str:
    """The scene as a scenario YAML file (``socialnav run FILE`` / ``validate`` read it back)."""
    data = scn.model_dump(mode="json", exclude_defaults=False)
    return yaml.safe_dump(data, sort_keys=False)


# --- geometry helpers -------------------------------------------------------------------------


def room_walls(
    width: float, height: float
) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """The four walls of the room ``[0, width] × [0, height]`` (m)."""
    c = [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)]
    return [(c[i], c[(i + 1) % 4]) for i in range(4)]


def uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


def face(src: Sequence[float] | np.ndarray, dst: Sequence[float] | np.ndarray) -> float:
    return float(math.atan2(dst[1] - src[1], dst[0] - src[0]))


def r3(x: float) -> float:
    """Round to mm: YAML files stay readable and round-trip exactly."""
    return round(float(x), 3)


def xy(p: Sequence[float] | np.ndarray) -> tuple[float, float]:
    return (r3(p[0]), r3(p[1]))


def robot_model(name: str) -> RobotModel:
    return ROBOT_MODELS[name]


def half_width(robot: RobotModel) -> float:
    """Half the footprint's width (m): how close to a wall a robot driving along it gets."""
    return float(np.abs(robot.polygon[:, 1]).max())


class FreeSpace:
    """The robot centre's free cells: static map inflated by the inscribed radius, standing
    people inflated by person radius + inscribed radius, ``blocked`` polygons (activity spaces,
    queue bands: the footprint must stay out, so inflated by the inscribed radius) and discs
    (o-spaces: the success condition is on the robot's centre, so not inflated).
    ``distance_to_obstacle`` is the clearance (m) of a point to walls and obstacles."""

    def __init__(
        self,
        scn: Scenario,
        robot: RobotModel,
        blocked_polygons: Sequence[FloatArray] = (),
        blocked_discs: Sequence[tuple[FloatArray, float]] = (),
        people: bool = True,
    ) -> None:
        from scipy.ndimage import distance_transform_edt

        from socialnav.core.geometry import points_in_polygon
        from socialnav.world.grid import LETHAL

        costmap = scn.static_costmap(robot, resolution=CHECK_RESOLUTION)
        self.geometry = costmap.geometry
        res = self.geometry.resolution
        lethal = costmap.costs >= LETHAL
        self.clearance = distance_transform_edt(~lethal) * res  # (rows, cols) m
        self.free = self.clearance > robot.inscribed_radius
        xs, ys = self.geometry.cell_centers()
        r_in = robot.inscribed_radius
        if people:
            for p in scn.people:
                if p.behavior.type != "stand":
                    continue
                d = np.hypot(xs - p.position[0], ys - p.position[1])
                self.free &= d > p.radius + r_in
        pts = np.stack([xs.ravel(), ys.ravel()], axis=1)
        for poly in blocked_polygons:
            inside = points_in_polygon(pts, np.asarray(poly, dtype=float)).reshape(xs.shape)
            mask = distance_transform_edt(~inside) * res <= r_in
            self.free &= ~mask
        for center, radius in blocked_discs:
            d = np.hypot(xs - center[0], ys - center[1])
            self.free &= d > radius

    def cell(self, p: Sequence[float]) -> tuple[int, int] | None:
        rc = self.geometry.world_to_cell(np.asarray(p[:2], dtype=float))
        if not bool(self.geometry.in_bounds(rc)):
            return None
        return int(rc[0]), int(rc[1])

    def distance_to_obstacle(self, p: Sequence[float]) -> float:
        c = self.cell(p)
        return 0.0 if c is None else float(self.clearance[c])

    def connected(
        self,
        a: Sequence[float],
        b: Sequence[float],
        snap: float = 0.15,
        free: np.ndarray | None = None,
    ) -> bool:
        """A free path joins ``a`` and ``b`` (each snapped to a free cell within ``snap`` m:
        the end points themselves sit next to the people they are about); ``free`` (the grid's
        shape) replaces :attr:`free` as the robot centre's free cells."""
        from scipy.ndimage import label

        labels, _ = label(self.free if free is None else free)
        la, lb = self._label_near(labels, a, snap), self._label_near(labels, b, snap)
        return bool(la & lb)

    def _label_near(self, labels: np.ndarray, p: Sequence[float], snap: float) -> set[int]:
        c = self.cell(p)
        if c is None:
            return set()
        k = max(round(snap / self.geometry.resolution), 0)
        r0, c0 = max(c[0] - k, 0), max(c[1] - k, 0)
        window = labels[r0 : c[0] + k + 1, c0 : c[1] + k + 1]
        return {int(v) for v in np.unique(window) if v > 0}


def footprint_clear(
    scn: Scenario, robot: RobotModel, pose: Sequence[float], space: FreeSpace, margin: float = 0.03
) -> tuple[bool, str]:
    """The robot's footprint at ``pose (3,)`` touches no person (disc) and no wall, with
    ``margin`` (m); returns ``(ok, why not)``."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    poly = robot.polygon @ np.array([[c, s], [-s, c]]) + np.asarray(pose[:2])
    # Densify the footprint's edges: distance checks against points are then exact to ~1 cm.
    edges = np.concatenate(
        [
            np.linspace(a, b, 12, endpoint=False)
            for a, b in zip(poly, np.roll(poly, -1, 0), strict=True)
        ]
    )
    for p in scn.people:
        d = np.hypot(*(edges - np.asarray(p.position)).T).min()
        inside = _point_in_convex(np.asarray(p.position), poly)
        if inside or d < p.radius + margin:
            return False, f"footprint at the spot touches person {p.id}"
    wall = min(space.distance_to_obstacle(e) for e in edges)
    if wall < margin:
        return False, "footprint at the spot touches a wall or obstacle"
    return True, ""


def _point_in_convex(p: FloatArray, poly: FloatArray) -> bool:
    a, b = poly, np.roll(poly, -1, axis=0)
    cross = (b[:, 0] - a[:, 0]) * (p[1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (p[0] - a[:, 0])
    return bool(np.all(cross >= 0) or np.all(cross <= 0))


def social_goal_of(scn: Scenario) -> Any:
    """The social goal the scene resolves to from the robot's start (None when none)."""
    from socialnav.social.resolve import resolve_social_goal

    return resolve_social_goal(scn.social_context(), np.asarray(scn.goal), np.asarray(scn.start))


def spot_facts(
    scn: Scenario,
    blocked_polygons: Sequence[FloatArray] = (),
    blocked_discs: Sequence[tuple[FloatArray, float]] = (),
    spot_condition: str = "",
) -> tuple[dict[str, dict[str, Any]], Any]:
    """Per robot: is the social spot clear for the footprint, and reachable from the start
    without entering the ``blocked`` regions? Raises :class:`Infeasible` when not (the task
    itself would be impossible)."""
    goal = social_goal_of(scn)
    if goal is None:
        raise Infeasible("no social goal resolves")
    if goal.fallback in ("no_free_spot", "viewer_not_in_front"):
        raise Infeasible(f"social goal fallback {goal.fallback}")
    facts: dict[str, dict[str, Any]] = {}
    for name in ROBOTS:
        robot = robot_model(name)
        space = FreeSpace(scn, robot, blocked_polygons, blocked_discs)
        ok, why = footprint_clear(scn, robot, goal.pose, space)
        if not ok:
            raise Infeasible(f"{name}: {why}")
        if not space.connected(scn.start, goal.pose):
            raise Infeasible(f"{name}: the social spot is not reachable around the structure")
        start_ok, why = footprint_clear(scn, robot, scn.start, space)
        if not start_ok:
            raise Infeasible(f"{name}: start: {why}")
        facts[name] = {
            "social_goal": str(goal.kind),
            "social_goal_fallback": str(goal.fallback or ""),
            "spot_x": r3(goal.pose[0]),
            "spot_y": r3(goal.pose[1]),
            "spot_reachable": True,
            "spot_clearance": r3(space.distance_to_obstacle(goal.pose)),
        }
    return facts, goal


#: the conditions that judge arrival at the target's position (the social spot's included)
POSITION_CONDITIONS = ("reached_goal", "at_presenter_spot", "at_tail_slot", "at_free_spot")


def success_options(
    family: str,
    at_spot: bool,
    per_robot: dict[str, dict[str, RobotSuccessOverride]] | None = None,
    has_queue: bool = False,
) -> dict[str, SuccessOverride]:
    """The generated suite's ``success:`` overrides for a scene of ``family``: arrival within
    :data:`POSITION_TOLERANCE` (target and social spot), the final yaw within
    :data:`YAW_TOLERANCE` where the target is a social spot (``at_spot``), and ``per_robot``
    (robot model → condition → change, e.g. not required with the reason)."""
    names = {c.name for c in FAMILIES.get(judged_family(family, has_queue)).conditions}
    out = {n: SuccessOverride(tolerance=POSITION_TOLERANCE) for n in POSITION_CONDITIONS}
    if at_spot:
        out["arrival_yaw"] = SuccessOverride(tolerance=YAW_TOLERANCE)
    for robot, changes in (per_robot or {}).items():
        for name, change in changes.items():
            entry = out.setdefault(name, SuccessOverride())
            entry.per_robot[robot] = change
    return {n: o for n, o in out.items() if n in names}


def time_limit_for(distance: float, slack: float = 40.0) -> float:
    """A time limit (s) for a path of ``distance`` m: 0.3 m/s average plus ``slack``."""
    return float(math.ceil(distance / 0.3 + slack))

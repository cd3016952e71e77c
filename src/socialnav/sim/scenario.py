"""Scenario files: the paper's test situations as validated YAML.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization
Approach" (section "Results") evaluate a hallway, an art gallery, a queue and a group in Stage.
The paper shows their geometry only in figures; the files in ``sim/scenarios/`` fix the numbers
(read off the figures and text, the same for every planner). Deviations/choices:

- start yaws (other than the hallway's) and goal yaws are not given: starts face the given goal,
  goals face the direction of travel (or the art/desk where the goal is "in front of" it);
- walkers without an end point in scenarios.md stop 0.5 m before the corridor's open end;
- the desk is a rectangle obstacle; navground sees it as four wall segments.

A scenario is pure data (no simulator import): ``engine.py`` turns it into a navground world.
Units: metres, seconds, radians; yaw counter-clockwise from +x.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import yaml
from numpy.typing import NDArray
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    model_validator,
)

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.scene import (
    HUMAN_RADIUS,
    Artwork,
    Group,
    Person,
    Queue,
    SocialContext,
    Structure,
)
from socialnav.core.success import (
    FAMILIES,
    ConditionOverride,
    ConditionSpec,
    apply_overrides,
    judged_family,
)
from socialnav.social.spaces import fit_circle
from socialnav.social.structures import (
    make_structure,
    structure_conditions,
    structure_json_schemas,
)
from socialnav.world.grid import Costmap, GridGeometry

#: the group family's conditions on joining the group: not required when no standing group of
#: the scene passes the sanity limits (:meth:`Scenario.family_conditions`)
JOIN_CONDITIONS = ("at_free_spot", "facing_centre", "outside_o_space")

DISC_POLYGON_SIDES = 24


def _finite(value: float) -> float:
    if not math.isfinite(value):
        raise ValueError("must be a finite number")
    return value


def _positive(value: float) -> float:
    if not value > 0:
        raise ValueError("must be positive")
    return value


def _non_negative(value: float) -> float:
    if not value >= 0:
        raise ValueError("must be non-negative")
    return value


Finite = Annotated[float, AfterValidator(_finite)]
Positive = Annotated[float, AfterValidator(_finite), AfterValidator(_positive)]
NonNegative = Annotated[float, AfterValidator(_finite), AfterValidator(_non_negative)]
Vec2 = tuple[Finite, Finite]
Pose = tuple[Finite, Finite, Finite]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


# --- map -----------------------------------------------------------------------------------


class Rectangle(_Model):
    """A rectangular obstacle (e.g. the desk): ``size = (length along its own x, width)``."""

    center: Vec2
    size: tuple[Positive, Positive]
    yaw: Finite = 0.0

    def polygon(self) -> FloatArray:
        """Corners ``(4, 2)`` counter-clockwise, world frame."""
        hx, hy = self.size[0] / 2.0, self.size[1] / 2.0
        local = np.array([[hx, hy], [-hx, hy], [-hx, -hy], [hx, -hy]])
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return local @ np.array([[c, -s], [s, c]]).T + np.asarray(self.center)


class DiscObstacle(_Model):
    center: Vec2
    radius: Positive


class MapSpec(_Model):
    """Vector geometry and/or a ROS map_server map (``ros_map``: path relative to the YAML)."""

    walls: list[tuple[Vec2, Vec2]] = Field(default_factory=list)
    polygons: list[list[Vec2]] = Field(default_factory=list)
    rectangles: list[Rectangle] = Field(default_factory=list)
    discs: list[DiscObstacle] = Field(default_factory=list)
    ros_map: str | None = None
    margin: NonNegative = Field(1.0, description="free border around the geometry (costmap)")

    @model_validator(mode="after")
    def _check(self) -> MapSpec:
        for i, poly in enumerate(self.polygons):
            if len(poly) < 3:
                raise ValueError(f"polygons.{i}: a polygon needs at least 3 vertices")
        for i, (a, b) in enumerate(self.walls):
            if a == b:
                raise ValueError(f"walls.{i}: a wall needs two distinct end points")
        return self


# --- people --------------------------------------------------------------------------------


class Stand(_Model):
    type: Literal["stand"] = "stand"


class Walk(_Model):
    """Constant velocity along a line, not reacting to anyone, stopping at the end point.

    Give ``velocity`` (m/s, world) or ``speed`` + ``heading``; end at ``until`` (its projection on
    the walking line) or after ``distance`` metres; neither: walk until the time limit.
    """

    type: Literal["walk"] = "walk"
    velocity: Vec2 | None = None
    speed: Positive | None = None
    heading: Finite | None = None
    until: Vec2 | None = None
    distance: Positive | None = None

    @model_validator(mode="after")
    def _check(self) -> Walk:
        has_speed = self.speed is not None or self.heading is not None
        if (self.velocity is None) == (not has_speed):
            raise ValueError("give either 'velocity' or 'speed' and 'heading'")
        if has_speed and (self.speed is None or self.heading is None):
            raise ValueError("'speed' and 'heading' go together")
        if self.velocity is not None and math.hypot(*self.velocity) == 0.0:
            raise ValueError("velocity must be non-zero (use 'stand')")
        if self.until is not None and self.distance is not None:
            raise ValueError("give at most one of 'until' and 'distance'")
        return self

    def direction_speed(self) -> tuple[FloatArray, float]:
        """Unit direction ``(2,)`` and speed (m/s)."""
        if self.velocity is not None:
            v = np.asarray(self.velocity, dtype=float)
            speed = float(np.linalg.norm(v))
            return v / speed, speed
        assert self.heading is not None and self.speed is not None
        return np.array([math.cos(self.heading), math.sin(self.heading)]), float(self.speed)

    def length(self, start: Sequence[float]) -> float:
        """Walked distance (m) from ``start``; ``inf`` when the walk never ends."""
        if self.distance is not None:
            return float(self.distance)
        if self.until is None:
            return math.inf
        direction, _ = self.direction_speed()
        return float(np.dot(np.asarray(self.until) - np.asarray(start), direction))


class Track(_Model):
    """A recorded or precomputed path: ``points[k]`` is the position at ``t = k·dt`` (s); the
    person stops at the last point. People on a track ignore the robot (CrowdNav's "invisible
    robot" test bank: the crowd's ORCA paths are computed without the robot)."""

    type: Literal["track"] = "track"
    dt: Positive
    points: list[Vec2] = Field(min_length=2)

    def direction_speed(self) -> tuple[FloatArray, float]:
        """Unit direction ``(2,)`` and speed (m/s) of the first segment (a still first
        segment gives direction +x and speed 0)."""
        d = np.asarray(self.points[1], dtype=float) - np.asarray(self.points[0], dtype=float)
        n = float(np.linalg.norm(d))
        if n == 0.0:
            return np.array([1.0, 0.0]), 0.0
        return d / n, n / self.dt


class PersonSpec(_Model):
    id: int
    position: Vec2
    yaw: Finite | None = Field(None, description="default: the walking heading, else 0")
    radius: Positive = HUMAN_RADIUS
    behavior: Stand | Walk | Track = Field(default_factory=Stand, discriminator="type")
    reactive_goal: Vec2 | None = Field(
        None, description="target for --humans reactive (default: walk end, or stay in place)"
    )

    @model_validator(mode="after")
    def _check(self) -> PersonSpec:
        if isinstance(self.behavior, Walk) and self.behavior.length(self.position) <= 0:
            raise ValueError("behavior.until lies behind the start (or on it)")
        if isinstance(self.behavior, Track) and tuple(self.behavior.points[0]) != tuple(
            self.position
        ):
            raise ValueError("behavior.points.0 must equal position")
        return self

    @property
    def heading(self) -> float:
        """The yaw the person faces (rad)."""
        if self.yaw is not None:
            return float(self.yaw)
        if isinstance(self.behavior, Walk | Track):
            d, _ = self.behavior.direction_speed()
            return float(math.atan2(d[1], d[0]))
        return 0.0

    def initial_velocity(self) -> FloatArray:
        if isinstance(self.behavior, Walk | Track):
            d, speed = self.behavior.direction_speed()
            return d * speed
        return np.zeros(2)

    def end_point(self) -> FloatArray | None:
        """Where a scripted walk or track ends (``None`` for standing people or endless walks)."""
        if isinstance(self.behavior, Track):
            return np.asarray(self.behavior.points[-1], dtype=float)
        if not isinstance(self.behavior, Walk):
            return None
        length = self.behavior.length(self.position)
        if not math.isfinite(length):
            return None
        d, _ = self.behavior.direction_speed()
        return np.asarray(self.position, dtype=float) + d * length


class GroupSpec(_Model):
    members: list[int] = Field(min_length=2)
    mode: Literal["join", "lead", "walking"] = Field(
        "join", description="join/lead a standing group, or walking: people moving together"
    )


class QueueSpec(_Model):
    members: list[int] = Field(min_length=1, description="head (being served) to tail")
    service_point: Vec2
    spacing: Positive = 0.8


class ArtworkSpec(_Model):
    center: Vec2
    width: Positive
    facing: Finite = Field(description="yaw of the artwork's normal into the room (rad)")
    viewers: list[int] = Field(default_factory=list)


class RobotSuccessOverride(_Model):
    """A change to one success condition for one robot model (``success.NAME.per_robot``)."""

    required: bool | None = Field(None, description="whether the condition counts toward success")
    tolerance: Finite | None = Field(None, description="the condition's tolerance, in its unit")
    reason: str | None = Field(None, description="why it is not required (shown in reports)")

    def override(self) -> ConditionOverride:
        tolerance = None if self.tolerance is None else float(self.tolerance)
        return ConditionOverride(self.required, tolerance, self.reason)


class SuccessOverride(RobotSuccessOverride):
    """A scenario's change to one success condition (``success: {NAME: {...}}``);
    ``per_robot`` changes it further for one robot model (a corridor wide enough for one
    robot's clearance may not be for another's)."""

    per_robot: dict[str, RobotSuccessOverride] = Field(
        default_factory=dict, description="robot model name → its own change of this condition"
    )


def _known_family(value: str) -> str:
    if value not in FAMILIES:
        raise ValueError(FAMILIES.unknown_message(value))
    return value


def _structures(value: list[dict[str, Any]]) -> list[dict[str, Any]]:
    for i, item in enumerate(value):
        make_structure(item, where=str(i))  # raises with the entry's index and field
    return value


class Jitter(_Model):
    """Per-seed randomization (see :meth:`Scenario.randomize`)."""

    position_sigma: NonNegative = Field(0.0, description="Gaussian σ on people positions (m)")
    speed_sigma: NonNegative = Field(0.0, description="Gaussian σ on walking speeds (m/s)")
    speed_uniform: NonNegative = Field(0.0, description="uniform ± on walking speeds (m/s)")
    start_shift: NonNegative = Field(
        0.0, description="uniform ± shift of a walker's start along its walking line (m)"
    )
    lateral_shift: NonNegative = Field(
        0.0,
        description="uniform ± shift of a walker's whole line sideways, perpendicular to its "
        "walking direction (m); drawn from its own stream, so other draws do not change",
    )


# --- the scenario ---------------------------------------------------------------------------


class Scenario(_Model):
    """One test situation: map, robot start and given goal, people and their social structure."""

    name: str
    family: Annotated[str, AfterValidator(_known_family)] = Field(
        description="a registered scenario family (socialnav.core.success.FAMILIES)"
    )
    description: str = ""
    map: MapSpec = Field(default_factory=MapSpec)
    start: Pose
    goal: Pose
    goal_tolerance: Positive = 0.3
    people: list[PersonSpec] = Field(default_factory=list)
    groups: list[GroupSpec] = Field(default_factory=list)
    queues: list[QueueSpec] = Field(default_factory=list)
    artworks: list[ArtworkSpec] = Field(default_factory=list)
    structures: Annotated[list[dict[str, Any]], AfterValidator(_structures)] = Field(
        default_factory=list,
        description="social structures of registered kinds: {type: KIND, ...its parameters}",
    )
    success: dict[str, SuccessOverride] = Field(
        default_factory=dict,
        description="per-condition overrides of the family's success conditions",
    )
    time_limit: Positive = 60.0
    control_period: Positive = 0.1
    seed: int = 0
    jitter: Jitter = Field(default_factory=Jitter)
    humans: Literal["scripted", "reactive"] | None = Field(
        None, description="the human model this scene needs (overrides the run's default)"
    )
    reactive_behavior: Literal["HL", "ORCA", "SocialForce"] | None = Field(
        None, description="navground behaviour of reactive people (default HL)"
    )
    feasibility: dict[str, dict[str, float | bool | str]] = Field(
        default_factory=dict,
        description="facts per robot model that the success conditions rely on (generated "
        "scenes: largest clearance per person, passage, reachable social spot)",
    )

    _source: Path | None = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _check_references(self) -> Scenario:
        ids = [p.id for p in self.people]
        dup = sorted({i for i in ids if ids.count(i) > 1})
        if dup:
            raise ValueError(f"people: duplicate ids {dup}")
        known = set(ids)
        for kind, items, attr in (
            ("groups", self.groups, "members"),
            ("queues", self.queues, "members"),
            ("artworks", self.artworks, "viewers"),
        ):
            for i, item in enumerate(items):
                missing = [m for m in getattr(item, attr) if m not in known]
                if missing:
                    raise ValueError(f"{kind}.{i}.{attr}: unknown person ids {missing}")
        for i, structure in enumerate(self.structure_list()):
            missing = [m for m in structure.member_ids if m not in known]
            if missing:
                raise ValueError(f"structures.{i}: unknown person ids {missing}")
        self.success_spec()  # an override of a condition that does not apply fails here
        if self.control_period > self.time_limit:
            raise ValueError("control_period must not exceed time_limit")
        return self

    # -- files ------------------------------------------------------------------------------

    @property
    def source(self) -> Path | None:
        """The YAML file this scenario was loaded from, if any."""
        return self._source

    def with_source(self, source: Path | None) -> Scenario:
        copy = self.model_copy()
        copy._source = source
        return copy

    def person(self, person_id: int) -> PersonSpec:
        for p in self.people:
            if p.id == person_id:
                return p
        raise KeyError(person_id)

    # -- social structure ---------------------------------------------------------------------

    def social_context(self, robot_pose: Sequence[float] | None = None) -> SocialContext:
        """The initial :class:`SocialContext` (people at their start, walkers' velocities).

        ``robot_pose`` is accepted for interface symmetry with perception (everything is
        visible in simulation) and is not used.
        """
        del robot_pose
        people = tuple(
            Person(
                id=p.id,
                position=(float(p.position[0]), float(p.position[1])),
                velocity=tuple(float(v) for v in p.initial_velocity()),  # type: ignore[arg-type]
                yaw=p.heading,
                radius=float(p.radius),
            )
            for p in self.people
        )
        return self.context_with_people(people)

    def structure_list(self) -> tuple[Structure, ...]:
        """The ``structures:`` entries, validated by their kinds."""
        return tuple(
            make_structure(s, where=f"structures.{i}") for i, s in enumerate(self.structures)
        )

    def family_conditions(self) -> tuple[ConditionSpec, ...]:
        """The family's and structures' conditions, before this scenario's overrides (a
        ``mixed`` scene is judged as ``queue`` when it has a queue, else as ``group``). When
        no standing group passes the sanity limits (:meth:`group_warnings`), there is no
        join target: the conditions on joining one are not required, with the reason."""
        family = judged_family(self.family, bool(self.queues))
        specs = FAMILIES.get(family).conditions + structure_conditions(self.structure_list())
        standing = [g for g in self.groups if g.mode != "walking"]
        warnings = self.group_warnings()
        if family == "group" and standing and len(warnings) == len(standing):
            why = "; ".join(warnings)
            specs = tuple(
                dataclasses.replace(c, required=False, reason=why)
                if c.name in JOIN_CONDITIONS
                else c
                for c in specs
            )
        return specs

    def group_warnings(self) -> tuple[str, ...]:
        """One line per standing group that is no join target: its fitted circle, spacing or
        members fail :mod:`socialnav.social.plausibility` (``socialnav validate`` prints
        them; the planner plans around such members as people)."""
        from socialnav.social.plausibility import implausible_groups

        return tuple(
            f"groups.{k}: not a join target: {why}"
            for k, why in implausible_groups(self.social_context())
        )

    def success_spec(self, robot: str = "") -> tuple[ConditionSpec, ...]:
        """The conditions this scenario is judged on: :meth:`family_conditions` with its
        ``success:`` overrides applied, then those of ``per_robot[robot]``. Raises
        ``ConfigurationError`` for an override of a condition that does not apply."""
        specs = self.family_conditions()
        specs = apply_overrides(
            specs, {k: v.override() for k, v in self.success.items()}, where=self.name
        )
        per_robot = {k: v.per_robot[robot] for k, v in self.success.items() if robot in v.per_robot}
        return apply_overrides(specs, {k: o.override() for k, o in per_robot.items()}, self.name)

    def context_with_people(self, people: tuple[Person, ...]) -> SocialContext:
        """Groups, queues, artworks and structures of this scenario around the given people."""
        return SocialContext(
            people=people,
            groups=tuple(Group(tuple(g.members), g.mode) for g in self.groups),
            queues=tuple(
                Queue(
                    tuple(q.members),
                    (float(q.service_point[0]), float(q.service_point[1])),
                    float(q.spacing),
                )
                for q in self.queues
            ),
            artworks=tuple(
                Artwork(
                    (float(a.center[0]), float(a.center[1])),
                    float(a.width),
                    float(a.facing),
                    tuple(a.viewers),
                )
                for a in self.artworks
            ),
            structures=self.structure_list(),
        )

    # -- geometry -----------------------------------------------------------------------------

    def ros_map_path(self) -> Path | None:
        if self.map.ros_map is None:
            return None
        path = Path(self.map.ros_map)
        if not path.is_absolute() and self._source is not None:
            path = self._source.parent / path
        return path

    def _load_ros_map(self) -> Any:
        from socialnav.world.mapio import load_map

        path = self.ros_map_path()
        if path is None:
            return None
        try:
            return load_map(path)
        except (OSError, ValueError) as exc:
            where = self._source.name if self._source is not None else self.name
            raise ConfigurationError(f"{where}: map.ros_map: {exc}") from exc

    def walls_array(self) -> FloatArray:
        """Wall segments ``(S, 2, 2)``: the vector walls plus, with a ROS map, the boundaries
        between occupied and other cells (merged into straight runs)."""
        walls = np.asarray(self.map.walls, dtype=float).reshape(-1, 2, 2)
        occ = self._load_ros_map()
        if occ is not None:
            occupied, _ = _ros_masks(occ)
            walls = np.concatenate([walls, occupancy_boundaries(occupied, occ.geometry)])
        return walls

    def obstacle_polygons(self) -> list[FloatArray]:
        """Obstacle polygons ``(V, 2)``: polygons, rectangles (the desk) and discs as
        ``DISC_POLYGON_SIDES``-gons (discs stay exact discs for navground and collisions)."""
        polys = [np.asarray(p, dtype=float) for p in self.map.polygons]
        polys += [r.polygon() for r in self.map.rectangles]
        angles = np.linspace(0.0, 2 * np.pi, DISC_POLYGON_SIDES, endpoint=False)
        unit = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        polys += [np.asarray(d.center) + d.radius * unit for d in self.map.discs]
        return polys

    def discs_array(self) -> FloatArray:
        """Disc obstacles ``(D, 3)`` as ``[x, y, r]``."""
        return np.array([[*d.center, d.radius] for d in self.map.discs], dtype=float).reshape(-1, 3)

    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` of all geometry, start, goal and people, plus margin."""
        pts = [np.asarray(self.start[:2])[None], np.asarray(self.goal[:2])[None]]
        pts.append(np.asarray(self.map.walls, dtype=float).reshape(-1, 2))
        pts += self.obstacle_polygons()
        pts.append(np.array([p.position for p in self.people], dtype=float).reshape(-1, 2))
        allp = np.concatenate(pts)
        lo, hi = allp.min(axis=0) - self.map.margin, allp.max(axis=0) + self.map.margin
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    def static_costmap(self, robot: RobotModel, resolution: float = 0.05) -> Costmap:
        """Walls and obstacles rasterized and inflated for ``robot`` (people are *not* in it:
        the planner sees them through the SocialContext).

        With a ROS map the map's own grid (and resolution) is used and the vector geometry is
        drawn on top of it.
        """
        from socialnav.world.inflation import inflate

        occupied, unknown, geometry = self._occupancy(resolution)
        return inflate(occupied, geometry, robot.inscribed_radius, unknown=unknown)

    def _occupancy(self, resolution: float) -> tuple[NDArray[np.bool_], Any, GridGeometry]:
        """Occupied cells (walls, obstacles, ROS map), UNKNOWN cells (ROS map or None), grid."""
        from scipy.ndimage import binary_dilation

        from socialnav.world.raster import rasterize

        occ = self._load_ros_map()
        unknown = None
        if occ is not None:
            geometry = occ.geometry
            base, unknown = _ros_masks(occ)
        else:
            if not (math.isfinite(resolution) and resolution > 0):
                raise ConfigurationError(f"resolution must be positive, got {resolution}")
            xmin, ymin, xmax, ymax = self.bounds()
            shape = (math.ceil((ymax - ymin) / resolution), math.ceil((xmax - xmin) / resolution))
            geometry = GridGeometry(shape, resolution, (xmin, ymin))
            base = np.zeros(shape, dtype=bool)
        walls = rasterize(
            geometry, segments=np.asarray(self.map.walls, dtype=float).reshape(-1, 2, 2)
        )
        solids = rasterize(
            geometry,
            polygons=[np.asarray(p, dtype=float) for p in self.map.polygons]
            + [r.polygon() for r in self.map.rectangles],
            discs=self.discs_array(),
        )
        # Polygons and discs mark cells whose centre is inside; one cell of dilation makes the
        # grid cover the true shape, so a footprint legal on the grid cannot touch the shape.
        # (Wall segments already mark every cell they pass within half a cell diagonal of.)
        occupied = base | walls | binary_dilation(solids, structure=np.ones((3, 3), dtype=bool))
        return occupied, unknown, geometry

    def geometry_problems(self) -> list[str]:
        """What is wrong with the scene's geometry, each naming the field: a start, goal or
        person inside a wall or obstacle (on the map's occupied cells, without inflation), a
        goal or start outside the map (off a ROS map's grid or on its UNKNOWN cells; without
        one, outside the walls' extent). Raises ``ConfigurationError`` for a missing or
        unreadable ROS map file (``map.ros_map``)."""
        occupied, unknown, geo = self._occupancy(0.05)
        walls = np.asarray(self.map.walls, dtype=float).reshape(-1, 2)
        points = [("start", self.start[:2]), ("goal", self.goal[:2])]
        points += [(f"people.{i}.position", p.position) for i, p in enumerate(self.people)]
        problems = []
        for field, xy in points:
            x, y = float(xy[0]), float(xy[1])
            rc = geo.world_to_cell(np.array([x, y]))
            on_grid = bool(geo.in_bounds(rc))
            if field in ("start", "goal"):
                outside = not on_grid or (unknown is not None and bool(unknown[rc[0], rc[1]]))
                if self.map.ros_map is None and walls.size:
                    lo, hi = walls.min(axis=0), walls.max(axis=0)
                    outside = not (lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1])
                if outside:
                    problems.append(f"{field}: ({x:g}, {y:g}) is outside the map")
                    continue
            if on_grid and bool(occupied[rc[0], rc[1]]):
                problems.append(f"{field}: ({x:g}, {y:g}) is inside a wall or obstacle")
        return problems

    # -- randomization ------------------------------------------------------------------------

    def randomize(self, seed: int, vary_group_sizes: bool = False) -> Scenario:
        """A copy with this scenario's :class:`Jitter` applied, drawn from
        ``numpy.random.default_rng(seed)`` (same seed → same scenario).

        ``vary_group_sizes`` re-draws each group's size in ``{n-1, n, n+1}`` (at least 2),
        keeping its circle and the centre of its widest gap, members evenly spread over the
        rest of the circle, facing the centre (queue/artwork people are never moved off).
        """
        rng = np.random.default_rng(seed)
        lateral_rng = np.random.default_rng([seed, 1])  # own stream: older draws unchanged
        j = self.jitter
        people: list[PersonSpec] = []
        for p in self.people:
            # Draw every number for every person so the stream does not depend on the config.
            d_pos = rng.normal(0.0, 1.0, 2) * j.position_sigma
            d_speed = rng.normal(0.0, 1.0) * j.speed_sigma + rng.uniform(-1, 1) * j.speed_uniform
            d_start = rng.uniform(-1, 1) * j.start_shift
            d_lateral = lateral_rng.uniform(-1, 1) * j.lateral_shift
            if isinstance(p.behavior, Track):  # a track is data: never jittered
                people.append(p)
                continue
            pos = np.asarray(p.position, dtype=float) + d_pos
            update: dict[str, Any] = {}
            if isinstance(p.behavior, Walk):
                direction, speed = p.behavior.direction_speed()
                normal = np.array([-direction[1], direction[0]])
                pos = pos + direction * d_start + normal * d_lateral
                new_speed = max(speed + d_speed, 0.05)
                shifted = {}
                if p.behavior.until is not None and d_lateral:
                    until = np.asarray(p.behavior.until, dtype=float) + normal * d_lateral
                    shifted["until"] = (float(until[0]), float(until[1]))
                walk = p.behavior.model_copy(
                    update={
                        "velocity": (
                            float(direction[0] * new_speed),
                            float(direction[1] * new_speed),
                        ),
                        "speed": None,
                        "heading": None,
                        **shifted,
                    }
                )
                update["behavior"] = walk
                if p.yaw is None:
                    update["yaw"] = p.heading
            update["position"] = (float(pos[0]), float(pos[1]))
            people.append(p.model_copy(update=update))
        out = self.model_copy(update={"people": people, "seed": int(seed)})
        if vary_group_sizes and self.groups:
            out = _vary_groups(out, rng)
        # Re-validate: jitter may have produced an invalid walk (end behind start).
        return Scenario.model_validate(out.model_dump()).with_source(self._source)


def _vary_groups(scn: Scenario, rng: np.random.Generator) -> Scenario:
    people = list(scn.people)
    groups = []
    next_id = max((p.id for p in people), default=0) + 1
    for g in scn.groups:
        members = [scn.person(i) for i in g.members]
        pos = np.array([m.position for m in members], dtype=float)
        center = pos.mean(axis=0) if len(pos) < 3 else fit_circle(pos)[0]
        radius = float(np.linalg.norm(pos - center, axis=1).mean())
        ang = np.sort(np.arctan2(pos[:, 1] - center[1], pos[:, 0] - center[0]))
        gaps = np.diff(np.concatenate([ang, ang[:1] + 2 * np.pi]))
        k = int(np.argmax(gaps))
        gap_lo, gap = ang[k], gaps[k]
        n = max(2, len(members) + int(rng.integers(-1, 2)))
        # Members over the arc outside the gap, ends included: the gap stays where it was.
        arc = np.linspace(gap_lo + gap, gap_lo + 2 * np.pi, n)
        people = [p for p in people if p.id not in g.members]
        new_ids = []
        reuse = list(g.members)
        for a in arc:
            pid = reuse.pop(0) if reuse else next_id
            xy = center + radius * np.array([math.cos(a), math.sin(a)])
            people.append(
                PersonSpec(
                    id=pid,
                    position=(float(xy[0]), float(xy[1])),
                    yaw=float(math.atan2(-math.sin(a), -math.cos(a))),
                )
            )
            new_ids.append(pid)
            next_id = max(next_id, pid + 1)
        groups.append(g.model_copy(update={"members": new_ids}))
    return scn.model_copy(update={"people": people, "groups": groups})


def _ros_masks(occ: Any) -> tuple[np.ndarray, np.ndarray]:
    """Occupied and unknown masks of a loaded ROS map, read as costmap_2d's static layer does."""
    return occ.occupied_mask(), occ.unknown_mask()


def occupancy_boundaries(occupied: np.ndarray, geometry: GridGeometry) -> FloatArray:
    """Edges between occupied and non-occupied cells as merged straight segments ``(S, 2, 2)``.

    Cells outside the grid count as not occupied, so the map's occupied border is closed.
    """
    occ = np.pad(np.asarray(occupied, dtype=bool), 1)
    res, (ox, oy) = geometry.resolution, geometry.origin
    segments: list[FloatArray] = []
    # Horizontal edges: between padded rows r-1 and r, i.e. at y = oy + (r-1)·res.
    h = occ[1:, 1:-1] != occ[:-1, 1:-1]  # (rows+1, cols)
    for r in np.flatnonzero(h.any(axis=1)):
        for c0, c1 in _runs(h[r]):
            y = oy + r * res
            segments.append(np.array([[ox + c0 * res, y], [ox + c1 * res, y]]))
    v = occ[1:-1, 1:] != occ[1:-1, :-1]  # (rows, cols+1)
    for c in np.flatnonzero(v.any(axis=0)):
        for r0, r1 in _runs(v[:, c]):
            x = ox + c * res
            segments.append(np.array([[x, oy + r0 * res], [x, oy + r1 * res]]))
    return np.asarray(segments, dtype=float).reshape(-1, 2, 2)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """``[start, end)`` index runs of True in a 1-D mask."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1), strict=True))


# --- loading --------------------------------------------------------------------------------


def _scenario_dir() -> Any:
    return resources.files("socialnav.sim") / "scenarios"


def builtin_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    return sorted(
        p.name.removesuffix(".yaml") for p in _scenario_dir().iterdir() if p.name.endswith(".yaml")
    )


def _format_errors(where: str, exc: ValidationError) -> str:
    lines = []
    for err in exc.errors():
        loc = ".".join(str(part) for part in err["loc"]) or "(top level)"
        lines.append(f"{where}: {loc}: {err['msg']}")
    return "\n".join(lines)


def scenario_from_dict(data: Any, where: str = "<scenario>") -> Scenario:
    """Validate a parsed YAML mapping; errors name ``where`` and the field path."""
    if not isinstance(data, dict):
        raise ConfigurationError(
            f"{where}: (top level): expected a mapping, got {type(data).__name__}"
        )
    try:
        return Scenario.model_validate(data)
    except ValidationError as exc:
        raise ConfigurationError(_format_errors(where, exc)) from None


def load_scenario(name_or_path: str | Path) -> Scenario:
    """A built-in scenario by name (see :func:`builtin_scenarios`) or a YAML file by path.

    Raises :class:`ConfigurationError` naming the file and the field path
    (``file.yaml: people.0.position.1: must be a finite number``).
    """
    text = str(name_or_path)
    path = Path(text)
    if not path.suffix and not path.exists():
        resource = _scenario_dir() / f"{text}.yaml"
        if not resource.is_file():
            from difflib import get_close_matches

            close = get_close_matches(text, builtin_scenarios(), n=1)
            hint = f" Did you mean {close[0]!r}?" if close else ""
            raise ConfigurationError(
                f"unknown scenario {text!r}.{hint} Known: {', '.join(builtin_scenarios())}."
            )
        with resources.as_file(resource) as real:
            return _load_file(Path(real))
    return _load_file(path)


# Scenario files are a few kB; anything this large is not one, and is refused before parsing
# (a YAML parser holds the whole document in memory, many times its size).
MAX_SCENARIO_BYTES = 1_000_000
# Nesting deeper than any scenario needs is refused before the parser recurses into it.
MAX_NESTING = 64


def _nesting_depth(text: str) -> int:
    """Upper bound of the flow-collection nesting (``[``/``{``) and indentation depth."""
    depth = best = 0
    for ch in text:
        if ch in "[{":
            depth += 1
            best = max(best, depth)
        elif ch in "]}":
            depth = max(depth - 1, 0)
    indent = max((len(line) - len(line.lstrip(" ")) for line in text.splitlines()), default=0)
    return max(best, indent // 2)


def _load_file(path: Path) -> Scenario:
    try:
        size = path.stat().st_size
        if size > MAX_SCENARIO_BYTES:
            raise ConfigurationError(
                f"{path}: {size} bytes is over the {MAX_SCENARIO_BYTES}-byte limit of a "
                "scenario file; not parsed"
            )
        data_bytes = path.read_bytes()
    except OSError as exc:
        raise ConfigurationError(f"{path}: cannot read: {exc.strerror or exc}") from None
    if b"\x00" in data_bytes:
        raise ConfigurationError(f"{path}: not a text file (NUL bytes): not a scenario")
    try:
        raw = data_bytes.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigurationError(
            f"{path}: not UTF-8 text (byte {exc.start}): not a scenario"
        ) from None
    if _nesting_depth(raw) > MAX_NESTING:
        raise ConfigurationError(f"{path}: nested deeper than {MAX_NESTING} levels: not a scenario")
    try:
        data = yaml.safe_load(raw)
    except yaml.YAMLError as exc:
        raise ConfigurationError(f"{path}: invalid YAML: {exc}") from None
    except RecursionError:
        raise ConfigurationError(f"{path}: YAML nested too deeply: not a scenario") from None
    return scenario_from_dict(data, str(path)).with_source(path)


def scenario_json_schema() -> dict[str, Any]:
    """JSON Schema of scenario files (for editors and ``socialnav schema``)."""
    schema = Scenario.model_json_schema()
    props = schema["properties"]
    props["family"]["enum"] = FAMILIES.names()
    kinds = structure_json_schemas()
    if kinds:
        props["structures"]["items"] = {"oneOf": kinds}
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    schema.setdefault("title", "socialnav scenario")
    return schema

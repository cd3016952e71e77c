"""Joint clearance: how far from *every* person at once a robot can stay on its way to the goal.

A per-person clearance (the widest the corridor allows from one person) says nothing about two
walkers who pass the robot at the same time on opposite sides. The joint clearance is the
bottleneck value of a space-time search: over every path of the robot centre from the start to
the goal (within ``tolerance``) through the centre's free cells, moving at most the robot's top
speed, the largest value of ``min over time and people of |robot − person|`` (centre to
centre, m), with the people on their scripted lines (:class:`~socialnav.sim.scenario.Walk`,
standing people still).

The search is generous to the robot: it turns in no time, accelerates without limit, moves
holonomically at ``hypot(max_vel_x, max_vel_y)`` in any direction (a 3×3 cell neighbourhood per
step, so diagonals are √2 faster), and is judged only at the step instants. A value below a
threshold therefore means no real robot can do better: the condition cannot be met.

Recursion (``D_t`` the distance field to the nearest person at step ``t``, ``−inf`` in
blocked cells): ``V_0 = D_0`` at the start cell, ``V_{t+1} = min(D_{t+1}, max_{3×3} V_t)``;
the answer is ``max_t max_{goal cells} V_t``. Runs until the time limit or until nobody moves
any more and ``V`` has stopped changing.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.planner.passing import lattice_commands
from socialnav.sim.scenario import PersonSpec, Scenario, Track, Walk


def scripted_positions(people: Sequence[PersonSpec], t: float) -> FloatArray:
    """Positions ``(K, 2)`` (m, world) of scripted ``people`` at time ``t`` (s): walkers at
    their speed along their line until their end point, tracks interpolated, others still."""
    out = np.zeros((len(people), 2))
    for k, p in enumerate(people):
        start = np.asarray(p.position, dtype=float)
        b = p.behavior
        if isinstance(b, Walk):
            d, speed = b.direction_speed()
            out[k] = start + d * min(speed * t, b.length(p.position))
        elif isinstance(b, Track):
            pts = np.asarray(b.points, dtype=float)
            s = float(np.clip(t / b.dt, 0.0, len(pts) - 1))
            i = min(int(s), len(pts) - 2)
            out[k] = (1.0 - (s - i)) * pts[i] + (s - i) * pts[i + 1]
        else:
            out[k] = start
    return out


def _still_after(people: Sequence[PersonSpec]) -> float:
    """Time (s) after which nobody moves (``inf`` for an endless walk)."""
    last = 0.0
    for p in people:
        b = p.behavior
        if isinstance(b, Walk):
            _, speed = b.direction_speed()
            last = max(last, b.length(p.position) / speed)
        elif isinstance(b, Track):
            last = max(last, (len(b.points) - 1) * b.dt)
    return last


def joint_clearance(
    scn: Scenario,
    robot: RobotModel,
    free: np.ndarray,
    xs: FloatArray,
    ys: FloatArray,
    tolerance: float | None = None,
    cap: float = 3.0,
) -> float:
    """The joint clearance (m, centre to centre, at most ``cap``) of ``scn`` for ``robot``.

    ``free (rows, cols)`` marks the cells the robot centre may occupy, ``xs``/``ys`` the cell
    centres (same shape, m, world, equally spaced). ``tolerance`` (m; default the scene's goal
    tolerance) is how near the goal counts as arrived. Returns ``-inf`` when no path reaches
    the goal in the time limit, ``cap`` with no people.
    """
    if not scn.people:
        return cap
    # Crop to the free cells' bounding box; work in squared distances (same order, no sqrt).
    rows, cols = np.nonzero(free)
    if rows.size == 0:
        return -math.inf
    window = np.s_[rows.min() : rows.max() + 1, cols.min() : cols.max() + 1]
    free, xs, ys = free[window], xs[window], ys[window]
    res = float(xs[0, 1] - xs[0, 0]) if xs.shape[1] > 1 else float(ys[1, 0] - ys[0, 0])
    x_axis, y_axis = xs[0, :], ys[:, 0]
    speed = math.hypot(robot.max_vel_x, robot.max_vel_y)
    dt = res / speed  # one cell per step
    tol = scn.goal_tolerance if tolerance is None else tolerance
    goal_cells = np.hypot(xs - scn.goal[0], ys - scn.goal[1]) <= max(tol, res / 2)
    goal_cells &= free
    start = np.unravel_index(np.argmin(np.hypot(xs - scn.start[0], ys - scn.start[1])), xs.shape)
    if not goal_cells.any() or not free[start]:
        return -math.inf
    blocked = ~free
    cap2 = cap * cap

    def field(t: float) -> FloatArray:
        d2 = np.full(xs.shape, cap2)
        for p in scripted_positions(scn.people, t):
            dx2 = (x_axis - p[0]) ** 2
            dy2 = (y_axis - p[1]) ** 2
            np.minimum(d2, dy2[:, None] + dx2[None, :], out=d2)
        d2[blocked] = -np.inf
        return d2

    value = np.full(xs.shape, -np.inf)
    value[start] = field(0.0)[start]
    best = float(value[goal_cells].max())
    still = _still_after(scn.people)
    steps = int(scn.time_limit / dt)
    static: FloatArray | None = None
    for k in range(1, steps + 1):
        t = k * dt
        if t > still and static is None:
            static = field(t)
        d2 = static if static is not None else field(t)
        new = np.minimum(d2, _max3x3(value))
        if static is not None and np.array_equal(new, value):
            break
        value = new
        best = max(best, float(value[goal_cells].max()))
        if best >= cap2:
            break
    return math.sqrt(best) if best >= 0 else -math.inf


def _max3x3(a: FloatArray) -> FloatArray:
    """Maximum over each cell's 3×3 neighbourhood (``-inf`` beyond the edges), ``a`` 2-D."""
    rows = a.copy()
    np.maximum(rows[1:], a[:-1], out=rows[1:])
    np.maximum(rows[:-1], a[1:], out=rows[:-1])
    out = rows.copy()
    np.maximum(out[:, 1:], rows[:, :-1], out=out[:, 1:])
    np.maximum(out[:, :-1], rows[:, 1:], out=out[:, :-1])
    return out


#: state lattice of :func:`can_avoid_collision`: command period (s), integration step (s), the
#: largest number of states kept per period, and the cell (m, rad) two states share
ESCAPE_PERIOD = 0.4
ESCAPE_STEP = 0.1
ESCAPE_STATES = 200
ESCAPE_CELL = (0.05, math.pi / 16)
PARK_MARGIN = 0.1  # m


def _parked_safely(scn: Scenario, need: FloatArray, xy: FloatArray, t: float) -> bool:
    """Whether some centre in ``xy (N, 2)`` keeps clear of every person's remaining path
    (from their position at ``t`` to their end point) by ``need (K,)`` m + :data:`PARK_MARGIN`."""
    from socialnav.core.geometry import point_segment_distance

    if not math.isfinite(_still_after(scn.people)):
        return False  # an endless walk: no end point to measure the path to
    now, end = scripted_positions(scn.people, t), scripted_positions(scn.people, math.inf)
    need = need + PARK_MARGIN
    d = point_segment_distance(xy, now, end)  # (N, K)
    return bool(np.any(np.all(d > need[None, :], axis=1)))


def _distance_raster(
    scn: Scenario, segments: FloatArray, res: float = 0.025
) -> Callable[[FloatArray], FloatArray]:
    """``f(points (..., 2)) -> (...)``: distance (m) to the nearest of ``segments (S, 2, 2)``,
    looked up on a ``res`` raster over the scene's bounds (``inf`` without segments, 0 off the
    raster)."""
    from socialnav.core.geometry import point_segment_distance

    x0, y0, x1, y1 = scn.bounds()
    xs = np.arange(x0, x1 + res, res)
    ys = np.arange(y0, y1 + res, res)
    if len(segments) == 0:
        return lambda pts: np.full(np.shape(pts)[:-1], np.inf)
    grid = np.stack(np.meshgrid(xs, ys), axis=-1)  # (rows, cols, 2)
    dist = point_segment_distance(grid, segments[:, 0], segments[:, 1]).min(axis=-1)

    def lookup(pts: FloatArray) -> FloatArray:
        col = np.round((pts[..., 0] - x0) / res).astype(int)
        row = np.round((pts[..., 1] - y0) / res).astype(int)
        inside = (row >= 0) & (row < len(ys)) & (col >= 0) & (col < len(xs))
        out = np.zeros(pts.shape[:-1])
        out[inside] = dist[row[inside], col[inside]] - res * 0.71  # a cell's half diagonal
        return out

    return lookup


class _Lattice:
    """The state lattice shared by :func:`can_avoid_collision`, :func:`can_keep_distance` and
    :func:`personal_space_path`: ``robot`` from ``scn``'s start at rest, each kept state
    branching every :data:`ESCAPE_PERIOD` s into the robot's lattice commands
    (:func:`~socialnav.planner.passing.lattice_commands`), velocities ramping toward the
    command at the acceleration limits and poses integrated every :data:`ESCAPE_STEP` s;
    a state whose footprint touches a wall or obstacle is dropped."""

    def __init__(self, scn: Scenario, robot: RobotModel) -> None:
        poly = robot.polygon
        # (E, 2) robot frame: wall contact is checked on these
        self.edges = np.concatenate(
            [
                np.linspace(a, b, 5, endpoint=False)
                for a, b in zip(poly, np.roll(poly, -1, 0), strict=True)
            ]
        )
        walls = scn.walls_array()
        obstacle_edges = [np.stack([p, np.roll(p, -1, 0)], axis=1) for p in scn.obstacle_polygons()]
        self.segments = np.concatenate([walls, *obstacle_edges]) if obstacle_edges else walls
        self.wall_distance = _distance_raster(scn, self.segments)
        self.robot = robot
        self.commands = lattice_commands(robot)
        self.acc = np.array([robot.acc_lim_x, robot.acc_lim_y, robot.acc_lim_theta]) * ESCAPE_STEP
        # state: x, y, θ, vx, vy, ω
        self.start = np.array([[scn.start[0], scn.start[1], scn.start[2], 0.0, 0.0, 0.0]])

    def period(
        self, states: FloatArray, t: float
    ) -> Iterator[tuple[FloatArray, FloatArray, FloatArray, np.ndarray, float]]:
        """Branch ``states (N, 6)`` into every command and integrate one period from ``t`` (s):
        yields ``(s, cos θ, sin θ, alive, t)`` after each step, walls checked (the arrays are
        updated in place; the caller drops more states by clearing ``alive``)."""
        s = np.repeat(states, len(self.commands), axis=0)
        cmd = np.tile(self.commands, (len(states), 1))
        alive = np.ones(len(s), dtype=bool)
        circ = self.robot.circumscribed_radius
        edges = self.edges
        for _ in range(round(ESCAPE_PERIOD / ESCAPE_STEP)):
            t += ESCAPE_STEP
            s[:, 3:] += np.clip(cmd - s[:, 3:], -self.acc, self.acc)
            c, sn = np.cos(s[:, 2]), np.sin(s[:, 2])
            s[:, 0] += (c * s[:, 3] - sn * s[:, 4]) * ESCAPE_STEP
            s[:, 1] += (sn * s[:, 3] + c * s[:, 4]) * ESCAPE_STEP
            s[:, 2] += s[:, 5] * ESCAPE_STEP
            c, sn = np.cos(s[:, 2]), np.sin(s[:, 2])
            if len(self.segments):
                near = np.flatnonzero(alive & (self.wall_distance(s[:, :2]) <= circ))
                if near.size:
                    cn, sm, sx = c[near, None], sn[near, None], s[near]
                    world = np.stack(
                        [
                            sx[:, None, 0] + cn * edges[:, 0] - sm * edges[:, 1],
                            sx[:, None, 1] + sm * edges[:, 0] + cn * edges[:, 1],
                        ],
                        axis=-1,
                    )  # (n, E, 2)
                    alive[near] &= self.wall_distance(world).min(axis=1) > 0.0
            yield s, c, sn, alive, t

    @staticmethod
    def merge(s: FloatArray) -> np.ndarray:
        """Indices of ``s (N, 6)`` with one state per lattice cell (:data:`ESCAPE_CELL`, and
        the velocity on a 0.05 grid), the first of each."""
        key = np.concatenate(
            [
                np.round(s[:, :2] / ESCAPE_CELL[0]),
                np.round(s[:, 2:3] / ESCAPE_CELL[1]),
                np.round(s[:, 3:] / 0.05),
            ],
            axis=1,
        )
        _, first = np.unique(key, axis=0, return_index=True)
        return np.asarray(first)


def can_avoid_collision(scn: Scenario, robot: RobotModel, horizon: float = 4.0) -> bool:
    """Whether some command sequence keeps ``robot``'s footprint off every person (discs on
    their scripted lines) and wall for the first ``horizon`` s from the scene's start, at rest.

    A state-lattice search with the robot model's velocity and acceleration limits
    (:class:`_Lattice`): every :data:`ESCAPE_PERIOD` s each kept state branches into
    :func:`~socialnav.planner.passing.lattice_commands`; the velocities ramp toward the command
    at the acceleration limits, poses integrate every :data:`ESCAPE_STEP` s and a state
    touching a person or a wall is dropped.
    States sharing a lattice cell (:data:`ESCAPE_CELL`, and the command) are merged; beyond
    :data:`ESCAPE_STATES` the ones farthest from people are kept. ``False`` means every
    sequence of the lattice collides: a walker who ignores the robot (the paper's people) runs
    into it whatever it does, e.g. one overtaking from right behind, faster than it can step
    aside. ``True`` as soon as a state's centre is farther than person radius + circumscribed
    radius + :data:`PARK_MARGIN` from what is left of every person's path: stopping there (the
    margin covers the stopping distance), nobody reaches it.
    """
    from socialnav.core.geometry import signed_distance_to_polygon

    poly = robot.polygon
    radii = np.array([p.radius for p in scn.people])
    circ = robot.circumscribed_radius

    def gap(s: FloatArray, c: FloatArray, sn: FloatArray, people: FloatArray) -> FloatArray:
        rel = people[None, :, :] - s[:, None, :2]  # (N, K, 2)
        # centre distance minus the circumscribed radius bounds the footprint's gap from
        # below: only the states that could touch someone get the exact polygon check
        out = np.hypot(rel[..., 0], rel[..., 1]) - circ - radii[None, :]
        close = np.flatnonzero((out <= 0.0).any(axis=1))
        if close.size:
            cc, ss, rr = c[close, None], sn[close, None], rel[close]
            local = np.stack(
                [cc * rr[..., 0] + ss * rr[..., 1], -ss * rr[..., 0] + cc * rr[..., 1]],
                axis=-1,
            )  # world → robot frame
            out[close] = signed_distance_to_polygon(local, poly) - radii[None, :]
        return np.asarray(out.min(axis=1))

    return _survives(scn, robot, horizon, gap, radii + circ)


def _nearest(states: FloatArray, people: FloatArray) -> FloatArray:
    """``(N,)`` distance (m) from each state's centre (``states (N, 6)``) to the nearest of
    ``people (K, 2)``, ``K >= 1``."""
    rel = people[None] - states[:, None, :2]  # (N, K, 2)
    return np.asarray(np.hypot(rel[..., 0], rel[..., 1]).min(axis=1))


def can_keep_distance(
    scn: Scenario, robot: RobotModel, distance: float = 1.2, horizon: float = 4.0
) -> bool:
    """Whether some command sequence keeps ``robot``'s centre at least ``distance`` m from
    every person's centre (on their scripted lines), and its footprint off every wall, for the
    first ``horizon`` s from the scene's start, at rest.

    :func:`can_avoid_collision`'s lattice and rule with the personal distance in place of
    contact: ``False`` means every sequence of the lattice comes closer, e.g. a fast walker
    closing from just behind, before a differential drive can turn and step aside; ``True``
    as soon as a state keeps ``distance`` + :data:`PARK_MARGIN` from what is left of every
    person's path. The joint clearance (:func:`joint_clearance`) cannot see this: it lets the
    robot move in any direction at once.
    """

    def gap(s: FloatArray, c: FloatArray, sn: FloatArray, people: FloatArray) -> FloatArray:
        return _nearest(s, people) - distance

    return _survives(scn, robot, horizon, gap, np.full(len(scn.people), distance))


def _survives(
    scn: Scenario,
    robot: RobotModel,
    horizon: float,
    gap: Callable[[FloatArray, FloatArray, FloatArray, FloatArray], FloatArray],
    need: FloatArray,
) -> bool:
    """The search of :func:`can_avoid_collision` and :func:`can_keep_distance`: whether some
    lattice state keeps ``gap(s, cos θ, sin θ, people (K, 2)) -> (N,)`` above 0 at every step
    until ``horizon`` s, or reaches a place ``need (K,)`` m + :data:`PARK_MARGIN` clear of
    every person's remaining path. States sharing a lattice cell are merged; beyond
    :data:`ESCAPE_STATES` the ones with the largest smallest gap are kept."""
    if not scn.people:
        return True
    lattice = _Lattice(scn, robot)
    states = lattice.start
    t = 0.0
    while t < horizon - 1e-9:
        margin = np.full(len(states) * len(lattice.commands), np.inf)
        for s, c, sn, alive, now in lattice.period(states, t):
            closest = gap(s, c, sn, scripted_positions(scn.people, now))
            margin = np.minimum(margin, closest)
            alive &= closest > 0.0
        t = now
        s, margin = s[alive], margin[alive]
        if len(s) == 0:
            return False
        if _parked_safely(scn, need, s[:, :2], t):
            return True
        first = lattice.merge(s)
        s, margin = s[first], margin[first]
        if len(s) > ESCAPE_STATES:
            s = s[np.argsort(-margin)[:ESCAPE_STATES]]
        states = s
    return True


#: :func:`personal_space_path`: states kept per period, and the coarse cell (m, rad) of which
#: each keeps its state nearest the goal before the rest fill up by progress (the beam must
#: keep waiting beside a wall alive next to driving on)
PATH_STATES = 4000
PATH_CELL = (0.4, math.pi / 4)


def personal_space_path(
    scn: Scenario,
    robot: RobotModel,
    distance: float = 1.2,
    tolerance: float = 0.3,
    max_states: int = PATH_STATES,
) -> tuple[bool, float]:
    """Whether some command sequence within ``robot``'s limits takes it from the scene's start
    (at rest) to within ``tolerance`` m of the goal (any heading) in the time limit while the
    robot's centre stays at least ``distance`` m from every person's centre (people on their
    scripted lines) and its footprint off every wall; also that path's smallest distance (m;
    ``inf`` without people, ``nan`` when no path is found).

    The state lattice of :func:`can_avoid_collision` (:class:`_Lattice`), run to the goal: a
    beam of ``max_states`` states per period, merged per lattice cell, with one state per
    :data:`PATH_CELL` cell (the one nearest the goal) kept first and the rest by distance to
    the goal. ``True`` is constructive: the lattice's command sequence is one this robot can
    drive. ``False`` only means the lattice found none: unlike :func:`joint_clearance` (a
    bound that is generous to the robot), it proves nothing. Raises ``ValueError`` when
    ``distance`` is below a person's radius + the robot's circumscribed radius (the centre
    distance must rule out contact).
    """
    lattice = _Lattice(scn, robot)
    radii = np.array([p.radius for p in scn.people])
    if len(radii) and distance < float(radii.max()) + robot.circumscribed_radius:
        raise ValueError(
            f"distance {distance} m is below a person's radius + the robot's circumscribed "
            f"radius ({float(radii.max()) + robot.circumscribed_radius:.3f} m)"
        )
    goal = np.asarray(scn.goal[:2], dtype=float)
    states = lattice.start
    closest = np.array([np.inf])
    t = 0.0
    while t < scn.time_limit - 1e-9:
        lowest = np.repeat(closest, len(lattice.commands))
        for s, _, _, alive, now in lattice.period(states, t):
            if scn.people:
                d = _nearest(s, scripted_positions(scn.people, now))
                lowest = np.minimum(lowest, d)
                alive &= d >= distance
            arrived = alive & (np.hypot(*(s[:, :2] - goal).T) <= tolerance)
            if arrived.any():
                return True, float(lowest[arrived].max())
        t = now
        s, lowest = s[alive], lowest[alive]
        if len(s) == 0:
            return False, math.nan
        to_goal = np.hypot(*(s[:, :2] - goal).T)
        keep = lattice.merge(s)
        keep = keep[np.argsort(to_goal[keep], kind="stable")]
        if len(keep) > max_states:
            coarse = np.concatenate(
                [np.round(s[keep, :2] / PATH_CELL[0]), np.round(s[keep, 2:3] / PATH_CELL[1])],
                axis=1,
            )
            _, first = np.unique(coarse, axis=0, return_index=True)
            spread = keep[np.sort(first)]
            rest = keep[~np.isin(keep, spread)]
            keep = np.concatenate([spread, rest])[: max(max_states, len(spread))]
        states, closest = s[keep], lowest[keep]
    return False, math.nan

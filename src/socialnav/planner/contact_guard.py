"""Contact guard: the command a control cycle sends never pushes the footprint into a person.

Francis et al. 2023 (and ``socialnav.metrics.crowd``) call a contact *active* when the robot's
own motion — translation and turning, the person held where they are — closes its footprint
on the person faster than a small speed. The local planner's approach rule
(``InterpersonalCritic.approach_footprint``) keeps that out of the trajectories it selects, but
not every command comes from a selection: a zero command of ``WAITING`` or ``STUCK`` and an
evasive step are brought into the acceleration window by
:func:`~socialnav.planner.limits.enforce_limits`, and a robot turning at 0.7 rad/s still turns
at 0.36 rad/s one cycle later, sweeping a corner into the walker who has just reached it
(recorded crowds: every active contact of ``paccet`` on development seeds 0–89 and reporting
seeds 10,000–10,049 was such a step).

:func:`guard_contact` checks the limited command against every person within reach as the
start of a stop: the command for one control period ``T``, then the full brake (every axis
toward zero at its ``acc_lim_*``) until the robot stands, one Euler step per period (as the
simulator integrates and the crowd metric samples), people at constant velocity. At every
step of that sequence:

- a person *in contact after the step* (footprint–disc gap below ``contact_tolerance`` at
  their forecast) may not be approached during it: the signed distance from the footprint to
  their centre, held at that forecast, may not fall faster than ``approach_speed``;
- a person *in contact before the step* may not be approached from there: the same test with
  them held at the step's start.

The brake is part of the test because a command is only as safe as the stop that can follow
it: a Pioneer turning at 1 rad/s needs three more cycles to stop turning (3 rad/s²), and a
guard that only looked one step ahead let it turn on until no reachable command avoided the
person touching it (recorded crowd eth_hotel, Pioneer, dev seed 26). With the stop included
the robot can always come to rest without pushing anyone it touches, when such a stop exists
(*passive safety*: if contact happens, the robot is not the one moving into it; Macek et al.
2009, Bouraine et al. 2012).

When the command fails the test, the guard sends the reachable command nearest to it that
passes: the alternatives are a grid of ``grid`` values per velocity axis over the acceleration
window (:func:`~socialnav.planner.limits.enforce_limits`'s, inside the velocity box), the
unchanged command and the plain brake, each judged as executed (a holonomic base's
translational speed capped at ``max_speed``), nearness measured per axis in units of the
window. When none passes, the one whose worst approach is slowest (among those within
0.1 mm/s of it, the nearest), except when it is only people who were not in view the cycle
before (``appeared``: a new track, or one back after dropping out, as people appear in
recorded crowds; an id reused for someone else is not new) that make every command fail —
some command closes on none of the others: then the plain brake, every axis toward zero at
its limit. A constant-velocity forecast of someone just seen is the least reliable one, and
braking at the limits is what passive safety asks once someone is seen and what the crowd
metric does not hold against the robot (``socialnav.metrics.crowd.braking_after``); the
slowest forecast approach kept a PR2 turning at 1 rad/s one more period beside someone who had
just appeared, and its next turn swept a corner into them (recorded crowds, dev eth_hotel 34).
With the static ``costmap``, a command whose stop puts the
footprint's outline on a LETHAL cell it is not on now is never chosen (the incoming command
included, once it has failed; cells it covers now do not count), unless every command's stop
does; then the people decide. A command that passes the people test is not checked against
walls (the local planner's occupancy critic chose it).
The chosen command keeps the result's status; the message says the guard acted. Nothing
changes when the command passes, so away from people the guard costs one distance test per
cycle (about 40–60 µs after the limits' 20 µs; ``benchmarks/bench_contact_guard.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from numbers import Integral

import numpy as np
from numpy.typing import NDArray

from socialnav.core.errors import ConfigurationError, is_non_negative_number
from socialnav.core.geometry import (
    FloatArray,
    points_in_polygon,
    signed_distance_to_polygon,
    world_to_body_frames,
)
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.critics.occupancy import footprint_outline
from socialnav.planner.limits import acceleration_limits, acceleration_window
from socialnav.world.grid import LETHAL, Costmap

#: the most braking steps a stop is followed for (5 s at 0.1 s; a robot within its limits
#: stops in under 1 s)
MAX_BRAKING_STEPS = 50
#: the largest ``ContactGuardParams.grid`` (15³ = 3375 commands for a holonomic base: ~60 ms)
MAX_GRID = 15


@dataclass(frozen=True)
class ContactGuardParams:
    """``approach_speed`` (m/s): the fastest the footprint may close on a person in contact
    (below the crowd metric's 0.05 m/s, as the local planner's approach rule);
    ``contact_tolerance`` (m): a footprint–disc gap below this counts as contact (the forecast
    of where someone will be one period later is off by their acceleration); ``grid``: values
    per velocity axis over the acceleration window (odd, so the window's centre is one; at
    most ``MAX_GRID``: a holonomic base checks ``grid³`` commands, 343 at 7, about 9 ms with
    the wall check)."""

    approach_speed: float = 0.02
    contact_tolerance: float = 0.05
    grid: int = 7

    def __post_init__(self) -> None:
        for name in ("approach_speed", "contact_tolerance"):
            if not is_non_negative_number(getattr(self, name)):
                raise ConfigurationError(
                    f"contact guard: {name} must be a finite number >= 0, got "
                    f"{getattr(self, name)!r}"
                )
        grid = self.grid
        if not (isinstance(grid, Integral) and 3 <= grid <= MAX_GRID and grid % 2 == 1):
            raise ConfigurationError(
                f"contact guard: grid must be an odd int in [3, {MAX_GRID}], got {grid!r}"
            )


def braking_twists(twists: FloatArray, robot: RobotModel, period: float) -> FloatArray:
    """``(N, H, 3)``: each of ``twists (N, 3)`` (body, m/s and rad/s, as executed) for one
    ``period`` s, then the full brake (every axis toward zero at its ``acc_lim_*``) until all
    have stopped; ``H - 1`` braking steps, as many as the slowest-stopping twist needs (at most
    ``MAX_BRAKING_STEPS``: a twist far beyond the limits, or a tiny period, is not followed to
    a stop)."""
    acc = acceleration_limits(robot) * period
    need = np.where(acc > 0, np.abs(twists) / np.where(acc > 0, acc, 1.0), 0.0)
    steps = min(int(np.ceil(need.max(initial=0.0) - 1e-9)), MAX_BRAKING_STEPS)
    out = np.empty((twists.shape[0], steps + 1, 3))
    out[:, 0] = twists
    for j in range(1, steps + 1):
        out[:, j] = np.clip(0.0, out[:, j - 1] - acc, out[:, j - 1] + acc)
    return out


def sequence_poses(pose: FloatArray, twists: FloatArray, period: float) -> FloatArray:
    """``(N, H + 1, 3)`` poses (m, rad, world frame) from ``pose (3,)`` under the body-twist
    sequences ``twists (N, H, 3)``, one Euler step of ``period`` s each (translation along the
    heading at the step's start, as the simulator integrates and the crowd metric samples)."""
    n, h = twists.shape[:2]
    out = np.empty((n, h + 1, 3))
    out[:, 0] = pose
    for j in range(h):
        c, s = np.cos(out[:, j, 2]), np.sin(out[:, j, 2])
        vx, vy, w = twists[:, j, 0], twists[:, j, 1], twists[:, j, 2]
        out[:, j + 1, 0] = out[:, j, 0] + (c * vx - s * vy) * period
        out[:, j + 1, 1] = out[:, j, 1] + (s * vx + c * vy) * period
        out[:, j + 1, 2] = out[:, j, 2] + w * period
    return out


def stop_poses(
    pose: FloatArray, twists: FloatArray, robot: RobotModel, period: float
) -> FloatArray:
    """``(N, H + 1, 3)``: the poses of each of ``twists (N, 3)`` followed by the full brake
    (:func:`braking_twists`, :func:`sequence_poses`), starting at ``pose (3,)``."""
    return sequence_poses(pose, braking_twists(twists, robot, period), period)


def approach_speeds(
    poses: FloatArray,
    robot: RobotModel,
    positions: FloatArray,
    velocities: FloatArray,
    radii: FloatArray,
    period: float,
    contact_tolerance: float,
) -> FloatArray:
    """``(N,)`` the fastest (m/s) the footprint closes on a person it touches along each of the
    pose sequences ``poses (N, H + 1, 3)`` (m, rad, world frame; one ``period`` s apart, e.g. a
    command and its stop, :func:`stop_poses`), by the two tests of the module docstring at
    every step; people ``positions``/``velocities (K, 2)`` (m, m/s, world frame, forecast at
    constant velocity), ``radii (K,)`` m. ``-inf`` when it touches nobody. Raises nothing on
    finite input."""
    h = poses.shape[1] - 1
    t = np.arange(h + 1) * period
    people = (positions[None] + t[:, None, None] * velocities[None])[None]  # (1, H+1, K, 2)
    polygon = robot.polygon

    def sd(at: FloatArray, points: FloatArray) -> FloatArray:
        return signed_distance_to_polygon(world_to_body_frames(points, at), polygon)

    same = sd(poses, people)  # (N, H+1, K): pose j, people at sample j
    ahead = sd(poses[:, :-1], people[:, 1:])  # pose j, people at sample j + 1
    behind = sd(poses[:, 1:], people[:, :-1])  # pose j + 1, people at sample j
    touch = same < radii + contact_tolerance
    # the step from sample j to j + 1: into someone touching at j + 1, out of the contact of
    # sample j, each with the person held at that sample's forecast
    into = np.where(touch[:, 1:], (ahead - same[:, 1:]) / period, -np.inf)
    out = np.where(touch[:, :-1], (same[:, :-1] - behind) / period, -np.inf)
    worst: FloatArray = (
        np.maximum(into, out).reshape(poses.shape[0], -1).max(axis=1, initial=-np.inf)
    )
    return worst


def _passes_without(
    fresh: NDArray[np.bool_],
    stops: FloatArray,
    wall: NDArray[np.bool_],
    params: ContactGuardParams,
    worst_of: Callable[[FloatArray, NDArray[np.bool_]], FloatArray],
) -> bool:
    """Whether some stop of ``stops`` off the walls closes on none of the people *not*
    ``fresh (K,)`` (``worst_of(stops, who)`` judges them against the people ``who``): then
    only the people who just appeared make every command fail."""
    return bool(fresh.all()) or bool(
        np.any((worst_of(stops, ~fresh) <= params.approach_speed) & ~wall)
    )


def _alternatives(
    cmd: FloatArray, velocity: FloatArray, robot: RobotModel, period: float, grid: int
) -> FloatArray:
    """``(M, 3)``: the command, the brake, then a grid over the acceleration window."""
    w_lo, w_hi = acceleration_window(velocity, robot, period)
    axes = [np.linspace(w_lo[i], w_hi[i], grid) for i in range(3)]
    if not robot.holonomic:
        axes[1] = np.zeros(1)
    mesh = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    brake = np.clip(np.zeros(3), w_lo, w_hi)
    return np.vstack([cmd[None], brake[None], mesh])


def executed(twists: FloatArray, robot: RobotModel) -> FloatArray:
    """``twists (N, 3)`` as a holonomic base executes them: the translational speed capped at
    ``max_speed`` (``RobotModel.max_speed``; the velocity box bounds each axis only)."""
    if not robot.holonomic:
        return twists
    speed = np.hypot(twists[:, 0], twists[:, 1])
    out = twists.copy()
    out[:, :2] *= np.minimum(1.0, robot.max_speed / np.maximum(speed, 1e-12))[:, None]
    return out


def footprint_cells(
    costmap: Costmap, poses: FloatArray, robot: RobotModel
) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """``(flat cell indices (N, P), on the map (N, P))`` of the footprint's outline, sampled at
    the map's resolution, at each of ``poses (N, 3)`` (m, rad, world frame)."""
    geo = costmap.geometry
    outline = footprint_outline(robot.polygon, geo.resolution)  # (P, 2) body frame
    c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    x = poses[:, 0:1] + c * outline[:, 0] - s * outline[:, 1]
    y = poses[:, 1:2] + s * outline[:, 0] + c * outline[:, 1]
    cells = geo.world_to_cell(np.stack([x, y], axis=-1))
    inside = geo.in_bounds(cells)
    flat = np.where(inside, cells[..., 0] * geo.shape[1] + cells[..., 1], 0)
    return flat, inside


def cells_under(costmap: Costmap, pose: FloatArray, robot: RobotModel) -> NDArray[np.intp]:
    """Flat indices of the LETHAL cells the footprint at ``pose (3,)`` is on now: those its
    outline (sampled at the map's resolution) lies on and those whose centre it covers."""
    geo = costmap.geometry
    flat, inside = footprint_cells(costmap, pose[None], robot)
    lethal = costmap.costs.reshape(-1) >= LETHAL
    edge = flat[inside & lethal[flat]]
    r = robot.circumscribed_radius
    lo = geo.world_to_cell(pose[:2] - r)
    hi = geo.world_to_cell(pose[:2] + r)
    rows = np.arange(max(lo[0], 0), min(hi[0] + 1, geo.shape[0]))
    cols = np.arange(max(lo[1], 0), min(hi[1] + 1, geo.shape[1]))
    rr, cc = np.meshgrid(rows, cols, indexing="ij")
    box = (rr * geo.shape[1] + cc).reshape(-1)
    box = box[lethal[box]]
    if box.size:
        centres = geo.cell_to_world(np.column_stack([box // geo.shape[1], box % geo.shape[1]]))
        body = world_to_body_frames(centres, pose)
        box = box[points_in_polygon(body, robot.polygon)]
    return np.unique(np.concatenate([edge, box]))


def footprint_on_lethal(
    costmap: Costmap | None,
    poses: FloatArray,
    robot: RobotModel,
    allowed: NDArray[np.intp] | None = None,
) -> NDArray[np.bool_]:
    """``(N,)`` whether the footprint's outline at each pose ``(N, 3)`` lies on a LETHAL cell of
    ``costmap`` other than the flat cell indices ``allowed`` (off-map points do not count)."""
    if costmap is None:
        return np.zeros(poses.shape[0], dtype=bool)
    flat, inside = footprint_cells(costmap, poses, robot)
    hit = inside & (costmap.costs.reshape(-1)[flat] >= LETHAL)
    if allowed is not None and allowed.size:
        hit &= ~np.isin(flat, allowed)
    return np.asarray(hit.any(axis=1))


def guard_contact(
    cmd: FloatArray,
    pose: FloatArray,
    velocity: FloatArray,
    robot: RobotModel,
    social: SocialContext,
    period: float,
    params: ContactGuardParams | None = None,
    costmap: Costmap | None = None,
    appeared: frozenset[int] = frozenset(),
) -> tuple[FloatArray, float]:
    """``(command (3,), its approach speed m/s)``: ``cmd`` (a body twist already within
    :func:`~socialnav.planner.limits.enforce_limits`'s window around the measured body twist
    ``velocity (3,)``, m/s and rad/s) when it and its stop close on nobody it touches, else the
    reachable alternative of the module docstring. ``pose (3,)`` world ``(x, y, yaw)`` (m,
    rad); ``social``: the people in view (world frame); ``period`` (s): the control period;
    ``costmap``: the static map whose LETHAL cells no chosen stop may newly touch;
    ``appeared``: the ids of the people not in view the cycle before (when no command passes
    but one passes against everyone else, the plain brake is sent). The approach speed is
    ``-inf`` when nobody is touched. Never raises on ``(3,)`` numeric input: a
    non-finite ``cmd``, ``velocity`` or ``pose``, or a ``period`` that is not positive,
    returns ``cmd`` as it is with ``-inf`` (there is nothing it can judge); a stop is followed
    for at most ``MAX_BRAKING_STEPS`` periods."""
    p = params or ContactGuardParams()
    c = np.asarray(cmd, dtype=float).reshape(3)
    v = np.asarray(velocity, dtype=float).reshape(3)
    q = np.asarray(pose, dtype=float).reshape(3)
    finite = math.isfinite(float(c.sum() + v.sum() + q.sum()))  # one test for nine values
    if not social.people or not finite or not (np.isfinite(period) and period > 0):
        return cmd, -np.inf  # nothing to check against, or nothing to check with
    positions, velocities, radii = social.positions(), social.velocities(), social.radii()
    # Only people the footprint can touch before it has stopped (either side at full speed).
    speed = np.hypot(velocities[:, 0], velocities[:, 1])
    acc = acceleration_limits(robot)
    stop = period + float(np.max(np.abs(v) / np.where(acc > 0, acc, np.inf))) + period
    reach = (robot.max_speed + speed) * stop + p.contact_tolerance + radii
    near = np.hypot(*(positions - q[:2]).T) <= robot.circumscribed_radius + reach
    near &= np.all(np.isfinite(positions), axis=1) & np.all(np.isfinite(velocities), axis=1)
    if not near.any():
        return cmd, -np.inf
    fresh = np.array([social.people[i].id in appeared for i in np.flatnonzero(near)], dtype=bool)
    positions, velocities, radii = positions[near], velocities[near], radii[near]

    def worst_of(stops: FloatArray, who: NDArray[np.bool_] | None = None) -> FloatArray:
        at = slice(None) if who is None else who
        return approach_speeds(
            stops, robot, positions[at], velocities[at], radii[at], period, p.contact_tolerance
        )

    first = worst_of(stop_poses(q, executed(c[None], robot), robot, period))
    if first[0] <= p.approach_speed:
        return cmd, float(first[0])
    twists = _alternatives(c, v, robot, period, p.grid)
    stops = stop_poses(q, executed(twists, robot), robot, period)  # (N, H + 1, 3)
    worst = worst_of(stops)
    # Walls: no pose of the stop on a LETHAL cell the footprint is not on now.
    wall: NDArray[np.bool_] = np.zeros(twists.shape[0], dtype=bool)
    if costmap is not None:
        n, h = stops.shape[0], stops.shape[1] - 1
        now = cells_under(costmap, q, robot)
        hits = footprint_on_lethal(costmap, stops[:, 1:].reshape(-1, 3), robot, now)
        wall = np.asarray(hits.reshape(n, h).any(axis=1))
        if wall.all():
            wall[:] = False  # every stop meets a wall: the people decide
    dist = np.linalg.norm((twists - c) / np.maximum(2.0 * acc * period, 1e-9), axis=1)
    ok = (worst <= p.approach_speed) & ~wall
    if ok.any():
        k = int(np.argmin(np.where(ok, dist, np.inf)))
    elif fresh.any() and not wall[1] and _passes_without(fresh, stops, wall, p, worst_of):
        k = 1  # only someone who just appeared is closed on: brake at the limits (docstring)
    else:  # the slowest approach off the walls; among near-ties (0.1 mm/s), the nearest
        best = float(np.min(np.where(wall, np.inf, worst)))
        k = int(np.argmin(np.where(~wall & (worst <= best + 1e-4), dist, np.inf)))
    return twists[k].copy(), float(worst[k])

"""Timed passing: a short space-time search for a way past walkers that keeps personal space.

A reactive local planner sees a walker's closest approach only inside its rollout, too late for
a differential drive to turn and leave the walker's lane, and it cannot time a pass (wait beside
one wall until a walker has gone by, then cross). This search looks ``horizon`` s ahead over
command *sequences*: from the robot's pose and twist, each kept state branches every
``period`` s into the robot's commands (:func:`lattice_commands`), velocities ramp toward the
command at the acceleration limits and poses integrate every ``step`` s; people are forecast at
constant velocity, and a state whose centre comes nearer than ``distance`` to anyone (nearer
than they are now, for someone already inside it) is dropped, as is one the static check
rejects. States sharing a lattice cell are merged; a beam of ``beam`` states, one per coarse
cell first, then by the plan length still to go, carries on. Of the sequences that survive the
horizon and end where the robot can stop untouched by anyone walking on (``contact``, for
``hold`` s), the answer is the one with the least plan still to go at the horizon, each metre
its closest approach falls short of ``comfort`` (the paper's 1.5 m ID threshold) counting as
``clearance_weight`` m of plan: where the corridor allows, the robot passes wider than the
hard ``distance``. The control loop commands its first twist and searches again every
period, following the plan in between while it holds (:func:`follow_plan`; receding horizon).

Reference: time-dependent planning over forecast people, Kollmitz et al., "Time Dependent
Planning on a Layered Social Cost Map for Human-Aware Robot Navigation", ECMR 2015; state
lattices with kinodynamic limits, Pivtoraiko and Kelly 2005.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.planner import kernels
from socialnav.planner.limits import acceleration_limits


@dataclass(frozen=True)
class PassingParams:
    """Search parameters: ``distance`` (m, centre to centre), ``horizon``, ``period`` and
    ``step`` (s), ``beam`` (states kept per period), ``cell`` (m, rad: merge cell),
    ``coarse`` (m, rad: the cell of which each keeps its best state first, within the beam),
    ``hold`` (s: how long people are followed past the horizon for a safe stop), ``comfort``
    (m) and ``clearance_weight`` (m of plan per m of clearance short of ``comfort``) of the
    final choice. Raises ``ValueError`` on a non-positive or non-finite value."""

    distance: float = 1.2
    horizon: float = 6.0
    period: float = 0.5
    step: float = 0.1
    beam: int = 60
    cell: tuple[float, float] = (0.05, math.pi / 16)
    coarse: tuple[float, float] = (0.3, math.pi / 4)
    hold: float = 8.0
    comfort: float = 1.5
    clearance_weight: float = 10.0

    def __post_init__(self) -> None:
        positive = ("distance", "horizon", "period", "step", *_pair("cell"), *_pair("coarse"))
        nonnegative = ("hold", "comfort", "clearance_weight")
        bad = [n for n in positive if not (_finite(self, n) and _value(self, n) > 0)]
        bad += [n for n in nonnegative if not (_finite(self, n) and _value(self, n) >= 0)]
        if not isinstance(self.beam, int) or isinstance(self.beam, bool) or self.beam < 1:
            bad.append("beam")
        if bad:
            raise ValueError(
                f"passing parameters: {', '.join(bad)} out of range (distance, horizon, period, "
                f"step, cell and coarse positive; hold, comfort and clearance_weight >= 0; all "
                f"finite; beam an integer >= 1), got {self}"
            )
        if self.step > self.period:
            raise ValueError(
                f"passing parameters: step {self.step} s exceeds period {self.period} s"
            )


def _pair(name: str) -> tuple[str, str]:
    return f"{name}[0]", f"{name}[1]"


def _value(params: PassingParams, name: str) -> float:
    """A field of ``params`` by name, ``"cell[1]"`` for an element of a pair."""
    if name.endswith("]"):
        field, index = name[:-1].split("[")
        return float(getattr(params, field)[int(index)])
    return float(getattr(params, name))


def _finite(params: PassingParams, name: str) -> bool:
    try:
        return math.isfinite(_value(params, name))
    except (TypeError, ValueError, IndexError):
        return False


def _checked(
    pose: FloatArray, twist: FloatArray, people: FloatArray, people_velocities: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The inputs of :func:`timed_pass` as float arrays; ``ValueError`` naming the argument
    when a shape is wrong or a value is not finite."""
    pose = np.asarray(pose, dtype=float)
    twist = np.asarray(twist, dtype=float)
    people = np.asarray(people, dtype=float).reshape(-1, 2)
    vel = np.asarray(people_velocities, dtype=float).reshape(-1, 2)
    for name, a, shape in (("pose", pose, (3,)), ("twist", twist, (3,))):
        if a.shape != shape:
            raise ValueError(f"timed_pass: {name} must have shape {shape}, got {a.shape}")
    if people.shape != vel.shape:
        raise ValueError(
            f"timed_pass: people {people.shape} and people_velocities {vel.shape} differ"
        )
    for name, a in (
        ("pose", pose),
        ("twist", twist),
        ("people", people),
        ("people_velocities", vel),
    ):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"timed_pass: {name} has a non-finite value")
    return pose, twist, people, vel


@dataclass(frozen=True)
class PassingPlan:
    """The search's answer: ``command (3,)`` body twist for the next period, ``commands (P, 3)``
    the whole sequence, ``poses (P, 3)`` the pose at the end of each period, ``closest`` (m)
    the smallest centre distance to anyone along it and ``to_go`` (m) at its end."""

    command: FloatArray
    commands: FloatArray
    poses: FloatArray
    closest: float
    to_go: float


def lattice_commands(robot: RobotModel) -> FloatArray:
    """Command set ``(C, 3)`` ``(vx, vy, ω)`` (body frame): each velocity limit and zero, and
    half the forward speed and turn rate for a differential drive."""
    w = robot.max_vel_theta
    if robot.holonomic:
        vx = [robot.min_vel_x, 0.0, robot.max_vel_x]
        vy = [-robot.max_vel_y, 0.0, robot.max_vel_y]
        wz = [-w, 0.0, w]
    else:
        vx = [robot.min_vel_x, 0.0, robot.max_vel_x / 2, robot.max_vel_x]
        vy = [0.0]
        wz = [-w, -w / 2, 0.0, w / 2, w]
    grid = np.stack(np.meshgrid(vx, vy, wz, indexing="ij"), axis=-1).reshape(-1, 3)
    return np.unique(grid, axis=0)


def timed_pass(
    pose: FloatArray,
    twist: FloatArray,
    robot: RobotModel,
    people: FloatArray,
    people_velocities: FloatArray,
    to_go: Callable[[FloatArray], FloatArray],
    static_ok: Callable[[FloatArray, FloatArray, FloatArray], np.ndarray],
    params: PassingParams | None = None,
    contact: FloatArray | None = None,
) -> PassingPlan | None:
    """Search (module docstring) from ``pose (3,)`` world and ``twist (3,)`` body; ``people
    (K, 2)`` m and ``people_velocities (K, 2)`` m/s world frame; ``to_go(xy (N, 2)) -> (N,)``
    the plan length (m) still to go; ``static_ok(commands (N, 3), poses (N, S, 3), t (S,)) ->
    (N,) bool`` the static check of one period's poses (column 0 is the period's start);
    ``contact (K,)`` m: the centre distance at which each person would touch the robot
    standing still (person radius + circumscribed radius + a margin) — without it the final
    safe-stop check is skipped.

    Returns ``None`` when no sequence survives the horizon: every one comes nearer than the
    distance to someone, or fails the static check, or ends where someone walking on would
    touch the robot stopped there. Raises ``ValueError`` on a wrong shape or a non-finite
    input (naming the argument)."""
    p = params or PassingParams()
    pose, twist, people, vel = _checked(pose, twist, people, people_velocities)
    commands = lattice_commands(robot)
    acc, need, states = _start(pose, twist, robot, people, p)
    first = v1 = np.zeros((1, 3))
    history: list[FloatArray] = []  # per period: (parent index (N,), command (N, 3), pose)
    closest = np.full(1, np.inf)
    substeps = max(1, round(p.period / p.step))
    t = 0.0
    while t < p.horizon - 1e-9:
        n = len(states)
        times = np.empty(substeps + 1)
        times[0] = t
        for k in range(substeps):
            t += p.step
            times[k + 1] = t
        s, poses, alive, low = _period()(
            states, commands, acc, p.step, times, people, vel, need, closest
        )
        cmd = np.tile(commands, (n, 1))
        parent = np.repeat(np.arange(n), len(commands))
        if not history:
            v1 = _first_step_velocity(states[0], commands, acc)
        keep = np.flatnonzero(alive)
        if keep.size == 0:
            return None
        keep = keep[_merge(s[keep], p.cell)]
        # the beam's order is the final choice's score (below) so far
        go = to_go(s[keep, :2]) + p.clearance_weight * np.maximum(p.comfort - low[keep], 0.0)
        order = np.argsort(go, kind="stable")
        keep = keep[order]
        # beam order: each coarse cell's best state first, then the rest by score (waiting
        # beside a wall stays alive next to driving on)
        coarse = np.concatenate(
            [np.round(s[keep, :2] / p.coarse[0]), np.round(s[keep, 2:3] / p.coarse[1])], axis=1
        )
        spread = _first_per_key(coarse)
        later = np.ones(keep.size, dtype=bool)
        later[spread] = False
        rest = np.flatnonzero(later)
        keep = keep[np.concatenate([spread, rest])[: 2 * p.beam]]
        # the static check (the costlier test) only on the beam's candidates
        keep = keep[static_ok(cmd[keep], poses[keep], times)][: p.beam]
        if keep.size == 0:
            return None
        first = v1[keep] if not history else first[parent[keep]]
        history.append(np.column_stack([parent[keep], cmd[keep], s[keep, :3]]))
        states, closest = s[keep], low[keep]
    safe = _safe_to_stop(states, t, people, vel, contact, p)
    if not safe.any():
        return None
    states, closest, first = states[safe], closest[safe], first[safe]
    history[-1] = history[-1][safe]
    # the least plan still to go, each metre of clearance short of ``comfort`` counting as
    # ``clearance_weight`` m of it (the paper's ID objective is zero beyond 1.5 m)
    end = to_go(states[:, :2])
    best = int(np.argmin(end + p.clearance_weight * np.maximum(p.comfort - closest, 0.0)))
    # walk the parents back for the whole sequence
    rows = []
    i = best
    for h in reversed(history):
        rows.append(h[i])
        i = int(h[i, 0])
    rows.reverse()
    seq = np.array(rows)
    return PassingPlan(
        command=first[best].copy(),
        commands=seq[:, 1:4],
        poses=seq[:, 4:7],
        closest=float(closest[best]),
        to_go=float(end[best]),
    )


def _start(
    pose: FloatArray, twist: FloatArray, robot: RobotModel, people: FloatArray, p: PassingParams
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """What both searches start from: the twist change per step ``(3,)``, the distance each
    person must keep ``(K,)`` (someone already inside it: no nearer than now) and the state
    ``(1, 6)``."""
    acc = acceleration_limits(robot) * p.step
    now = np.hypot(*(people - pose[:2]).T) if len(people) else np.zeros(0)
    need = np.minimum(p.distance, now - 1e-6)
    return acc, need, np.concatenate([pose, twist])[None].astype(float)


def _period() -> Callable[..., tuple[FloatArray, FloatArray, np.ndarray, FloatArray]]:
    """One lattice period: the compiled kernel or its NumPy reference."""
    return kernels.lattice_period if kernels.enabled() else lattice_period_reference


def _safe_to_stop(
    states: FloatArray,
    t: float,
    people: FloatArray,
    vel: FloatArray,
    contact: FloatArray | None,
    p: PassingParams,
) -> np.ndarray:
    """``(N,)``: the robot standing at each of ``states (N, 6)`` from ``t`` s on is not touched
    (centre distance ``>= contact (K,)`` m) by anyone walking on for ``p.hold`` s: the search
    ends in no trap at its horizon. All true without people, ``hold`` or ``contact``."""
    if not (len(people) and p.hold > 0 and contact is not None):
        return np.ones(len(states), dtype=bool)
    th = t + np.arange(0.0, p.hold + 1e-9, p.step)
    fut = people[None] + th[:, None, None] * vel[None]  # (H, K, 2)
    rel = fut[None] - states[:, None, None, :2]  # (N, H, K, 2)
    gap = np.hypot(rel[..., 0], rel[..., 1]).min(axis=1)
    return np.asarray((gap >= np.asarray(contact)[None]).all(axis=1))


def follow_plan(
    plan: PassingPlan,
    elapsed: float,
    pose: FloatArray,
    twist: FloatArray,
    robot: RobotModel,
    people: FloatArray,
    people_velocities: FloatArray,
    static_ok: Callable[[FloatArray, FloatArray, FloatArray], np.ndarray],
    params: PassingParams | None = None,
    contact: FloatArray | None = None,
) -> FloatArray | None:
    """The twist to command now ``(3,)`` to go on with ``plan``, found ``elapsed`` s ago, from
    ``pose (3,)`` and ``twist (3,)``; ``None`` when its rest no longer keeps the distance, the
    static check or a safe stop against the people as they are forecast now (arguments as
    :func:`timed_pass`). Between searches the control loop only checks the plan it follows
    (a receding horizon replanned every period)."""
    p = params or PassingParams()
    pose, twist, people, vel = _checked(pose, twist, people, people_velocities)
    j = int(elapsed // p.period + 1e-9)
    if not (elapsed >= 0 and j < len(plan.commands)):
        return None
    acc, need, state = _start(pose, twist, robot, people, p)
    closest = np.full(1, np.inf)
    period = _period()
    t, end = 0.0, (j + 1) * p.period - elapsed
    for k in range(j, len(plan.commands)):
        steps = max(1, round(end / p.step))
        times = np.asarray(t + p.step * np.arange(steps + 1), dtype=np.float64)
        cmd = plan.commands[k : k + 1]
        state, poses, alive, closest = period(
            state, cmd, acc, p.step, times, people, vel, need, closest
        )
        if not alive[0] or not static_ok(cmd, poses, times)[0]:
            return None
        t, end = float(times[-1]), p.period
    if not _safe_to_stop(state, t, people, vel, contact, p)[0]:
        return None
    return _first_step_velocity(np.concatenate([pose, twist]), plan.commands[j : j + 1], acc)[0]


def _merge(s: FloatArray, cell: tuple[float, float]) -> np.ndarray:
    """Indices of ``s (N, 6)`` with one state per lattice cell (``cell`` m, rad, and the
    velocity on a 0.05 grid), the first of each."""
    return _first_per_key(
        np.concatenate(
            [
                np.round(s[:, :2] / cell[0]),
                np.round(s[:, 2:3] / cell[1]),
                np.round(s[:, 3:] / 0.05),
            ],
            axis=1,
        )
    )


def _first_per_key(key: FloatArray) -> np.ndarray:
    """Sorted indices of the first row of each distinct row of integer-valued ``key (N, D)``
    (a 1-D unique on a mixed-radix code: ``np.unique(axis=0)`` sorts rows lexicographically,
    several times slower)."""
    k = key.astype(np.int64)
    k -= k.min(axis=0)
    code = np.zeros(len(k), dtype=np.int64)
    for col, span in zip(k.T, k.max(axis=0) + 1, strict=True):
        code = code * int(span) + col
    _, first = np.unique(code, return_index=True)
    return np.sort(first)


def _first_step_velocity(state: FloatArray, commands: FloatArray, acc: FloatArray) -> FloatArray:
    """``(C, 3)`` the twist one step after ``state (6,)`` toward each command: what the control
    loop commands now (the next cycle replans)."""
    return np.asarray(state[3:] + np.clip(commands - state[3:], -acc, acc))


def lattice_period_reference(
    states: FloatArray,
    commands: FloatArray,
    acc: FloatArray,
    step: float,
    times: FloatArray,
    people: FloatArray,
    vel: FloatArray,
    need: FloatArray,
    low_in: FloatArray,
) -> tuple[FloatArray, FloatArray, np.ndarray, FloatArray]:
    """One period of the search: each of ``states (N, 6)`` ``(x, y, θ, vx, vy, ω)`` driven
    toward each of ``commands (C, 3)`` (row ``i * C + j``), the twist ramping by at most
    ``acc (3,)`` per ``step`` s, poses integrated at ``times (S + 1,)`` (``times[0]`` the
    period's start, s from now). People ``people (K, 2)`` m at ``vel (K, 2)`` m/s, ``need (K,)``
    m. Returns the end states ``(N C, 6)``, the poses ``(N C, S + 1, 3)`` (column 0 the start),
    ``alive (N C,)`` (never nearer than ``need`` to anyone at a sample) and the smallest
    distance so far ``(N C,)`` (``low_in (N,)`` carried on). NumPy reference of
    :func:`socialnav.planner.kernels.lattice_period`."""
    s = np.repeat(states, len(commands), axis=0)
    cmd = np.tile(commands, (len(states), 1))
    low = np.repeat(low_in, len(commands))
    alive = np.ones(len(s), dtype=bool)
    poses = np.empty((len(s), len(times), 3))
    poses[:, 0] = s[:, :3]
    for k in range(1, len(times)):
        s[:, 3:] += np.clip(cmd - s[:, 3:], -acc, acc)
        c, sn = np.cos(s[:, 2]), np.sin(s[:, 2])
        s[:, 0] += (c * s[:, 3] - sn * s[:, 4]) * step
        s[:, 1] += (sn * s[:, 3] + c * s[:, 4]) * step
        s[:, 2] += s[:, 5] * step
        poses[:, k] = s[:, :3]
        if len(people):
            d = np.hypot(
                people[None, :, 0] + times[k] * vel[None, :, 0] - s[:, None, 0],
                people[None, :, 1] + times[k] * vel[None, :, 1] - s[:, None, 1],
            )
            alive &= (d >= need[None]).all(axis=1)
            low = np.minimum(low, d.min(axis=1))
    return s, poses, alive, low

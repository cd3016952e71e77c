"""Task and efficiency metrics (metrics.md, "Task and efficiency").

"Goal" here is ``record.target`` (the pose at which success is measured); "reached" means within
``record.goal_tolerance`` and held until the end of the record (see ``table1.time_to_goal``).
The straight-line distance is ``|target - p_0|`` from the first recorded robot position.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.robot import ROBOT_MODELS
from socialnav.metrics.base import metric
from socialnav.metrics.series import goal_reached_index, reached_within_limit, step_lengths
from socialnav.metrics.success import evaluate_success
from socialnav.metrics.table1 import time_to_goal

NOT_MOVING_SPEED = 0.01  # m/s: below this the robot counts as standing still


def _onsets(flags: np.ndarray) -> int:
    """Number of False→True transitions; a record starting True counts one."""
    f = np.asarray(flags, dtype=bool)
    if f.size == 0:
        return 0
    return int(f[0]) + int(np.count_nonzero(f[1:] & ~f[:-1]))


def _straight_line(record: EpisodeRecord) -> float:
    return float(np.linalg.norm(record.target[:2] - record.robot_xy[0]))


@metric("success", unit="1", direction="max")
def success(record: EpisodeRecord) -> float:
    """1.0 when every required success condition of the record's family holds
    (``socialnav.metrics.success.evaluate_success(record)["success"]``), else 0.0."""
    return float(evaluate_success(record)["success"])


@metric("collisions_person", unit="1", direction="min")
def collisions_person(record: EpisodeRecord) -> float:
    """Number of collision onsets with people: False→True transitions of
    ``record.collision_person`` (a record starting in collision counts one)."""
    assert record.collision_person is not None  # filled by EpisodeRecord.__post_init__
    return float(_onsets(record.collision_person))


@metric("collisions_obstacle", unit="1", direction="min")
def collisions_obstacle(record: EpisodeRecord) -> float:
    """Number of collision onsets with walls and obstacles: False→True transitions of
    ``record.collision_obstacle`` (a record starting in collision counts one)."""
    assert record.collision_obstacle is not None  # filled by EpisodeRecord.__post_init__
    return float(_onsets(record.collision_obstacle))


@metric("collisions", unit="1", direction="min")
def collisions(record: EpisodeRecord) -> float:
    """Total collision onsets: collisions_person + collisions_obstacle (a person and a wall hit at
    the same sample count two)."""
    return collisions_person(record) + collisions_obstacle(record)


@metric("timeout", unit="1", direction="min")
def timeout(record: EpisodeRecord) -> float:
    """1.0 when the goal was not reached (and held) within ``record.time_limit`` seconds of the
    first sample — whatever the reason the episode ended — else 0.0."""
    return 0.0 if reached_within_limit(record) else 1.0


@metric("path_length", unit="m", direction="min")
def path_length(record: EpisodeRecord) -> float:
    """L = Σ_t |p_{t+1} - p_t| over the whole record (compare ``total_distance``, which stops at
    the goal)."""
    return float(step_lengths(record).sum())


@metric("path_length_ratio", unit="1", direction="min")
def path_length_ratio(record: EpisodeRecord) -> float:
    """L / |target - p_0| (>= 1 for a run that ends at the target). NaN when the robot starts on
    the target."""
    straight = _straight_line(record)
    return float("nan") if straight < 1e-9 else path_length(record) / straight


@metric("spl", unit="1", direction="max", reference="Anderson et al. 2018; metrics.md")
def spl(record: EpisodeRecord) -> float:
    """SPL = S · ℓ / max(L, ℓ), S = success flag, ℓ = |target - p_0| (the Euclidean lower bound
    on the shortest path, ignoring obstacles), L = path_length. NaN when ℓ == 0."""
    straight = _straight_line(record)
    if straight < 1e-9:
        return float("nan")
    return success(record) * straight / max(path_length(record), straight)


@metric("time_not_moving", unit="s", direction="min")
def time_not_moving(record: EpisodeRecord) -> float:
    """dt × number of steps whose translational speed |p_{t+1} - p_t| / dt is below 0.01 m/s,
    counted until the goal is reached (whole record if never reached). Rotation in place
    counts as not moving."""
    speeds = step_lengths(record) / record.dt
    k = goal_reached_index(record)
    if k is not None:
        speeds = speeds[:k]
    return float(np.count_nonzero(speeds < NOT_MOVING_SPEED) * record.dt)


def max_speed_of(record: EpisodeRecord) -> float | None:
    """The robot's top translational speed (m/s): ``meta["max_speed"]``, else
    :attr:`~socialnav.core.robot.RobotModel.max_speed` of the model named by ``meta["robot"]``
    in ``ROBOT_MODELS`` (a holonomic base is faster diagonally than forward), else None."""
    if "max_speed" in record.meta:
        return float(record.meta["max_speed"])
    model = ROBOT_MODELS.get(str(record.meta.get("robot", "")))
    return None if model is None else model.max_speed


@metric("extra_time", unit="s", direction="min")
def extra_time(record: EpisodeRecord) -> float:
    """time_to_goal - max(|target - p_0| - goal_tolerance, 0) / v_max: the time lost against
    driving straight at top speed until the goal tolerance is met (the same arrival criterion
    as ``time_to_goal``). v_max from ``meta["max_speed"]`` or the robot model named by
    ``meta["robot"]``. NaN when the goal is not reached or v_max is unknown."""
    v_max = max_speed_of(record)
    if v_max is None or v_max <= 0:
        return float("nan")
    straight = max(_straight_line(record) - record.goal_tolerance, 0.0)
    return time_to_goal(record) - straight / v_max

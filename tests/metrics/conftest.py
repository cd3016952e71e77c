"""A builder of analytic EpisodeRecords for the metric tests."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from socialnav.core.episode import EpisodeRecord
from socialnav.core.scene import Person, SocialContext

SQUARE = np.array([[0.2, 0.2], [-0.2, 0.2], [-0.2, -0.2], [0.2, -0.2]])  # 0.4 m square


def segment(p0: tuple[float, float], p1: tuple[float, float], steps: int) -> np.ndarray:
    """``steps + 1`` evenly spaced points from ``p0`` to ``p1`` inclusive: ``(steps + 1, 2)``."""
    s = np.linspace(0.0, 1.0, steps + 1)[:, None]
    return (1.0 - s) * np.asarray(p0, float) + s * np.asarray(p1, float)


def build_record(
    robot_xy: Any,
    *,
    yaw: float | Any = 0.0,
    people: Any = None,
    people_velocities: Any = None,
    people_radii: Any = None,
    dt: float = 0.1,
    start: Any = None,
    goal: Any = None,
    target: Any = None,
    goal_tolerance: float = 0.1,
    time_limit: float = 60.0,
    family: str = "hallway",
    scenario: str = "test",
    footprint: Any = SQUARE,
    robot_radius: float | None = None,
    groups: tuple = (),
    queues: tuple = (),
    artworks: tuple = (),
    person_yaws: Any = None,
    collision_person: Any = None,
    collision_obstacle: Any = None,
    waypoint: Any = None,
    meta: dict | None = None,
) -> EpisodeRecord:
    """An EpisodeRecord from a robot path ``(T, 2)`` and people ``(T, K, 2)`` or static ``(K, 2)``.

    People velocities default to forward differences of their positions (last one repeated);
    ``start`` defaults to the first robot position, ``goal`` to the last, ``target`` to ``goal``.
    The context lists the people at their first position (ids 0..K-1, yaws ``person_yaws``).
    """
    xy = np.asarray(robot_xy, dtype=float)
    steps = xy.shape[0]
    yaws = np.broadcast_to(np.asarray(yaw, dtype=float), (steps,)).copy()
    if people is None:
        pos = np.zeros((steps, 0, 2))
    else:
        pos = np.asarray(people, dtype=float)
        if pos.ndim == 2:
            pos = np.broadcast_to(pos, (steps, *pos.shape)).copy()
    k = pos.shape[1]
    if people_velocities is None:
        vel = np.zeros_like(pos)
        if steps > 1:
            d = np.diff(pos, axis=0) / dt
            vel = np.concatenate([d, d[-1:]], axis=0)
    else:
        vel = np.broadcast_to(np.asarray(people_velocities, dtype=float), pos.shape).copy()
    radii = np.full(k, 0.25) if people_radii is None else np.asarray(people_radii, float)
    p_yaws = np.zeros(k) if person_yaws is None else np.asarray(person_yaws, float)
    persons = tuple(
        Person(i, tuple(pos[0, i]), tuple(vel[0, i]), float(p_yaws[i]), float(radii[i]))
        for i in range(k)
    )
    context = SocialContext(persons, tuple(groups), tuple(queues), tuple(artworks))
    fp = np.asarray(footprint, dtype=float)
    start_pose = np.array([*xy[0], yaws[0]]) if start is None else np.asarray(start, float)
    goal_pose = np.array([*xy[-1], yaws[-1]]) if goal is None else np.asarray(goal, float)
    target_pose = goal_pose if target is None else np.asarray(target, float)
    return EpisodeRecord(
        dt=dt,
        times=np.arange(steps) * dt,
        robot_poses=np.column_stack([xy, yaws]),
        robot_twists=np.zeros((steps, 3)),
        robot_footprint=fp,
        robot_radius=(
            float(np.linalg.norm(fp, axis=1).max()) if robot_radius is None else robot_radius
        ),
        people_ids=np.arange(k),
        people_positions=pos,
        people_velocities=vel,
        people_radii=radii,
        start=start_pose,
        goal=goal_pose,
        target=target_pose,
        goal_tolerance=goal_tolerance,
        time_limit=time_limit,
        family=family,
        scenario=scenario,
        context=context,
        waypoint=None if waypoint is None else np.asarray(waypoint, float),
        collision_person=None if collision_person is None else np.asarray(collision_person),
        collision_obstacle=None if collision_obstacle is None else np.asarray(collision_obstacle),
        meta=meta or {},
    )


@pytest.fixture(scope="session")
def make_record() -> Callable[..., EpisodeRecord]:
    return build_record


@pytest.fixture(scope="session")
def seg() -> Callable[..., np.ndarray]:
    return segment

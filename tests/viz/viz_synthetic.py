"""Synthetic EpisodeRecords for the viz tests (geometry of the paper scenarios).

Robot paths are analytic (polylines sampled at constant speed), not planner output: the tests
check drawing, not navigation.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.robot import PR2
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext

DT = 0.1


def room_walls(size: float = 25.0) -> np.ndarray:
    c = np.array([[0, 0], [size, 0], [size, size], [0, size]], dtype=float)
    return np.stack([c, np.roll(c, -1, axis=0)], axis=1)


def hallway_walls() -> np.ndarray:
    return np.array([[[0.0, -1.5], [20.0, -1.5]], [[0.0, 1.5], [20.0, 1.5]]])


def resample(polyline: np.ndarray, speed: float, dt: float = DT) -> np.ndarray:
    """Poses (T, 3) moving along ``polyline`` (P, 2) at ``speed`` m/s, yaw along the motion."""
    seg = np.linalg.norm(np.diff(polyline, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.arange(0.0, s[-1] / speed + dt, dt)
    q = np.minimum(t * speed, s[-1])
    xy = np.column_stack([np.interp(q, s, polyline[:, 0]), np.interp(q, s, polyline[:, 1])])
    d = np.gradient(xy, axis=0)
    yaw = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    return np.column_stack([xy, yaw])


def make_record(
    poses: np.ndarray,
    people: np.ndarray,
    context: SocialContext,
    *,
    goal: tuple[float, float, float],
    target: tuple[float, float, float] | None = None,
    family: str,
    scenario: str,
    planner: str = "paccet",
    walls: np.ndarray | None = None,
    obstacles: tuple[np.ndarray, ...] = (),
    waypoint: np.ndarray | None = None,
) -> EpisodeRecord:
    T, K = poses.shape[0], people.shape[1]
    vel = np.gradient(people, DT, axis=0) if T > 1 else np.zeros_like(people)
    return EpisodeRecord(
        dt=DT,
        times=np.arange(T) * DT,
        robot_poses=poses,
        robot_twists=np.zeros((T, 3)),
        robot_footprint=PR2.polygon,
        robot_radius=PR2.circumscribed_radius,
        people_ids=np.array([p.id for p in context.people][:K], dtype=int),
        people_positions=people,
        people_velocities=vel,
        people_radii=np.full(K, 0.25),
        start=poses[0].copy(),
        goal=np.asarray(goal, dtype=float),
        target=np.asarray(target if target is not None else goal, dtype=float),
        goal_tolerance=0.3,
        time_limit=60.0,
        family=family,
        scenario=scenario,
        context=context,
        waypoint=waypoint,
        walls=room_walls() if walls is None else walls,
        obstacles=obstacles,
        meta={"planner": planner, "robot": "pr2", "seed": 0},
    )


def static_people(positions: np.ndarray, T: int) -> np.ndarray:
    return np.repeat(np.asarray(positions, dtype=float)[None], T, axis=0)


def hallway(planner: str = "paccet") -> EpisodeRecord:
    """hallway_passing: robot (0.5,-0.45)→(5.5,-0.45), a walker on y=+0.45 at 0.5 m/s."""
    x = np.linspace(0.5, 5.5, 60)
    bump = 0.0 * x if planner == "traditional" else -0.55 * np.exp(-(((x - 3.0) / 0.9) ** 2))
    poses = resample(np.column_stack([x, -0.45 + bump]), 0.38)
    T = poses.shape[0]
    t = np.arange(T) * DT
    walker = np.column_stack([6.0 - 0.5 * t, np.full(T, 0.45)])[:, None, :]
    ctx = SocialContext(people=(Person(0, (6.0, 0.45), (-0.5, 0.0), np.pi),))
    return make_record(
        poses,
        walker,
        ctx,
        goal=(5.5, -0.45, 0.0),
        family="hallway",
        scenario="hallway_passing",
        planner=planner,
        walls=hallway_walls(),
    )


def group(planner: str = "paccet") -> EpisodeRecord:
    """group_join: members at 90°, 180°, 270° on a 0.9 m circle; the gap faces the robot."""
    c, r = np.array([12.5, 12.5]), 0.9
    ang = np.deg2rad([90.0, 180.0, 270.0])
    pos = c + r * np.column_stack([np.cos(ang), np.sin(ang)])
    people = tuple(
        Person(i, tuple(p), yaw=float(a + np.pi))
        for i, (p, a) in enumerate(zip(pos, ang, strict=True))
    )
    ctx = SocialContext(people=people, groups=(Group((0, 1, 2)),))
    end = (13.4, 12.5) if planner != "traditional" else (13.0, 12.6)
    poses = resample(np.array([[20.0, 12.5], [16.0, 12.9], end]), 0.5)
    poses[-5:, 2] = np.pi  # final turn to face the centre
    return make_record(
        poses,
        static_people(pos, poses.shape[0]),
        ctx,
        goal=(12.5, 12.5, np.pi),
        target=(13.4, 12.5, np.pi),
        family="group",
        scenario="group_join",
        planner=planner,
    )


def desk(center: tuple[float, float], size: tuple[float, float] = (1.6, 0.6)) -> np.ndarray:
    hx, hy = size[0] / 2, size[1] / 2
    return np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]]) + np.asarray(center)


def queue(planner: str = "paccet") -> EpisodeRecord:
    """queue_line: desk at (12.5, 20.3); people at y = 19.4, 18.6, 17.8; tail slot y = 17.0."""
    pos = np.array([[12.5, 19.4], [12.5, 18.6], [12.5, 17.8]])
    people = tuple(Person(i, tuple(p), yaw=np.pi / 2) for i, p in enumerate(pos))
    ctx = SocialContext(people=people, queues=(Queue((0, 1, 2), (12.5, 20.0)),))
    if planner == "traditional":
        line = np.array([[6.0, 14.0], [9.0, 17.0], [11.7, 19.5]])
    else:
        line = np.array([[6.0, 14.0], [10.0, 15.6], [12.5, 16.2], [12.5, 17.0]])
    poses = resample(line, 0.5)
    if planner != "traditional":
        poses[-8:, 2] = np.pi / 2
    return make_record(
        poses,
        static_people(pos, poses.shape[0]),
        ctx,
        goal=(12.5, 19.5, np.pi / 2),
        target=(12.5, 17.0, np.pi / 2),
        family="queue",
        scenario="queue_line",
        planner=planner,
        obstacles=(desk((12.5, 20.3)),),
    )


def gallery(planner: str = "paccet") -> EpisodeRecord:
    """gallery_activity: viewer at (13, 22.5) facing an artwork at (13, 25); robot passes behind."""
    viewer = np.array([[13.0, 22.5]])
    art = Artwork((13.0, 25.0), 1.2, -np.pi / 2, viewer_ids=(0,))
    ctx = SocialContext(people=(Person(0, (13.0, 22.5), yaw=np.pi / 2),), artworks=(art,))
    if planner == "traditional":
        line = np.array([[7.0, 23.8], [19.0, 23.8]])
    else:
        line = np.array([[7.0, 23.8], [10.5, 22.2], [13.0, 21.3], [15.5, 22.2], [19.0, 23.8]])
    poses = resample(line, 0.5)
    return make_record(
        poses,
        static_people(viewer, poses.shape[0]),
        ctx,
        goal=(19.0, 23.8, 0.0),
        family="gallery_activity",
        scenario="gallery_activity",
        planner=planner,
        waypoint=np.array([13.0, 21.3]),
    )


ALL = {"hallway": hallway, "group": group, "queue": queue, "gallery": gallery}

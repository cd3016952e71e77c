"""A recorded crowd: UCY zara01 replayed through ``Navigator.step`` (people do not react).

The control-loop issue's case: from t = 33.2 s of the recording, the PR2 drives from
(−1.90, 6.41) to (−4.25, 16.78); at about 15 s a pedestrian walks into the stopped robot, and
every planner used to end STUCK 3 m short. Expected now: the goal.

The obsmat tracks (frame, id, x, z, y, vx, vz, vy; metres; every 10 frames at 25 fps) are read
with pandas and interpolated linearly to the 0.1 s control period; a person is in view from
their first to their last annotation. The robot's command is integrated exactly (kinematic);
the scene is open space over the annotated area (2 m margin).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _planner_helpers import step_pose

from socialnav.core.robot import PR2
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.local_planner import PlannerStatus
from socialnav.planner.presets import build_navigator
from socialnav.world.grid import FREE, Costmap, GridGeometry

pd = pytest.importorskip("pandas")

DATA = Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "crowds"
ZARA = DATA / "ucy_zara01_obsmat.txt"
FPS = 25.0
T0 = 33.2
START = np.array([-1.90, 6.41, np.arctan2(16.78 - 6.41, -4.25 + 1.90)])
GOAL = np.array([-4.25, 16.78, START[2]])
DT = 0.1


def _tracks() -> pd.DataFrame:
    cols = ["frame", "id", "x", "z", "y", "vx", "vz", "vy"]
    df = pd.read_csv(ZARA, sep=r"\s+", header=None, names=cols, usecols=range(8))
    df["t"] = df["frame"] / FPS
    return df


def _scene(df: pd.DataFrame, t: float) -> SocialContext:
    people = []
    for pid, g in df.groupby("id", sort=True):
        ts = g["t"].to_numpy()
        if not ts[0] <= t <= ts[-1]:
            continue
        x = float(np.interp(t, ts, g["x"]))
        y = float(np.interp(t, ts, g["y"]))
        k = min(int(np.searchsorted(ts, t, side="right")), len(ts) - 1)
        j = max(k - 1, 0)
        span = ts[k] - ts[j]
        if span > 0:
            vx = float((g["x"].iloc[k] - g["x"].iloc[j]) / span)
            vy = float((g["y"].iloc[k] - g["y"].iloc[j]) / span)
        else:
            vx = vy = 0.0
        people.append(Person(int(pid), (x, y), (vx, vy), float(np.arctan2(vy, vx))))
    return SocialContext(tuple(people))


def _open_space(df: pd.DataFrame, res: float = 0.05) -> Costmap:
    lo = np.array([df["x"].min(), df["y"].min()]) - 2.0
    hi = np.array([df["x"].max(), df["y"].max()]) + 2.0
    shape = (int(np.ceil((hi[1] - lo[1]) / res)), int(np.ceil((hi[0] - lo[0]) / res)))
    return Costmap(np.full(shape, FREE, dtype=np.uint8), GridGeometry(shape, res, tuple(lo)))


@pytest.mark.skipif(not ZARA.is_file(), reason="shared crowd data not present")
@pytest.mark.parametrize("preset", ["traditional", "paccet"])
def test_zara01_pedestrian_walking_into_the_stopped_robot_does_not_end_the_episode(preset):
    df = _tracks()
    costmap = _open_space(df)
    nav = build_navigator(preset, PR2, costmap, GOAL, _scene(df, T0))
    pose, vel = START.copy(), np.zeros(3)
    statuses = []
    for k in range(int(60.0 / DT)):
        res = nav.step(T0 + k * DT, pose, vel, _scene(df, T0 + k * DT))
        statuses.append(res.status)
        if res.status == PlannerStatus.GOAL_REACHED and np.all(np.abs(res.cmd) < 1e-3):
            break
        vel = res.cmd
        pose = step_pose(pose, vel)
    assert statuses[-1] == PlannerStatus.GOAL_REACHED, sorted(set(statuses))
    assert np.hypot(*(pose[:2] - GOAL[:2])) <= 0.1 + 1e-9

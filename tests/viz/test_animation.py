"""Animations: GIF frames, FanFrame conversion, frame subsampling, bad input."""

from __future__ import annotations

import importlib.util
from dataclasses import replace

import numpy as np
import pytest
import viz_synthetic as S
from PIL import Image

from socialnav.planner.record import EvaluationRecord
from socialnav.viz.animation import FanFrame, animate_episode, fan_frame, frame_indices


def _short_hallway(n: int = 24):
    rec = S.hallway()
    sl = slice(0, n)
    return replace(
        rec,
        times=rec.times[sl],
        robot_poses=rec.robot_poses[sl],
        robot_twists=rec.robot_twists[sl],
        people_positions=rec.people_positions[sl],
        people_velocities=rec.people_velocities[sl],
        collision_person=None,
        collision_obstacle=None,
        status=None,
    )


def _fan(pose: np.ndarray, n: int = 9, steps: int = 6) -> FanFrame:
    """Arcs of constant speed 0.5 m/s and turn rates in [-1, 1] rad/s over 1.5 s."""
    w = np.linspace(-1.0, 1.0, n)
    t = np.linspace(0.0, 1.5, steps)
    yaw = pose[2] + w[:, None] * t
    dx = np.cumsum(0.5 * np.cos(yaw) * (t[1] - t[0]), axis=1)
    dy = np.cumsum(0.5 * np.sin(yaw) * (t[1] - t[0]), axis=1)
    xy = np.stack([pose[0] + dx, pose[1] + dy], axis=-1)
    fitness = np.abs(w)
    fitness[0] = np.inf
    return FanFrame(xy, fitness, np.isfinite(fitness), chosen=int(np.argmin(fitness)))


def test_gif_has_one_frame_per_selected_sample(tmp_path):
    rec = _short_hallway()
    diags = [_fan(p) if i % 2 == 0 else None for i, p in enumerate(rec.robot_poses)]
    out = animate_episode(rec, diags, tmp_path / "a.gif", stride=3, dpi=40)
    expected = len(frame_indices(rec.num_steps, 3, 150))
    with Image.open(out) as im:
        assert im.format == "GIF"
        assert im.n_frames == expected > 1
        first = np.asarray(im.convert("RGB"), dtype=float)
        im.seek(im.n_frames - 1)
        last = np.asarray(im.convert("RGB"), dtype=float)
    assert first.std() > 10.0
    assert np.abs(first - last).mean() > 0.1  # the robot moved between frames


def test_gif_without_diagnostics(tmp_path):
    rec = _short_hallway(12)
    out = animate_episode(rec, path=tmp_path / "b.gif", dpi=40)
    with Image.open(out) as im:
        assert im.n_frames == 12  # short episodes keep every sample
    # the path may also come second positionally
    assert animate_episode(rec, str(tmp_path / "c.gif"), dpi=40) == tmp_path / "c.gif"


def test_frame_indices_limits():
    idx = frame_indices(1000, None, 150)
    assert len(idx) <= 150 and idx[0] == 0 and idx[-1] == 999
    assert np.all(np.diff(idx) >= 2)
    np.testing.assert_array_equal(frame_indices(5, None, 150), np.arange(5))
    np.testing.assert_array_equal(frame_indices(7, 3, 150), [0, 3, 6])
    np.testing.assert_array_equal(frame_indices(8, 3, 150), [0, 3, 6, 7])
    with pytest.raises(ValueError):
        frame_indices(10, 0, 150)


def test_fan_frame_shapes_and_relative_fitness():
    f = FanFrame(np.zeros((4, 3)), [1.0, 2.0, 3.0, np.inf], [True, True, True, False], 0)
    assert f.poses.shape == (4, 1, 2)  # end poses -> one-point rollouts, yaw dropped
    np.testing.assert_allclose(f.relative_fitness(), [0.0, 0.5, 1.0, np.nan])
    tie = FanFrame(np.zeros((2, 2)), [5.0, 5.0], [True, True])
    np.testing.assert_array_equal(tie.relative_fitness(), [0.0, 0.0])
    with pytest.raises(ValueError, match="out of range"):
        FanFrame(np.zeros((2, 2)), [1.0, 2.0], [True, True], chosen=2)
    with pytest.raises(ValueError, match="must both be"):
        FanFrame(np.zeros((2, 5, 2)), [1.0], [True, True])
    with pytest.raises(ValueError, match="NaN"):
        FanFrame(np.full((2, 5, 2), np.nan), [1.0, 2.0], [True, True])


def test_fan_frame_from_an_evaluation_record():
    end = np.random.default_rng(0).normal(size=(5, 3))
    rec = EvaluationRecord(
        time=0.0,
        pose=np.zeros(3),
        velocity=np.zeros(3),
        goal=np.ones(3),
        status="OK",
        twists=np.zeros((5, 3)),
        end_poses=end,
        legal=np.array([1, 1, 0, 1, 0], bool),
        fitness=np.array([2.0, 2.0, np.inf, 1.0, np.inf]),
        chosen=3,
    )
    fan = fan_frame(rec)
    assert fan is not None and fan.poses.shape == (5, 1, 2) and fan.chosen == 3
    np.testing.assert_allclose(fan.poses[:, 0], end[:, :2])
    assert fan.legal.tolist() == [True, True, False, True, False]
    assert fan_frame(None) is None
    assert fan_frame(replace(rec, fitness=None, chosen=None)) is None  # nothing was selected


def test_bad_input(tmp_path):
    rec = _short_hallway(6)
    empty = replace(
        rec,
        times=np.zeros(0),
        robot_poses=np.zeros((0, 3)),
        robot_twists=np.zeros((0, 3)),
        people_positions=np.zeros((0, 1, 2)),
        people_velocities=np.zeros((0, 1, 2)),
        collision_person=None,
        collision_obstacle=None,
        status=None,
    )
    with pytest.raises(ValueError, match="no samples"):
        animate_episode(empty, tmp_path / "e.gif")
    with pytest.raises(ValueError, match="format"):
        animate_episode(rec, tmp_path / "e.avi")
    with pytest.raises(ValueError, match="fps"):
        animate_episode(rec, tmp_path / "e.gif", fps=0)
    with pytest.raises(ValueError, match="fans for a record"):
        animate_episode(rec, [None] * 7, tmp_path / "e.gif")
    with pytest.raises(ValueError, match="output path"):
        animate_episode(rec, [None] * 6)


@pytest.mark.skipif(
    importlib.util.find_spec("imageio_ffmpeg") is not None, reason="imageio-ffmpeg installed"
)
def test_mp4_without_ffmpeg_is_a_clear_error(tmp_path):
    with pytest.raises(ImportError, match=r"socialnav\[video\]"):
        animate_episode(_short_hallway(6), tmp_path / "v.mp4")


def test_mp4_with_ffmpeg(tmp_path):
    pytest.importorskip("imageio_ffmpeg")
    out = animate_episode(_short_hallway(6), tmp_path / "v.mp4", dpi=40)
    assert out.stat().st_size > 1000
    with open(out, "rb") as fh:
        assert b"ftyp" in fh.read(64)

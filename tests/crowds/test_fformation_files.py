"""The F-formation dataset reader: settings, features and annotations, clear errors, and
the facts about the shared files that the benchmark relies on."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.io import savemat

from socialnav.crowds.fformations import (
    HEADING_CONVENTIONS,
    FFormationFormatError,
    FFormationFrame,
    facing_offsets,
    front_share,
    heading_step,
    load_fformation_frames,
    load_fformation_settings,
    mutual_neighbours,
)

DATA = Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "fformations"


def _cell(items: list) -> np.ndarray:
    out = np.empty((1, len(items)), dtype=object)
    for i, x in enumerate(items):
        out[0, i] = x
    return out


def _settings(path: Path, **params) -> Path:
    fields = {"radius": 60.0, "covmat": np.diag([400.0, 400.0, 0.005]), "nsamples": 800.0}
    fields |= {"quant": 2.0, "empty": 0.7}
    fields |= params
    fields = {k: v for k, v in fields.items() if v is not None}
    savemat(path, {"params": fields})
    return path


def _dataset(folder: Path, gt_stamps=(2, 1), gt=None, rows=None) -> Path:
    folder.mkdir(exist_ok=True)
    frame = np.array([[1, 100.0, 0.0, np.pi], [2, -100.0, 0.0, 0.0], [3, 0.0, 500.0, 0.0]])
    feats = _cell([frame if rows is None else rows, frame[:2]])
    savemat(folder / "features.mat", {"features": feats, "timestamp": np.array([[1, 2]])})
    groups = gt if gt is not None else [_cell([np.array([[1, 2]])]), _cell([np.array([[1, 2]])])]
    savemat(
        folder / "groundtruth.mat",
        {"GTgroups": _cell(groups), "GTtimestamp": np.array([list(gt_stamps)])},
    )
    return folder


def test_settings_in_metres(tmp_path):
    s = load_fformation_settings(_settings(tmp_path / "settings.mat"))
    assert s.stride == pytest.approx(0.6)
    assert s.position_sigma == pytest.approx(0.2)
    assert s.heading_sigma == pytest.approx(np.sqrt(0.005))
    assert s.quant == pytest.approx(0.02) and s.nsamples == 800 and s.empty == pytest.approx(0.7)


@pytest.mark.parametrize(
    ("params", "field"),
    [
        ({"radius": None}, "params.radius"),
        ({"radius": -5.0}, "params.radius"),
        ({"radius": np.array([60.0, 70.0])}, "params.radius"),
        ({"covmat": np.eye(2)}, "params.covmat"),
        ({"covmat": -np.eye(3)}, "params.covmat"),
        ({"empty": "much"}, "params.empty"),
    ],
)
def test_bad_settings_name_file_and_field(tmp_path, params, field):
    path = _settings(tmp_path / "settings.mat", **params)
    with pytest.raises(FFormationFormatError, match=field) as err:
        load_fformation_settings(path)
    assert "settings.mat" in str(err.value)


def test_settings_not_a_mat_file(tmp_path):
    path = tmp_path / "settings.mat"
    path.write_text("radius: 60\n")
    with pytest.raises(FFormationFormatError, match=r"settings\.mat"):
        load_fformation_settings(path)
    savemat(path, {"other": 1.0})
    with pytest.raises(FFormationFormatError, match="field 'params' is missing"):
        load_fformation_settings(path)


def test_frames_matched_by_timestamp_not_position(tmp_path):
    frames = load_fformation_frames(_dataset(tmp_path / "d"))
    # GTtimestamp (2, 1): the first annotation is of the second feature frame (2 people)
    assert [f.timestamp for f in frames] == [2, 1]
    assert [f.ids.tolist() for f in frames] == [[1, 2], [1, 2, 3]]
    np.testing.assert_allclose(frames[1].positions, [[1.0, 0.0], [-1.0, 0.0], [0.0, 5.0]])
    assert frames[0].groups == [[1, 2]]


def test_bad_frames_name_file_and_field(tmp_path):
    with pytest.raises(FFormationFormatError, match=r"groundtruth.mat: field 'GTtimestamp'.*7"):
        load_fformation_frames(_dataset(tmp_path / "a", gt_stamps=(7, 1)))
    with pytest.raises(FFormationFormatError, match=r"features.mat: field 'features\{1\}'"):
        load_fformation_frames(_dataset(tmp_path / "b", rows=np.ones((3, 3))))
    bad = [_cell([np.array([[1, 9]])]), _cell([])]
    with pytest.raises(FFormationFormatError, match=r"'GTgroups\{1\}' names \[9\]"):
        load_fformation_frames(_dataset(tmp_path / "c", gt=bad))
    (tmp_path / "e").mkdir()
    with pytest.raises(FFormationFormatError, match=r"features\.mat: no such file"):
        load_fformation_frames(tmp_path / "e")


def test_heading_step():
    assert heading_step(np.radians([0, 90, 180, 270, -90])) == pytest.approx(np.pi / 2)
    assert heading_step(np.radians([0, 30, 45, 315])) == pytest.approx(np.radians(15))
    assert heading_step(np.array([0.1234, 1.0, 2.5])) == 0.0
    assert heading_step(np.array([])) == 0.0


def test_front_share_analytic():
    pair = np.array([[0.0, 0.0], [1.0, 0.0]])
    facing, away = np.array([0.0, np.pi]), np.array([np.pi, 0.0])
    assert front_share([(pair, facing)]) == (1.0, 2)
    assert front_share([(pair, away)]) == (0.0, 2)
    # a faces b; b looks away from a, 135° off the direction to a
    assert front_share([(pair, np.array([0.0, np.pi / 4]))]) == (0.5, 2)
    # beyond the range, and a lone person: nobody counted
    far = front_share([(pair * 2.0, facing), (pair[:1], facing[:1])])
    assert np.isnan(far[0]) and far[1] == 0
    # c's nearest is b, but b's is a: only the mutual pair (a, b) counts; frames add up
    three = np.array([[0.0, 0.0], [0.5, 0.0], [1.3, 0.0]])
    assert front_share([(three, np.array([0.0, np.pi, 0.0]))]) == (1.0, 2)
    assert front_share([(pair, facing), (pair, away)]) == (0.5, 4)


def test_mutual_neighbours():
    three = np.array([[0.0, 0.0], [0.5, 0.0], [1.3, 0.0]])  # c's nearest is b, b's is a
    who, other, gap = mutual_neighbours(three)
    assert who.tolist() == [0, 1] and other.tolist() == [1, 0]
    assert gap == pytest.approx([0.5, 0.5])
    assert mutual_neighbours(three, max_range=0.4)[0].size == 0
    assert mutual_neighbours(three[:1])[0].size == 0


@given(
    st.floats(-np.pi, np.pi),
    st.floats(-10, 10),
    st.floats(-10, 10),
    st.integers(0, 2**31 - 1),
)
def test_front_share_ignores_the_frame(angle, dx, dy, seed):
    """A rigid motion of the scene (rotation and translation) leaves the statistic unchanged."""
    rng = np.random.default_rng(seed)
    pos, yaw = rng.uniform(0, 4, (8, 2)), rng.uniform(-np.pi, np.pi, 8)
    c, s = np.cos(angle), np.sin(angle)
    moved = pos @ np.array([[c, s], [-s, c]]) + [dx, dy]
    before, after = front_share([(pos, yaw)]), front_share([(moved, yaw + angle)])
    assert before[1] == after[1]
    assert before[0] == pytest.approx(after[0], nan_ok=True)


def test_front_share_of_random_headings_is_a_half():
    rng = np.random.default_rng(3)
    pair = np.array([[0.0, 0.0], [1.0, 0.0]])
    share, people = front_share((pair, rng.uniform(0, 2 * np.pi, 2)) for _ in range(4000))
    assert people == 8000
    assert share == pytest.approx(0.5, abs=0.02)  # 4.5 standard errors


def _ring(yaw_of) -> list[FFormationFrame]:
    """Circles of 3 facing their centre, the stored angle written by ``yaw_of``."""
    rng = np.random.default_rng(0)
    out = []
    for t in range(20):
        a = rng.uniform(0, 2 * np.pi) + np.array([0, 2 * np.pi / 3, 4 * np.pi / 3])
        pos = np.column_stack([np.cos(a), np.sin(a)])
        out.append(FFormationFrame(t, np.arange(3), pos, yaw_of(a + np.pi), [[0, 1, 2]]))
    return out


@pytest.mark.parametrize("written", ["counter-clockwise from +x", "clockwise from +y (π/2 - θ)"])
def test_facing_offsets_find_the_convention(written):
    # each map is its own inverse except the reversal, which the test avoids
    frames = _ring(HEADING_CONVENTIONS[written])
    medians = {k: np.median(facing_offsets(frames, c)) for k, c in HEADING_CONVENTIONS.items()}
    assert min(medians, key=medians.get) == written
    assert medians[written] < 1e-9


@pytest.mark.parametrize("name", ["Synth", "CoffeeBreak_Seq1"])
def test_shared_files(name):
    """The facts the benchmark's F-formation section states about the shared files."""
    folder = DATA / name
    if not folder.is_dir():
        pytest.skip(f"shared dataset {name} not available")
    frames = load_fformation_frames(folder)
    settings = load_fformation_settings(folder / "settings.mat")
    assert settings.stride == pytest.approx(0.6)  # both sets publish a 60 cm stride
    assert len(frames) == {"Synth": 100, "CoffeeBreak_Seq1": 45}[name]
    step = heading_step(np.concatenate([f.yaws for f in frames]))
    assert np.degrees(step) == pytest.approx({"Synth": 15.0, "CoffeeBreak_Seq1": 90.0}[name])
    medians = {k: np.median(facing_offsets(frames, c)) for k, c in HEADING_CONVENTIONS.items()}
    assert min(medians, key=medians.get) == "counter-clockwise from +x"

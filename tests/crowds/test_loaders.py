"""Loaders: every format reads to the same tracks, frame periods follow their documented
defaults, and bad input names the file and the line."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from socialnav.crowds import (
    RecordingFormatError,
    load_four_column,
    load_groups,
    load_obsmat,
    load_recording,
    load_trajnet,
)
from socialnav.crowds.loaders import detect_format

ROWS = [  # frame, id, x, y: person 1 walks +x at 1 m/s (0.4 s per 10 frames), 2 stands
    (0, 1, 0.0, 0.0),
    (10, 1, 0.4, 0.0),
    (20, 1, 0.8, 0.0),
    (10, 2, 3.0, 1.0),
    (20, 2, 3.0, 1.0),
]


def write_obsmat(path: Path, rows=ROWS) -> Path:
    lines = [f"  {f:e}  {i:e}  {x:e}  0.0  {y:e}  0.0  0.0  0.0  " for f, i, x, y in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_trajnet(path: Path, rows=ROWS, fps: float | None = 2.5) -> Path:
    scene = {"id": 0, "p": 1, "s": 0, "e": 20}
    if fps is not None:
        scene["fps"] = fps
    lines = [json.dumps({"scene": scene})]
    lines += [json.dumps({"track": {"f": f, "p": i, "x": x, "y": y}}) for f, i, x, y in rows]
    lines.append(json.dumps({"scene": {**scene, "id": 1}}))
    lines += [json.dumps({"track": {"f": f, "p": i, "x": x, "y": y}}) for f, i, x, y in rows[:2]]
    path.write_text("\n".join(lines) + "\n")
    return path


def as_dict(rec):
    return {t.id: (t.times.tolist(), t.positions.tolist()) for t in rec.tracks}


def test_every_format_reads_the_same_tracks(tmp_path: Path) -> None:
    obsmat = load_obsmat(write_obsmat(tmp_path / "a_obsmat.txt"))
    tab = tmp_path / "b.txt"
    tab.write_text("\n".join("\t".join(map(str, r)) for r in ROWS) + "\n")
    comma = tmp_path / "c.csv"
    comma.write_text("\n".join(",".join(map(str, r)) for r in ROWS) + "\n")
    trajnet = load_trajnet(write_trajnet(tmp_path / "d.ndjson"))
    expected = as_dict(obsmat)
    assert expected[1][0] == pytest.approx([0.0, 0.4, 0.8])
    assert expected[1][1] == [[0.0, 0.0], [0.4, 0.0], [0.8, 0.0]]
    assert as_dict(load_four_column(tab)) == expected
    assert as_dict(load_four_column(comma)) == expected
    assert as_dict(trajnet) == expected  # the second scene's duplicate rows are dropped
    assert obsmat.format == "obsmat" and trajnet.format == "trajnet"


def test_frame_period_defaults_and_override(tmp_path: Path) -> None:
    path = write_obsmat(tmp_path / "x_obsmat.txt")
    assert load_obsmat(path).frame_period == 0.04
    assert load_obsmat(path, frame_period=0.1).track(1).times.tolist() == pytest.approx(
        [0.0, 1.0, 2.0]
    )
    # Trajnet++: 1 / (fps · frame step); 5 rows/s with frames stepping by 10 → 0.02 s.
    assert load_trajnet(write_trajnet(tmp_path / "f.ndjson", fps=5.0)).frame_period == 0.02
    assert load_trajnet(write_trajnet(tmp_path / "g.ndjson", fps=None)).frame_period == 0.04
    with pytest.raises(RecordingFormatError, match="frame_period"):
        load_obsmat(path, frame_period=0.0)


def test_detect_format_and_groups(tmp_path: Path) -> None:
    path = write_obsmat(tmp_path / "seq_obsmat.txt")
    (tmp_path / "seq_groups.txt").write_text("1 2\n\n1 99\n")
    assert detect_format(path) == "obsmat"
    # A group naming someone the file never shows keeps only the people present, and the
    # loader says so, naming the list and the id (newcomer trial: dropped silently).
    with pytest.warns(UserWarning, match=r"seq_groups\.txt: 1 group\(s\) name people .*ids 99\)"):
        rec = load_recording(path)
    assert rec.groups == ((1, 2),)
    # A group wholly absent is a slice's, not a mismatch: kept out without a word.
    (tmp_path / "seq_groups.txt").write_text("1 2\n98 99\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load_recording(path).groups == ((1, 2),)
    assert load_recording(path, groups=False).groups == ()
    assert load_groups(tmp_path / "seq_groups.txt") == ((1, 2), (98, 99))


def test_shared_hotel_slice(hotel_slice: Path) -> None:
    rec = load_recording(hotel_slice)
    raw = np.loadtxt(hotel_slice)
    assert len(rec.tracks) == len(np.unique(raw[:, 1]))
    first = raw[raw[:, 1] == raw[0, 1]]
    track = rec.track(int(raw[0, 1]))
    np.testing.assert_allclose(track.times, first[:, 0] * 0.04)
    np.testing.assert_allclose(track.positions, first[:, [2, 4]])
    assert rec.groups  # the sibling hotel_groups.txt was found
    assert all(len(g) >= 2 for g in rec.groups)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("1 1 0 0 0 0 0 0\n2 1 0 0 0 0 0\n", "line 2: 7 columns; expected 8"),
        ("1 1 0 0 0 0 0 0\n\n3 1 x 0 0 0 0 0\n", "line 3: column 3 \\(x\\)"),
        ("1 1 0 0 0 0 0 0\n2 1 0 0 nan 0 0 0\n", "line 2: column 5 \\(y\\)"),
        ("1 1 0 0 0 0 0 0\n1 1 1 0 0 0 0 0\n", "line 2: person 1 appears twice in frame 1"),
        ("1 1 0 0 0 0 0 0\n2 1.5 0 0 0 0 0 0\n", "line 2: id must be an integer"),
        ("1 1 0 0 0 0 0 0 9\n", "line 1: expected 8 columns"),
        ("", "no data rows"),
        ("1 1 0 0 0 0 0 0\n2 1 0 0 0 0 0 0 9\n", "line 2"),
    ],
)
def test_obsmat_errors_name_file_and_line(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "bad_obsmat.txt"
    path.write_text(text)
    with pytest.raises(RecordingFormatError, match=match) as info:
        load_obsmat(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize(
    ("line", "match"),
    [
        ("{not json", "line 2: not JSON"),
        ('{"track": {"f": 0, "p": 1, "x": 0.0}}', "line 2: track record has no 'y'"),
        ('{"track": {"f": 0, "p": 1, "x": "a", "y": 0}}', "line 2: track.x must be"),
        ('{"other": 1}', "line 2: expected a 'scene' or 'track'"),
    ],
)
def test_trajnet_errors_name_file_and_line(tmp_path: Path, line: str, match: str) -> None:
    path = tmp_path / "bad.ndjson"
    path.write_text('{"scene": {"id": 0, "p": 1, "s": 0, "e": 1}}\n' + line + "\n")
    with pytest.raises(RecordingFormatError, match=match) as info:
        load_trajnet(path)
    assert str(path) in str(info.value)


def test_missing_file_and_unknown_columns(tmp_path: Path) -> None:
    with pytest.raises(RecordingFormatError, match="no such file"):
        load_recording(tmp_path / "nope.txt")
    path = tmp_path / "six.txt"
    path.write_text("1 2 3 4 5 6\n")
    with pytest.raises(RecordingFormatError, match="line 1: 6 columns"):
        load_recording(path)
    groups = tmp_path / "g.txt"
    groups.write_text("1 2\n3 b\n")
    with pytest.raises(RecordingFormatError, match="line 2"):
        load_groups(groups)


# --- newcomer trial: what a recording file may look like, and what gets a clear error -------


def test_a_blank_first_line_and_commas_are_read_as_usual(tmp_path: Path) -> None:
    # a blank first line made pandas take the file for one column ("Expected 1 fields in line
    # 2, saw 8"); a comma-separated obsmat was read as one column
    plain = load_obsmat(write_obsmat(tmp_path / "plain_obsmat.txt"))
    blank = tmp_path / "blank_obsmat.txt"
    blank.write_text("\n" + (tmp_path / "plain_obsmat.txt").read_text())
    commas = tmp_path / "commas_obsmat.txt"
    commas.write_text("".join(f"{f},{i},{x},0,{y},0,0,0\n" for f, i, x, y in ROWS))
    for path in (blank, commas):
        assert as_dict(load_recording(path)) == as_dict(plain)


def test_a_row_with_an_extra_column_names_its_line(tmp_path: Path) -> None:
    path = write_obsmat(tmp_path / "extra_obsmat.txt")
    lines = path.read_text().splitlines()
    lines[2] += " 7.0"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(RecordingFormatError, match=r"extra_obsmat.txt: line 3: expected 8 col"):
        load_recording(path)


@pytest.mark.parametrize("suffix", ["_obsmat.txt", ".ndjson", "_groups.txt"])
def test_bytes_that_are_not_text_are_refused_with_the_line(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"binary{suffix}"
    path.write_bytes(b"1 1 0 0 0 0 0 0\n\xff\xfe\x00garbage\n")
    load = load_groups if suffix == "_groups.txt" else load_recording
    with pytest.raises(RecordingFormatError, match=r"binary.*: line 2: not a text file"):
        load(path)


@pytest.mark.parametrize("fps", [0, -2.5])
def test_a_trajnet_scene_rate_must_be_positive(tmp_path: Path, fps: float) -> None:
    path = write_trajnet(tmp_path / "rate.ndjson", fps=fps)
    with pytest.raises(RecordingFormatError, match=r"rate.ndjson: line 1: scene.fps must be pos"):
        load_recording(path)


@pytest.mark.parametrize("bad", ["4.7", "x", "nan", "1e400"])
def test_group_ids_must_be_integers(tmp_path: Path, bad: str) -> None:
    path = tmp_path / "groups.txt"
    path.write_text(f"1 2\n3 {bad}\n")
    with pytest.raises(RecordingFormatError, match=rf"groups.txt: line 2: .*integers.*{bad}"):
        load_groups(path)
    path.write_text("1 2\n3 4.0\n")
    assert load_groups(path) == ((1, 2), (3, 4))


def test_lone_carriage_returns_end_lines_too(tmp_path: Path) -> None:
    # second newcomer trial: a file saved with classic Mac OS line ends read as one person with
    # one sample, without a word
    plain = load_obsmat(write_obsmat(tmp_path / "plain_obsmat.txt"))
    for end in ("\r", "\r\n"):
        path = tmp_path / "cr_obsmat.txt"
        path.write_bytes((tmp_path / "plain_obsmat.txt").read_bytes().replace(b"\n", end.encode()))
        assert as_dict(load_recording(path)) == as_dict(plain)


def test_group_lists_take_commas_and_refuse_a_person_twice(tmp_path: Path) -> None:
    path = tmp_path / "groups.txt"
    path.write_text("1,2\n3, 4 5\n")
    assert load_groups(path) == ((1, 2), (3, 4, 5))
    path.write_text("1 2\n3 3\n")
    with pytest.raises(RecordingFormatError, match=r"groups\.txt: line 2: person 3 listed twice"):
        load_groups(path)


@pytest.mark.parametrize(
    ("line", "match"),
    [
        ('{"scene": "abc"}', "line 1: 'scene' must be an object"),
        ('{"track": {"f": 0, "p": 99999999999999999999999, "x": 0, "y": 0}}', "too large"),
    ],
)
def test_trajnet_records_that_would_be_misread(tmp_path: Path, line: str, match: str) -> None:
    path = tmp_path / "odd.ndjson"
    path.write_text(line + "\n" + '{"track": {"f": 0, "p": 1, "x": 0.0, "y": 0.0}}\n')
    with pytest.raises(RecordingFormatError, match=match):
        load_recording(path)


def test_text_ids_beyond_exact_integers_are_refused(tmp_path: Path) -> None:
    path = tmp_path / "huge.txt"
    path.write_text("0 1 0.0 0.0\n10 1e20 0.4 0.0\n")
    with pytest.raises(RecordingFormatError, match=r"huge\.txt: line 2: id is too large"):
        load_recording(path)

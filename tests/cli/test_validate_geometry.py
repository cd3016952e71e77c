"""``socialnav validate`` checks geometry and refuses hostile files with a clear error."""

from __future__ import annotations

import time

import pytest
from typer.testing import CliRunner

from socialnav.cli import app
from socialnav.sim.scenario import MAX_SCENARIO_BYTES

ROOM = """name: room
family: hallway
description: a 6 m x 4 m room with a box
map:
  walls:
  - [[0.0, 0.0], [6.0, 0.0]]
  - [[0.0, 4.0], [6.0, 4.0]]
  - [[0.0, 0.0], [0.0, 4.0]]
  - [[6.0, 0.0], [6.0, 4.0]]
  polygons:
  - [[3.0, 1.5], [4.0, 1.5], [4.0, 2.5], [3.0, 2.5]]
{extra}start: {start}
goal: {goal}
people:
- id: 1
  position: {person}
  behavior: {{type: stand}}
time_limit: 30.0
control_period: 0.1
goal_tolerance: 0.3
"""


def _write(tmp_path, name="s.yaml", start="[1.0, 2.0, 0.0]", goal="[5.0, 2.0, 0.0]",
           person="[2.0, 3.0]", extra=""):  # fmt: skip
    path = tmp_path / name
    path.write_text(ROOM.format(start=start, goal=goal, person=person, extra=extra))
    return path


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def test_a_clean_scene_validates(tmp_path):
    res = invoke("validate", str(_write(tmp_path)))
    assert res.exit_code == 0, res.output
    assert "ok" in res.output


@pytest.mark.parametrize(
    ("kw", "field", "what"),
    [
        ({"start": "[3.5, 2.0, 0.0]"}, "start", "inside a wall or obstacle"),
        ({"goal": "[3.2, 1.8, 0.0]"}, "goal", "inside a wall or obstacle"),
        ({"person": "[3.5, 2.2]"}, "people.0.position", "inside a wall or obstacle"),
        ({"goal": "[9.0, 2.0, 0.0]"}, "goal", "outside the map"),
        ({"start": "[0.0, 2.0, 0.0]"}, "start", "inside a wall or obstacle"),
    ],
)
def test_geometry_problems_name_file_and_field(tmp_path, kw, field, what):
    path = _write(tmp_path, **kw)
    res = invoke("validate", str(path))
    assert res.exit_code != 0
    assert f"{path}: {field}:" in res.output and what in res.output, res.output
    assert "Traceback" not in res.output


def test_a_missing_ros_map_file_is_named(tmp_path):
    path = _write(tmp_path, extra="")
    text = path.read_text().replace("map:\n", "map:\n  ros_map: nowhere.yaml\n", 1)
    path.write_text(text)
    res = invoke("validate", str(path))
    assert res.exit_code != 0
    assert "map.ros_map" in res.output and "nowhere.yaml" in res.output, res.output


@pytest.mark.parametrize(
    ("content", "expected"),
    [
        (bytes(range(256)) * 40, "not a text file"),
        (b"\xff\xfe garbage \xc3\x28", "not UTF-8"),
        (b"a: " + b"[" * 50_000 + b"]" * 50_000, "nested deeper"),
        (b"a:\n" + b"".join(b"  " * i + b"- \n" for i in range(1, 400)), "nested deeper"),
    ],
)
def test_hostile_files_get_a_clear_error(tmp_path, content, expected):
    path = tmp_path / "bad.yaml"
    path.write_bytes(content)
    res = invoke("validate", str(path))
    assert res.exit_code != 0
    assert expected in res.output, res.output
    assert "Traceback" not in res.output


def test_a_file_over_the_size_limit_is_refused_before_parsing(tmp_path):
    path = tmp_path / "huge.yaml"
    with path.open("wb") as f:
        f.write(b"people:\n")
        f.write(b"- {id: 1, position: [0.0, 0.0]}\n" * (MAX_SCENARIO_BYTES // 30 + 10))
    started = time.perf_counter()
    res = invoke("validate", str(path))
    assert time.perf_counter() - started < 2.0
    assert res.exit_code != 0 and "limit" in res.output, res.output


def test_a_map_image_whose_header_claims_an_enormous_size(tmp_path):
    (tmp_path / "map.pgm").write_bytes(b"P5\n200000 200000\n255\n" + b"\x00" * 64)
    (tmp_path / "map.yaml").write_text(
        "image: map.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    path = _write(tmp_path)
    path.write_text(path.read_text().replace("map:\n", "map:\n  ros_map: map.yaml\n", 1))
    res = invoke("validate", str(path))
    assert res.exit_code != 0
    assert "map.ros_map" in res.output and "image" in res.output, res.output
    assert "Traceback" not in res.output

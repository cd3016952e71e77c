"""Scenario files: built-ins, geometry against scenarios.md, validation errors, randomization."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import PR2
from socialnav.sim.scenario import (
    Scenario,
    builtin_scenarios,
    load_scenario,
    occupancy_boundaries,
    scenario_json_schema,
)
from socialnav.world.grid import LETHAL, GridGeometry

EXPECTED = {
    "hallway_stationary",
    "hallway_overtake",
    "hallway_oncoming",
    "hallway_headon",
    "hallway_passing",
    "gallery_present",
    "gallery_activity",
    "queue_line",
    "queue_shifted",
    "queue_rotated",
    "group_join",
    "group_join_back",
    "group_lead",
}


def test_all_builtins_load_and_validate() -> None:
    assert set(builtin_scenarios()) == EXPECTED
    for name in builtin_scenarios():
        s = load_scenario(name)
        assert s.name == name
        assert s.time_limit == 60.0 and s.control_period == 0.1
        ctx = s.social_context()
        assert len(ctx.people) == len(s.people)
        assert all(p.radius == 0.25 for p in ctx.people)
        # Round trip through the model's own dump.
        assert Scenario.model_validate(s.model_dump()).with_source(s.source) == s


def test_families() -> None:
    fam = {n: load_scenario(n).family for n in builtin_scenarios()}
    assert fam["hallway_passing"] == "hallway"
    assert fam["queue_rotated"] == "queue" and fam["group_lead"] == "group"
    assert fam["gallery_present"] == "gallery_present"


def test_hallway_geometry() -> None:
    s = load_scenario("hallway_stationary")
    walls = s.walls_array()
    # the two long walls of scenarios.md, then end caps that close the corridor
    np.testing.assert_allclose(
        walls,
        [
            [[0, -1.5], [20, -1.5]],
            [[0, 1.5], [20, 1.5]],
            [[0, -1.5], [0, 1.5]],
            [[20, -1.5], [20, 1.5]],
        ],
    )
    assert s.start == (1.0, 0.0, 0.0) and s.goal[:2] == (19.0, 0.0)
    assert s.people[0].position == (10.0, 0.2)
    assert s.people[0].heading == pytest.approx(-math.pi / 2, abs=1e-4)
    onc = load_scenario("hallway_oncoming").people[0]
    np.testing.assert_allclose(onc.initial_velocity(), [-1.0, 0.0])
    assert onc.position == (19.0, 0.75)
    ovt = load_scenario("hallway_overtake").people[0]
    np.testing.assert_allclose(ovt.end_point(), [19.0, 0.2])
    np.testing.assert_allclose(ovt.initial_velocity(), [0.25, 0.0])
    p = load_scenario("hallway_passing")
    assert p.start[:2] == (0.5, -0.45) and p.goal[:2] == (5.5, -0.45)
    assert p.people[0].position == (6.0, 0.45)
    assert p.jitter.speed_uniform == 0.05 and p.jitter.start_shift == 0.2


def test_gallery_queue_group_geometry() -> None:
    g = load_scenario("gallery_present")
    art = g.social_context().artworks[0]
    assert art.center == (13.0, 25.0) and art.width == 1.2
    assert art.facing == pytest.approx(-math.pi / 2, abs=1e-4)
    assert g.people[0].position == (13.0, 23.5) and g.goal[:2] == (13.0, 24.4)
    room = load_scenario("group_join").walls_array()
    assert room.min() == 0.0 and room.max() == 25.0 and room.shape == (4, 2, 2)

    q = load_scenario("queue_rotated")
    desk = q.obstacle_polygons()[0]
    np.testing.assert_allclose(desk.mean(axis=0), [18.0, 18.0], atol=1e-9)
    # The desk's short axis (its facing) is along the diagonal: front edge centre at 0.3 m SW.
    edges = np.linalg.norm(np.roll(desk, -1, axis=0) - desk, axis=1)
    np.testing.assert_allclose(sorted(edges), [0.6, 0.6, 1.6, 1.6], atol=1e-4)
    np.testing.assert_allclose(
        [p.position for p in q.people],
        [(17.36, 17.36), (16.80, 16.80), (16.23, 16.23), (15.67, 15.67)],
    )
    assert q.queues[0].members == [1, 2, 3, 4] and q.goal[:2] == (17.43, 17.43)
    # Queue people face the desk.
    for p in q.people:
        assert p.heading == pytest.approx(math.pi / 4, abs=1e-4)

    for name, radius, angles in (
        ("group_join", 0.9, (90, 180, 270)),
        ("group_join_back", 0.9, (0, 90, 270)),
        ("group_lead", 1.2, (150, 180, 210)),
    ):
        s = load_scenario(name)
        pos = np.array([p.position for p in s.people])
        np.testing.assert_allclose(np.linalg.norm(pos - 12.5, axis=1), radius, atol=1e-4)
        got = np.degrees(np.arctan2(pos[:, 1] - 12.5, pos[:, 0] - 12.5)) % 360
        np.testing.assert_allclose(np.sort(got), sorted(a % 360 for a in angles), atol=1e-3)
        for p, xy in zip(s.people, pos, strict=True):  # facing the centre
            want = math.atan2(12.5 - xy[1], 12.5 - xy[0])
            assert math.cos(p.heading - want) == pytest.approx(1.0, abs=1e-6)
        assert s.goal[:2] == (12.5, 12.5)
    assert load_scenario("group_lead").groups[0].mode == "lead"


def _write(tmp_path: Path, data: dict, name: str = "bad.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data))
    return path


def _base() -> dict:
    return load_scenario("group_join").model_dump(mode="json")


@pytest.mark.parametrize(
    ("mutate", "field"),
    [
        (lambda d: d.update(speed=3), "speed"),  # unknown top-level key
        (lambda d: d["people"][0].update(position=[float("nan"), 1.0]), "people.0.position.0"),
        (lambda d: d["people"][0].update(radius=-0.1), "people.0.radius"),
        (lambda d: d["groups"][0].update(members=[1, 2, 99]), "groups.0.members"),
        (lambda d: d["people"][1].update(id=1), "duplicate ids"),
        (lambda d: d["people"][0].update(behavior={"type": "walk"}), "people.0.behavior"),
        (lambda d: d.update(family="mall"), "family"),
        (lambda d: d["map"]["walls"][0].append([1, 2]), "map.walls.0"),
    ],
)
def test_malformed_files_name_file_and_field(tmp_path: Path, mutate, field: str) -> None:
    data = _base()
    mutate(data)
    path = _write(tmp_path, data)
    with pytest.raises(ConfigurationError) as err:
        load_scenario(path)
    msg = str(err.value)
    assert msg.startswith(f"{path}: ")  # the path as given, as the geometry checks say it
    assert field in msg


def test_invalid_yaml_and_unknown_name(tmp_path: Path) -> None:
    path = tmp_path / "broken.yaml"
    path.write_text("name: [unclosed\n")
    with pytest.raises(ConfigurationError, match=r"broken\.yaml"):
        load_scenario(path)
    with pytest.raises(ConfigurationError, match="Did you mean 'queue_line'"):
        load_scenario("queue_lien")


def test_walk_until_behind_start_rejected(tmp_path: Path) -> None:
    data = load_scenario("hallway_overtake").model_dump(mode="json")
    data["people"][0]["behavior"]["until"] = [1.0, 0.2]
    with pytest.raises(ConfigurationError, match=r"bad.yaml: people.0: .*behind"):
        load_scenario(_write(tmp_path, data))


def test_json_schema_exports() -> None:
    schema = scenario_json_schema()
    text = json.dumps(schema)
    assert schema["type"] == "object"
    assert {"people", "map", "start", "goal", "groups", "queues", "artworks"} <= set(
        schema["properties"]
    )
    assert schema.get("additionalProperties") is False
    assert "walk" in text and "stand" in text


def test_randomize_reproducible() -> None:
    s = load_scenario("hallway_passing")
    a, b, c = s.randomize(3), s.randomize(3), s.randomize(4)
    assert a == b
    assert a != c
    for r in (a, c):
        p = r.people[0]
        speed = float(np.hypot(*p.initial_velocity()))
        assert 0.45 <= speed <= 0.55
        assert 5.8 <= p.position[0] <= 6.2 and p.position[1] == 0.45
        np.testing.assert_allclose(p.end_point(), [0.0, 0.45], atol=1e-9)
    # Without jitter a scenario is unchanged by randomize (except the recorded seed).
    q = load_scenario("queue_line")
    assert q.randomize(7).people == q.people


def test_randomize_group_sizes() -> None:
    s = load_scenario("group_join")
    sizes = set()
    for seed in range(12):
        r = s.randomize(seed, vary_group_sizes=True)
        members = r.groups[0].members
        sizes.add(len(members))
        pos = np.array([r.person(i).position for i in members])
        np.testing.assert_allclose(np.linalg.norm(pos - 12.5, axis=1), 0.9, atol=1e-6)
        # The gap stays at 0° (facing the robot): no member within 45° of +x.
        ang = np.degrees(np.arctan2(pos[:, 1] - 12.5, pos[:, 0] - 12.5))
        assert np.all(np.abs(ang) >= 89.0)
    assert sizes == {2, 3, 4}
    assert s.randomize(5, vary_group_sizes=True) == s.randomize(5, vary_group_sizes=True)


def test_static_costmap_has_walls_and_desk_not_people() -> None:
    s = load_scenario("queue_line")
    cm = s.static_costmap(PR2, resolution=0.05)
    assert cm.cost_at(np.array([12.5, 20.3])) == LETHAL  # desk centre
    assert cm.cost_at(np.array([0.0, 10.0])) == LETHAL  # west wall
    assert cm.cost_at(np.array([12.5, 17.8])) == 0  # a person: not in the static map
    assert cm.cost_at(np.array([6.0, 14.0])) == 0


def test_occupancy_boundaries_of_a_block() -> None:
    occ = np.zeros((4, 5), dtype=bool)
    occ[1:3, 1:4] = True  # a 3 × 2 block
    segs = occupancy_boundaries(occ, GridGeometry((4, 5), 0.5, (10.0, 20.0)))
    assert segs.shape == (4, 2, 2)
    length = np.linalg.norm(segs[:, 1] - segs[:, 0], axis=1).sum()
    assert length == pytest.approx(2 * (1.5 + 1.0))
    assert segs[..., 0].min() == pytest.approx(10.5) and segs[..., 1].max() == pytest.approx(21.5)


def test_ros_map_scenario(tmp_path: Path) -> None:
    from socialnav.world.mapio import OccupancyMap, save_map

    geom = GridGeometry((40, 60), 0.1, (0.0, 0.0))
    occ = np.zeros(geom.shape, dtype=bool)
    occ[:, 30] = True  # a wall at x = 3.0 .. 3.1
    save_map(OccupancyMap.from_masks(occ, geom), tmp_path / "map.yaml")
    data = {
        "name": "roomy",
        "family": "custom",
        "map": {"ros_map": "map.yaml"},
        "start": [1, 2, 0],
        "goal": [5, 2, 0],
    }
    s = load_scenario(_write(tmp_path, data, "roomy.yaml"))
    walls = s.walls_array()
    xs = walls[..., 0]
    assert np.any(np.isclose(xs, 3.0)) and np.any(np.isclose(xs, 3.1))
    cm = s.static_costmap(PR2)
    assert cm.geometry == geom
    assert cm.cost_at(np.array([3.05, 2.0])) == LETHAL
    assert cm.cost_at(np.array([1.0, 2.0])) == 0
    bad = _write(tmp_path, {**data, "map": {"ros_map": "missing.yaml"}}, "nomap.yaml")
    with pytest.raises(ConfigurationError, match=r"nomap.yaml: map.ros_map"):
        load_scenario(bad).walls_array()

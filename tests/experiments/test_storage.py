"""Episode files round trip: ``load_episode(save_episode(r))`` equals ``r`` (Parquet and CSV)."""

from __future__ import annotations

import json
from dataclasses import fields
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from socialnav.core.episode import EpisodeRecord
from socialnav.core.errors import InvalidInputError
from socialnav.core.robot import PIONEER, PR2
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.experiments.storage import (
    EPISODE_FILE,
    TRAJECTORY_FILE,
    load_episode,
    save_episode,
    trajectory_table,
)


def rich_record(steps: int = 23, seed: int = 0) -> EpisodeRecord:
    """Irrational-looking floats, non-contiguous person ids and every kind of social structure."""
    rng = np.random.default_rng(seed)
    ids = np.array([3, 7, 11, 12, 20])
    people = tuple(
        Person(
            int(i),
            tuple(rng.normal(size=2)),
            tuple(rng.normal(size=2)),
            float(rng.normal()),
            0.2 + 0.01 * k,
        )
        for k, i in enumerate(ids)
    )
    context = SocialContext(
        people=people,
        groups=(Group((3, 7), "lead"),),
        queues=(Queue((11, 12), (1.0 / 3.0, -2.5), 0.75),),
        artworks=(Artwork((4.0, np.pi), 1.2, -np.pi / 2, (20,)),),
    )
    status = np.array(["OK", "RECOVERING", "ROTATING_TO_GOAL", "GOAL_REACHED"] * steps)[:steps]
    collisions = np.zeros(steps, dtype=bool)
    collisions[[4, 5]] = True
    return EpisodeRecord(
        dt=0.1,
        times=0.1 * np.arange(steps),
        robot_poses=rng.normal(size=(steps, 3)),
        robot_twists=rng.normal(size=(steps, 3)),
        robot_footprint=PIONEER.polygon,
        robot_radius=PIONEER.circumscribed_radius,
        people_ids=ids,
        people_positions=rng.normal(size=(steps, len(ids), 2)),
        people_velocities=rng.normal(size=(steps, len(ids), 2)),
        people_radii=np.array([p.radius for p in people]),
        start=np.array([0.1, 0.2, 0.3]),
        goal=np.array([5.0, -1.0 / 7.0, np.pi]),
        target=np.array([4.5, -0.3, -np.pi / 3]),
        goal_tolerance=0.25,
        time_limit=90.0,
        family="gallery_activity",
        scenario="storage_test",
        context=context,
        waypoint=np.array([2.0, 1.0 / 3.0]),
        walls=rng.normal(size=(4, 2, 2)),
        obstacles=(rng.normal(size=(4, 2)), rng.normal(size=(24, 2))),
        collision_person=collisions,
        collision_obstacle=np.roll(collisions, 7),
        status=status,
        meta={
            "planner": "paccet",
            "robot": "pioneer",
            "seed": seed,
            "termination": "goal_reached",
            "planner_ms_median": 3.25,
            "social_goal": None,
        },
    )


def empty_hallway(steps: int = 5) -> EpisodeRecord:
    """No people, no waypoint, no obstacles: the degenerate shapes."""
    return EpisodeRecord(
        dt=0.1,
        times=0.1 * np.arange(steps),
        robot_poses=np.column_stack([np.linspace(0, 1, steps), np.zeros(steps), np.zeros(steps)]),
        robot_twists=np.zeros((steps, 3)),
        robot_footprint=PR2.polygon,
        robot_radius=PR2.circumscribed_radius,
        people_ids=np.zeros(0, dtype=int),
        people_positions=np.zeros((steps, 0, 2)),
        people_velocities=np.zeros((steps, 0, 2)),
        people_radii=np.zeros(0),
        start=np.zeros(3),
        goal=np.array([1.0, 0.0, 0.0]),
        target=np.array([1.0, 0.0, 0.0]),
        goal_tolerance=0.1,
        time_limit=10.0,
        family="hallway",
        scenario="empty",
    )


def assert_records_equal(a: EpisodeRecord, b: EpisodeRecord) -> None:
    for f in fields(EpisodeRecord):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if f.name == "obstacles":
            assert len(x) == len(y)
            for p, q in zip(x, y, strict=True):
                np.testing.assert_array_equal(p, q)
        elif f.name == "robot_twists":
            # stored in the world frame like every agent's velocity: rotated there and back
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-12, err_msg=f.name)
        elif isinstance(x, np.ndarray):
            assert isinstance(y, np.ndarray), f.name
            assert x.shape == y.shape, f.name
            if x.dtype.kind in "fiub":
                assert y.dtype.kind == x.dtype.kind or {x.dtype.kind, y.dtype.kind} <= {"i", "u"}
            np.testing.assert_array_equal(x, y, err_msg=f.name)
        else:
            assert x == y, f.name


@pytest.mark.parametrize("fmt", ["parquet", "csv"])
@pytest.mark.parametrize("make", [rich_record, empty_hallway])
def test_save_then_load_gives_an_equal_record(tmp_path: Path, fmt: str, make) -> None:
    record = make()
    folder = save_episode(record, tmp_path / "episode", fmt=fmt)
    assert folder == tmp_path / "episode"
    table_file = TRAJECTORY_FILE if fmt == "parquet" else "trajectory.csv"
    assert sorted(p.name for p in folder.iterdir()) == sorted([EPISODE_FILE, table_file])
    loaded = load_episode(folder)
    assert_records_equal(record, loaded)
    assert loaded.context == record.context  # people, groups, queues, artworks
    assert loaded.num_steps == record.num_steps


def test_the_context_keeps_every_social_structure(tmp_path: Path) -> None:
    loaded = load_episode(save_episode(rich_record(), tmp_path))
    assert loaded.context.groups == (Group((3, 7), "lead"),)
    assert loaded.context.queues[0].service_point == (1.0 / 3.0, -2.5)
    assert loaded.context.artworks[0].viewer_ids == (20,)
    assert loaded.context.person(20).radius == pytest.approx(0.24)


def test_trajectory_is_a_long_table_one_row_per_agent_and_step(tmp_path: Path) -> None:
    record = rich_record(steps=9)
    save_episode(record, tmp_path)
    table = pq.read_table(tmp_path / TRAJECTORY_FILE)
    assert table.num_rows == 9 * (1 + 5)
    assert table.column_names[:6] == ["step", "t", "agent", "agent_id", "x", "y"]
    assert {"heading", "vx", "vy", "wz", "status"} <= set(table.column_names)
    rows = table.to_pylist()
    assert [(r["agent"], r["agent_id"]) for r in rows[:6]] == [
        ("robot", 0),
        *[("person", int(i)) for i in record.people_ids],
    ]
    for r in rows:
        if r["agent"] == "person":
            k = list(record.people_ids).index(r["agent_id"])
            assert r["vy"] == record.people_velocities[r["step"], k, 1]
            assert r["heading"] == record.people_headings[r["step"], k]
            assert r["wz"] is None and r["status"] is None and r["collision_person"] is None
        else:
            yaw = record.robot_poses[r["step"], 2]
            speed = np.hypot(*record.robot_twists[r["step"], :2])
            assert r["heading"] == yaw and np.hypot(r["vx"], r["vy"]) == pytest.approx(speed)
            assert r["status"] == record.status[r["step"]]
    assert trajectory_table(record).equals(table)


def test_people_present_for_part_of_an_episode_have_rows_only_while_present(
    tmp_path: Path,
) -> None:
    record = rich_record(steps=10)
    absent = np.zeros((10, 5), dtype=bool)
    absent[:3, 1] = True  # person 7 appears at step 3
    absent[6:, 4] = True  # person 20 leaves after step 5
    record.people_positions[absent] = np.nan
    record.people_velocities[absent] = np.nan
    record.people_headings[absent] = np.nan
    table = trajectory_table(record)
    seen = [(r["step"], r["agent_id"]) for r in table.to_pylist() if r["agent"] == "person"]
    assert len(seen) == 10 * 5 - 3 - 4
    assert (0, 7) not in seen and (3, 7) in seen and (5, 20) in seen and (6, 20) not in seen
    for fmt in ("parquet", "csv"):
        loaded = load_episode(save_episode(record, tmp_path / fmt, fmt=fmt))
        np.testing.assert_array_equal(np.isnan(loaded.people_positions[..., 0]), absent)
        assert_records_equal(record, loaded)


def test_people_headings_default_to_the_direction_of_motion() -> None:
    record = empty_hallway()
    v = np.zeros((4, 1, 2))
    v[1:3, 0] = (0.0, 1.0)
    record = EpisodeRecord(
        **{
            **{f.name: getattr(empty_hallway(4), f.name) for f in fields(EpisodeRecord)},
            "people_ids": np.array([1]),
            "people_positions": np.zeros((4, 1, 2)),
            "people_velocities": v,
            "people_radii": np.array([0.25]),
            "people_headings": None,
            "context": SocialContext(people=(Person(1, (0.0, 0.0), yaw=0.5),)),
        }
    )
    # the context's yaw before the first move, then the motion, then held while standing
    np.testing.assert_allclose(record.people_headings[:, 0], [0.5, np.pi / 2, np.pi / 2, np.pi / 2])


def test_episode_json_is_plain_json_and_names_the_format(tmp_path: Path) -> None:
    save_episode(rich_record(), tmp_path, fmt="csv")
    static = json.loads((tmp_path / EPISODE_FILE).read_text())
    assert static["trajectory_format"] == "csv"
    assert static["people_ids"] == [3, 7, 11, 12, 20]
    assert static["meta"]["planner"] == "paccet"


def test_different_records_do_not_load_equal(tmp_path: Path) -> None:
    a = load_episode(save_episode(rich_record(seed=0), tmp_path / "a"))
    b = load_episode(save_episode(rich_record(seed=1), tmp_path / "b"))
    with pytest.raises(AssertionError):
        assert_records_equal(a, b)


def test_an_unknown_format_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="xml"):
        save_episode(rich_record(), tmp_path, fmt="xml")


def _saved_with(tmp_path: Path, edit) -> Path:
    """An episode folder whose ``episode.json`` went through ``edit(static)`` after saving."""
    folder = save_episode(rich_record(), tmp_path / "episode")
    path = folder / EPISODE_FILE
    static = json.loads(path.read_text())
    edit(static)
    path.write_text(json.dumps(static))
    return folder


def test_bug_a_malformed_episode_json_did_not_name_the_file(tmp_path: Path) -> None:
    folder = save_episode(rich_record(), tmp_path / "episode")
    path = folder / EPISODE_FILE
    path.write_text('{"dt": 0.1,')  # cut short
    with pytest.raises(InvalidInputError, match=r"episode\.json: not valid JSON"):
        load_episode(folder)
    path.write_text("[1, 2]")
    with pytest.raises(InvalidInputError, match=r"episode\.json: .*JSON object"):
        load_episode(folder)


def test_an_episode_json_without_a_field_names_the_file_and_the_field(tmp_path: Path) -> None:
    def edit(static: dict) -> None:
        del static["people_ids"], static["time_limit"]

    folder = _saved_with(tmp_path, edit)
    with pytest.raises(InvalidInputError, match=r"episode\.json: .*'people_ids', 'time_limit'"):
        load_episode(folder)


def test_a_trajectory_row_of_someone_not_in_the_episode_names_the_table(tmp_path: Path) -> None:
    def edit(static: dict) -> None:
        static["people_ids"] = static["people_ids"][:-1]
        static["people_radii"] = static["people_radii"][:-1]

    folder = _saved_with(tmp_path, edit)
    with pytest.raises(InvalidInputError, match=rf"{TRAJECTORY_FILE}: .*person 20"):
        load_episode(folder)


def test_a_missing_step_table_names_the_file_and_says_it_is_missing(tmp_path: Path) -> None:
    folder = save_episode(rich_record(), tmp_path / "episode")
    (folder / TRAJECTORY_FILE).unlink()
    with pytest.raises(FileNotFoundError, match=rf"{TRAJECTORY_FILE}: no such file"):
        load_episode(folder)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("dt", "0.1", "'dt' must be a positive number"),
        ("dt", 0, "'dt' must be a positive number"),
        ("robot_footprint", [[1]], "'robot_footprint' must be a polygon"),
        ("meta", [1, 2], "'meta' must be an object"),
        ("people_ids", None, "'people_ids' must be a list of integers"),
        ("people_ids", [3, 7, 11, 12, "20"], "'people_ids' must be a list of integers"),
        ("people_radii", [0.3], "'people_radii' must list one radius per id"),
    ],
)
def test_a_field_of_the_wrong_type_or_shape_names_the_file_and_the_field(
    tmp_path: Path, field: str, value: object, message: str
) -> None:
    # each of these loaded (or raised a bare TypeError) and broke a metric later
    folder = _saved_with(tmp_path, lambda static: static.update({field: value}))
    with pytest.raises(InvalidInputError, match=rf"episode\.json: field {message}"):
        load_episode(folder)


def test_a_folder_given_as_a_string_loads_and_a_missing_file_says_so(tmp_path: Path) -> None:
    folder = save_episode(rich_record(), tmp_path / "episode")
    assert_records_equal(load_episode(str(folder)), load_episode(folder))
    (folder / EPISODE_FILE).unlink()
    with pytest.raises(FileNotFoundError, match=r"episode\.json: no such file"):
        load_episode(folder)

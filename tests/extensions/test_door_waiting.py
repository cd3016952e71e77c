"""A new social-structure kind is one module (``door_waiting.py``) plus this test: the scenario
schema, the social goal, the planner, the success check, storage and the figure pick it up."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml
from typer.testing import CliRunner

import extensions.door_waiting as door_waiting
from socialnav.cli import app
from socialnav.experiments.storage import load_episode, save_episode
from socialnav.metrics.success import evaluate_success
from socialnav.sim.runner import run_episode
from socialnav.sim.scenario import scenario_from_dict, scenario_json_schema
from socialnav.social.resolve import resolve_social_goal
from socialnav.viz.topdown import plot_episode

assert door_waiting.DoorWaiting.name == "door_waiting"  # the import registers the kind


def lobby(**overrides) -> dict:
    """A 10 m × 8 m lobby; a door in the top wall at (5, 8); two people wait left of it."""
    data = {
        "name": "door_lobby",
        "family": "custom",
        "map": {
            "walls": [
                [[0, 0], [10, 0]],
                [[10, 0], [10, 8]],
                [[10, 8], [0, 8]],
                [[0, 8], [0, 0]],
            ]
        },
        "start": [5.0, 1.5, 1.5708],
        "goal": [5.0, 7.0, 1.5708],
        "people": [
            {"id": 1, "position": [3.6, 7.0], "yaw": 0.0},
            {"id": 2, "position": [3.0, 6.4], "yaw": 0.5},
        ],
        "structures": [
            {"type": "door_waiting", "door": [5.0, 8.0], "facing": -1.5708, "members": [1, 2]}
        ],
        "time_limit": 40.0,
    }
    data.update(overrides)
    return data


def test_the_schema_and_validation_come_from_the_kind():
    schema = scenario_json_schema()
    kinds = schema["properties"]["structures"]["items"]["oneOf"]
    door = next(k for k in kinds if k["properties"]["type"] == {"const": "door_waiting"})
    assert {"door", "facing", "members"} <= set(door["properties"])
    with pytest.raises(ValueError, match=r"structures: .*0\.door"):
        scenario_from_dict(lobby(structures=[{"type": "door_waiting", "door": [5], "facing": 0}]))
    with pytest.raises(ValueError, match="unknown person ids"):
        scenario_from_dict(
            lobby(
                structures=[{"type": "door_waiting", "door": [5, 8], "facing": 0, "members": [9]}]
            )
        )
    scn = scenario_from_dict(lobby())
    assert [c.name for c in scn.success_spec()] == ["reached_goal", "no_collision", "beside_door"]


def test_the_social_goal_is_beside_the_door_away_from_the_waiting_people():
    scn = scenario_from_dict(lobby())
    sg = resolve_social_goal(scn.social_context(), np.array(scn.goal), np.array(scn.start))
    assert sg is not None and sg.kind == "door_side"
    # people wait at x < 5: the robot waits at x = 5 + 1.2, 0.8 m in front of the wall, facing it
    np.testing.assert_allclose(sg.pose[:2], [6.2, 7.2], atol=1e-4)  # 1.5708 ≈ π/2


@pytest.fixture(scope="module")
def episode():
    return run_episode(scenario_from_dict(lobby()), "paccet", "pr2").record


def test_paccet_waits_beside_the_door_and_the_success_check_knows_it(episode):
    np.testing.assert_allclose(episode.target[:2], [6.2, 7.2], atol=1e-4)
    result = evaluate_success(episode)
    assert result["beside_door"] and result["no_collision"] and result["success"]
    go_straight = run_episode(scenario_from_dict(lobby()), "go_to_goal", "pr2").record
    assert evaluate_success(go_straight)["beside_door"] is False  # it stops before the door


def test_storage_and_the_figure_keep_the_structure(episode, tmp_path):
    back = load_episode(save_episode(episode, tmp_path))
    assert back.context.structures == episode.context.structures
    assert back.success == episode.success
    assert evaluate_success(back) == evaluate_success(episode)
    fig = plot_episode(back)
    assert any(
        len(line.get_xdata()) == 2 and line.get_linewidth() == 4 for line in fig.axes[0].lines
    )


def test_a_scenario_file_with_the_kind_runs_from_the_cli(tmp_path):
    path = tmp_path / "lobby.yaml"
    path.write_text(yaml.safe_dump(lobby()))
    result = CliRunner().invoke(
        app, ["run", str(path), "--planner", "paccet", "--out", str(tmp_path / "o")]
    )
    assert result.exit_code == 0, result.output
    conditions = json.loads((tmp_path / "o" / "metrics.json").read_text())["success_conditions"]
    assert conditions["beside_door"] is True

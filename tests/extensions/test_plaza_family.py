"""A new scenario family is one module (``plaza_family.py``) plus this test: its conditions,
the per-scenario overrides in YAML (which are required, their tolerances) and the schema."""

from __future__ import annotations

import pytest

import extensions.plaza_family as plaza
from socialnav.core.success import ConditionSpec
from socialnav.metrics.success import evaluate_success, success_conditions
from socialnav.sim.runner import run_episode
from socialnav.sim.scenario import scenario_from_dict, scenario_json_schema


def plaza_scenario(**overrides) -> dict:
    """12 m × 12 m; the robot crosses left to right; a walker crosses bottom to top 1 m ahead."""
    data = {
        "name": "plaza_cross",
        "family": plaza.NAME,
        "map": {
            "walls": [
                [[0, 0], [12, 0]],
                [[12, 0], [12, 12]],
                [[12, 12], [0, 12]],
                [[0, 12], [0, 0]],
            ]
        },
        "start": [1.0, 6.0, 0.0],
        "goal": [11.0, 6.0, 0.0],
        "people": [
            {
                "id": 1,
                "position": [7.0, 2.0],
                "behavior": {"type": "walk", "velocity": [0.0, 0.8], "until": [7.0, 10.0]},
            }
        ],
        "time_limit": 40.0,
    }
    data.update(overrides)
    return data


def test_the_family_declares_its_conditions_and_is_in_the_schema():
    assert plaza.NAME in scenario_json_schema()["properties"]["family"]["enum"]
    scn = scenario_from_dict(plaza_scenario())
    assert scn.success_spec() == (
        ConditionSpec("reached_goal"),
        ConditionSpec("no_collision"),
        ConditionSpec("kept_clearance"),
    )


def test_a_scenario_overrides_tolerance_and_requirement_in_yaml():
    relaxed = scenario_from_dict(
        plaza_scenario(success={"kept_clearance": {"tolerance": 0.5, "required": False}})
    )
    assert relaxed.success_spec()[-1] == ConditionSpec("kept_clearance", False, 0.5)
    with pytest.raises(ValueError, match="kept_clerance is not a condition of this scenario"):
        scenario_from_dict(plaza_scenario(success={"kept_clerance": {"tolerance": 0.5}}))
    with pytest.raises(ValueError, match="unknown scenario family 'plazza'"):
        scenario_from_dict(plaza_scenario(family="plazza"))


def test_an_episode_is_judged_with_the_scenario_tolerances():
    strict = scenario_from_dict(plaza_scenario(success={"kept_clearance": {"tolerance": 50.0}}))
    record = run_episode(strict, "paccet", "pr2").record
    assert record.success == strict.success_spec()
    result = evaluate_success(record)
    assert result["reached_goal"] and result["no_collision"]
    assert result["kept_clearance"] is False and result["success"] is False  # nobody keeps 50 m
    optional = scenario_from_dict(
        plaza_scenario(success={"kept_clearance": {"tolerance": 50.0, "required": False}})
    )
    record = run_episode(optional, "paccet", "pr2").record
    conditions = {c.name: c for c in success_conditions(record)}
    assert conditions["kept_clearance"].required is False
    assert evaluate_success(record)["success"] is True

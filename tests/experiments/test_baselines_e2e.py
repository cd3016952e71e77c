"""One hallway_passing episode per planner name through ``run_spec``, the suite's unit of work.

Every planner a comparison can name (our presets and navground's behaviours) must run to a row
without error, reach the goal without collision, and give finite Table 1 metrics.
"""

from __future__ import annotations

import math

import pytest

from shared import ALL_PLANNERS
from socialnav.experiments.suite import EpisodeSpec, run_spec

FINITE = (
    "total_distance",
    "time_to_goal",
    "lateral_distance",
    "proxemic_intrusions",
    "path_length",
    "path_length_ratio",
    "min_distance_center",
    "psc_1.2",
)


def test_the_compared_planners_are_the_ones_the_readme_promises() -> None:
    promised = {
        "traditional",
        "proxemic_layer",
        "weighted_social",
        "orca",
        "hl",
        "social_force",
        "paccet_paper",
        "paccet",
    }
    assert set(ALL_PLANNERS) == promised
    assert ALL_PLANNERS[0] == "traditional" and ALL_PLANNERS[-1] == "paccet"  # display order


@pytest.fixture(scope="module")
def rows() -> dict[str, dict]:
    return {p: run_spec(EpisodeSpec("hallway_passing", p, "pr2", seed=0)) for p in ALL_PLANNERS}


@pytest.mark.parametrize("planner", ALL_PLANNERS)
def test_planner_runs_the_hallway_to_the_goal(rows: dict[str, dict], planner: str) -> None:
    row = rows[planner]
    assert row["error"] == ""
    assert row["run_id"] == f"hallway_passing__{planner}__pr2__scripted__s0"
    assert row["family"] == "hallway"
    assert row["steps"] > 10
    for name in FINITE:
        assert math.isfinite(row[f"metric.{name}"]), name
    assert row["ok.reached_goal"] is True
    assert row["ok.no_collision"] is True
    assert row["metric.collisions"] == 0
    # a person never passes through the robot: their centres stay apart by both radii
    assert row["metric.min_distance_center"] > 0.25 + 0.3
    # ends within the 0.1 m goal tolerance of a target 5 m away in a straight line
    assert row["metric.path_length_ratio"] >= (5.0 - 0.1) / 5.0
    assert row["wall_time_s"] > 0


def test_every_planner_reports_planning_time(rows: dict[str, dict]) -> None:
    for planner, row in rows.items():
        assert math.isfinite(row["planner_ms_median"]) and row["planner_ms_median"] > 0, planner


def test_paccet_keeps_the_personal_space_the_traditional_planner_enters(
    rows: dict[str, dict],
) -> None:
    assert rows["paccet"]["ok.success"] is True
    assert rows["paccet"]["metric.proxemic_intrusions"] == 0
    assert rows["traditional"]["ok.no_personal_space_intrusion"] is False
    assert rows["traditional"]["metric.proxemic_intrusions"] >= 1


def test_an_unknown_planner_becomes_an_error_row_not_an_exception() -> None:
    row = run_spec(EpisodeSpec("hallway_passing", "nope", "pr2"))
    assert row["error"].startswith("ConfigurationError")
    assert "'nope'" in row["error"]
    assert not any(k.startswith("metric.") for k in row)

"""One path measures an episode: ``socialnav run``'s metrics.json and the suite's row agree, and
success is judged at the target the controller resolved."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from socialnav.core.robot import PR2
from socialnav.experiments.results import condition_column, metric_column
from socialnav.experiments.run import run_single
from socialnav.experiments.suite import EpisodeSpec, run_spec
from socialnav.planner.presets import footprint_front
from socialnav.sim.runner import run_episode
from socialnav.sim.scenario import load_scenario
from socialnav.sim.target import resolve_target


def test_run_and_suite_measure_the_same(tmp_path):
    run_single("queue_line", "traditional", "pr2", out=tmp_path)
    written = json.loads((tmp_path / "metrics.json").read_text())
    row = run_spec(EpisodeSpec("queue_line", "traditional", "pr2"))
    assert row["error"] is None
    for name, value in written.items():
        if name == "success_conditions":
            continue
        got = row[metric_column(name)]
        assert (value is None and math.isnan(got)) or value == got, name
    conditions = {k: v for k, v in written["success_conditions"].items() if k != "success"}
    assert {k: row[condition_column(k)] for k in conditions} == conditions
    assert row["success"] == float(written["success_conditions"]["success"])


def test_success_is_measured_at_the_target_the_controller_resolved():
    scn = load_scenario("queue_line")
    paccet = run_episode(scn, "paccet", "pr2").record
    assert paccet.meta["target_source"] == "controller"  # its own social goal
    # a planner that ignores the queue drove to the given goal: judged at the scenario's spot
    plain = run_episode(scn, "traditional", "pr2").record
    assert plain.meta["target_source"] == "scenario"
    spot = resolve_target(scn, scn.social_context()).pose
    np.testing.assert_allclose(plain.target, spot)
    # paccet's own rule keeps the queue's body gap behind the last member: the PR2's front
    # reaches 0.075 m farther than a person's radius, so its slot is that much further back
    own = resolve_target(scn, scn.social_context(), queue_front=footprint_front(PR2)).pose
    np.testing.assert_allclose(paccet.target[:2], own[:2], atol=0.05)
    assert np.hypot(*(own[:2] - spot[:2])) == pytest.approx(0.075)

"""Episodes with the social context detected from noisy tracks, and ``socialnav detect``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from socialnav.cli import app
from socialnav.core.errors import ConfigurationError
from socialnav.sim.runner import DetectedContext, resolve_target, run_episode
from socialnav.sim.scenario import load_scenario


@pytest.mark.parametrize(
    ("name", "kind"),
    [
        ("group_join", "o_formation"),
        ("group_lead", "o_formation_lead"),
        ("queue_line", "queue_tail"),
        ("queue_rotated", "queue_tail"),
        ("gallery_present", "presenter"),
        ("gallery_activity", "waypoint"),
    ],
)
def test_the_detected_context_yields_the_same_kind_of_social_goal(name, kind):
    scn = load_scenario(name)
    seen = DetectedContext(scn, seed=0).warm_up(scn.social_context(), 0.1)
    assert resolve_target(scn, seen).meta["social_goal"] == kind
    assert resolve_target(scn, scn.social_context()).meta["social_goal"] == kind


def test_unknown_context_is_refused():
    with pytest.raises(ConfigurationError, match="context"):
        run_episode("hallway_stationary", "go_to_goal", context="told")


@pytest.mark.slow
def test_a_detected_episode_records_its_context_and_estimator_time():
    from socialnav.sim.stack import StackController

    result = run_episode("queue_line", StackController("paccet"), "pr2", context="detected")
    meta = result.record.meta
    assert meta["context"] == "detected" and meta["estimator_ms_median"] > 0
    assert meta["detected_social_goal"] == "queue_tail"
    # success is measured against the true context's target (people stand still here)
    scn = load_scenario("queue_line")
    given = resolve_target(scn, scn.social_context())
    assert meta["target_source"] == "true context"
    np.testing.assert_allclose(result.record.target, given.pose, atol=1e-9)


def test_detect_command_writes_structures_and_a_picture(tmp_path: Path):
    out = tmp_path / "det"
    res = CliRunner().invoke(app, ["detect", "group_join", "--out", str(out), "--noise", "none"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.output)
    assert summary["structures"] == {"fformation": 1}
    table = pq.read_table(out / "structures.parquet").to_pylist()
    assert table and all(r["members"] == [1, 2, 3] for r in table)
    assert abs(table[-1]["center_x"] - 12.5) < 0.3 and abs(table[-1]["center_y"] - 12.5) < 0.3
    assert (out / "context.png").stat().st_size > 10_000


def test_detect_command_names_a_bad_source(tmp_path: Path):
    res = CliRunner().invoke(app, ["detect", str(tmp_path), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "not an episode folder" in res.output

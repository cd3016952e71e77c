"""``socialnav compare --suite generated --seeds A:B``: the split, the report, bad input."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from socialnav.cli import app
from socialnav.core.errors import ConfigurationError
from socialnav.experiments.crowd import parse_seeds
from socialnav.experiments.results import load_results
from socialnav.experiments.suite import generated_specs


def invoke(*args: str):
    return CliRunner().invoke(app, list(args))


def test_parse_seeds():
    assert parse_seeds("5") == range(0, 5)
    assert parse_seeds("10000:10020") == range(10000, 10020)
    for bad in ("", "a", "3:1", "1:2:3", "-1:4"):
        with pytest.raises(ConfigurationError, match="--seeds"):
            parse_seeds(bad)


def test_generated_specs_name_family_and_seed():
    specs = generated_specs(["queue"], ["paccet"], ["pr2"], range(10000, 10002))
    assert [s.scenario for s in specs] == ["generated:queue"] * 2
    assert [s.seed for s in specs] == [10000, 10001]
    assert specs[0].run_id == "gen_queue__paccet__pr2__scripted__s10000"
    both = generated_specs(["queue"], ["paccet"], ["pr2"], [10000], ("given", "detected"))
    assert [s.context for s in both] == ["given", "detected"]
    assert both[1].run_id == "gen_queue__paccet__pr2__scripted__detected__s10000"


def test_compare_generated_rejects_bad_seeds_and_families(tmp_path: Path):
    out = str(tmp_path / "r")
    bad = invoke("compare", "--suite", "generated", "--seeds", "9:3", "--out", out)
    assert bad.exit_code == 2 and "--seeds" in bad.output
    fam = invoke("compare", "--suite", "generated", "--families", "hallwya", "--out", out)
    assert fam.exit_code == 2 and "hallway" in fam.output


@pytest.mark.slow
def test_compare_generated_end_to_end(tmp_path: Path):
    out = tmp_path / "r"
    # seed 4 of the hallway family is an empty corridor: one quick episode per planner
    result = invoke(
        "compare",
        "--suite",
        "generated",
        "--families",
        "hallway",
        "--seeds",
        "4:5",
        "--planners",
        "traditional,paccet",
        "--robots",
        "pr2",
        "--jobs",
        "1",
        "--out",
        str(out),
    )
    assert result.exit_code == 0, result.output
    rows = load_results(out, suite="generated")
    assert {r["planner"] for r in rows} == {"traditional", "paccet"}
    assert all(r["seed"] == 4 and not r["error"] for r in rows)
    report = (out / "report.md").read_text()
    assert "Pass rate per family and robot" in report
    assert "development split" in report
    assert "hallway" in report

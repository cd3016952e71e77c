"""The recorded-crowds report's target lines: met, missed, or not evaluated."""

from __future__ import annotations

from socialnav.report.crowd import REFERENCE, targets


def _row(**kw: float) -> dict[str, float]:
    row = {"success": 96.0, "active": 0.0, "passive": 10.0, "any_contact": 30.0, "t12": 5.0}
    row |= {"path_ratio": 1.2, "ms_p95": 4.0}
    return row | kw


def test_bug_a_comparison_without_the_other_runs_is_not_evaluated_not_missed():
    """A crowd run of paccet alone (the reference always runs) printed "missed — time within
    1.2 m below every baseline" although no other planner ran to compare with."""
    alone = targets({("paccet", "pr2"): _row(), (REFERENCE, "pr2"): _row(t12=9.0)})
    assert alone == [
        "`paccet` on pr2: met — success ≥ 95 %, active contacts 0, passive ≤ ⅓ of straight-line "
        "contacts, path ratio ≤ 1.25, step p95 ≤ 50 ms; missed — none; not evaluated (no run to "
        "compare with) — time within 1.2 m below every baseline."
    ]


def test_targets_met_and_missed_against_the_other_planners():
    rows = {
        ("paccet", "pr2"): _row(passive=12.0),
        (REFERENCE, "pr2"): _row(any_contact=30.0),
        ("hl", "pr2"): _row(t12=4.0),
    }
    (line,) = targets(rows)
    assert "missed — passive ≤ ⅓ of straight-line contacts, time within 1.2 m below every" in line
    assert "not evaluated" not in line
    rows[("hl", "pr2")] = _row(t12=6.0)
    assert "time within 1.2 m below every baseline" in targets(rows)[0].split("missed")[0]

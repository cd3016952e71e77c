"""Report statistics and statements: Wilson intervals, who beats paccet, the Table 1 verdict."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from socialnav.report.build import (
    PAPER_TABLE1,
    beaten_statement,
    build_report,
    table1_verdict,
    wilson_interval,
)

Z = 1.96


def wilson_reference(k: int, n: int) -> tuple[float, float]:
    """(p̂ + z²/2n ± z·sqrt(p̂(1-p̂)/n + z²/4n²)) / (1 + z²/n), written out independently."""
    p = k / n
    lo = (p + Z**2 / (2 * n) - Z * math.sqrt(p * (1 - p) / n + Z**2 / (4 * n**2))) / (1 + Z**2 / n)
    hi = (p + Z**2 / (2 * n) + Z * math.sqrt(p * (1 - p) / n + Z**2 / (4 * n**2))) / (1 + Z**2 / n)
    return lo, hi


# --- Wilson interval ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("k", "n", "expected"),
    [
        # published 95% Wilson intervals (z = 1.96)
        (0, 10, (0.0, 0.2775)),
        (10, 10, (0.7225, 1.0)),
        (5, 10, (0.2366, 0.7634)),
        (1, 20, (0.0089, 0.2361)),
    ],
)
def test_wilson_known_values(k: int, n: int, expected: tuple[float, float]) -> None:
    lo, hi = wilson_interval(k, n)
    assert lo == pytest.approx(expected[0], abs=1e-4)
    assert hi == pytest.approx(expected[1], abs=1e-4)
    ref = wilson_reference(k, n)
    assert lo == pytest.approx(max(0.0, ref[0]), abs=1e-12)
    assert hi == pytest.approx(min(1.0, ref[1]), abs=1e-12)


def test_wilson_at_the_ends_is_exact() -> None:
    # p = 0: the lower end is exactly 0 and the upper end is z²/(n + z²)
    lo, hi = wilson_interval(0, 10)
    assert lo == pytest.approx(0.0, abs=1e-15)
    assert hi == pytest.approx(Z**2 / (10 + Z**2), rel=1e-12)
    lo, hi = wilson_interval(10, 10)
    assert lo == pytest.approx(10 / (10 + Z**2), rel=1e-12)
    assert hi == pytest.approx(1.0, abs=1e-15)


def test_wilson_without_runs_is_undefined() -> None:
    lo, hi = wilson_interval(0, 0)
    assert math.isnan(lo) and math.isnan(hi)


@given(st.integers(1, 500).flatmap(lambda n: st.tuples(st.integers(0, n), st.just(n))))
def test_wilson_contains_the_rate_and_is_symmetric(kn: tuple[int, int]) -> None:
    k, n = kn
    lo, hi = wilson_interval(k, n)
    eps = 1e-12  # the ends at k = 0 and k = n are exact up to rounding
    assert 0.0 <= lo <= k / n + eps and k / n - eps <= hi <= 1.0
    mirror = wilson_interval(n - k, n)
    assert lo == pytest.approx(1.0 - mirror[1], abs=1e-12)
    assert hi == pytest.approx(1.0 - mirror[0], abs=1e-12)
    wider_z = wilson_interval(k, n, z=2.58)
    assert wider_z[0] <= lo + 1e-12 and wider_z[1] >= hi - 1e-12


def test_wilson_narrows_with_more_runs() -> None:
    widths = [hi - lo for lo, hi in (wilson_interval(n // 2, n) for n in (10, 40, 160))]
    assert widths[0] > widths[1] > widths[2]
    assert widths[1] == pytest.approx(widths[0] / 2, rel=0.15)  # ~1/sqrt(n)


# --- who beats paccet -----------------------------------------------------------------------------


def rows_with_passes(passes: dict[tuple[str, str], tuple[int, int]]) -> list[dict]:
    """``{(planner, family): (passed, runs)}`` as result rows."""
    rows = []
    for (planner, family), (k, n) in passes.items():
        rows += [{"planner": planner, "family": family, "success": float(i < k)} for i in range(n)]
    return rows


def test_beaten_statement_names_the_baseline_the_family_and_its_rate() -> None:
    rows = rows_with_passes(
        {
            ("paccet", "queue"): (1, 4),
            ("orca", "queue"): (3, 4),
            ("traditional", "queue"): (0, 4),
            ("paccet", "hallway"): (4, 4),
            ("orca", "hallway"): (2, 4),
        }
    )
    text = beaten_statement(rows, ["traditional", "orca", "paccet"], ["hallway", "queue"])
    assert text == "Where a baseline beats `paccet` on pass rate — queue: orca (75%)."


def test_beaten_statement_lists_every_family_and_baseline() -> None:
    rows = rows_with_passes(
        {
            ("paccet", "group"): (0, 2),
            ("hl", "group"): (1, 2),
            ("orca", "group"): (2, 2),
            ("paccet", "gallery_present"): (1, 3),
            ("hl", "gallery_present"): (3, 3),
        }
    )
    text = beaten_statement(rows, ["orca", "hl", "paccet"], ["gallery_present", "group"])
    assert "gallery_present: hl (100%)" in text
    assert "group: orca (100%), hl (50%)" in text
    assert text.index("gallery_present") < text.index("group")


def test_beaten_statement_when_no_baseline_is_better() -> None:
    rows = rows_with_passes({("paccet", "hallway"): (3, 5), ("orca", "hallway"): (1, 5)})
    text = beaten_statement(rows, ["orca", "paccet"], ["hallway"])
    assert text == "No baseline passes more runs than `paccet` in any family."


def test_beaten_statement_needs_paccet() -> None:
    rows = rows_with_passes({("orca", "hallway"): (1, 1)})
    assert beaten_statement(rows, ["orca"], ["hallway"]) == ""


# --- Table 1 verdict and the whole report ---------------------------------------------------------


def table1_rows(lateral: float, distance: float, time: float, intrusions: int) -> list[dict]:
    """5 runs each of paccet (these means) and traditional (0.9 m, 5 m, 10 s, 1 intrusion)."""
    rows = []
    for seed in range(5):
        for planner, values in (
            ("traditional", (0.9, 5.0, 10.0, 1)),
            ("paccet", (lateral, distance, time, intrusions if seed == 0 else 0)),
        ):
            rows.append(
                {
                    "run_id": f"hallway_passing__{planner}__pr2__scripted__s{seed}",
                    "scenario": "hallway_passing",
                    "planner": planner,
                    "robot": "pr2",
                    "seed": seed,
                    "family": "hallway",
                    "error": None,
                    "success": float(planner == "paccet"),
                    "ok_reached_goal": True,
                    "lateral_distance": values[0],
                    "total_distance": values[1],
                    "time_to_goal": values[2],
                    "proxemic_intrusions": float(values[3]),
                    "deviation_distance": math.nan,
                    "psc_1_2": 1.0,
                    "path_length_ratio": values[1] / 5.0,
                    "min_distance_center": values[0],
                    "path_length": values[1],
                    "planner_ms_median": 5.0,
                }
            )
    return rows


def test_table1_verdict_states_the_acceptance_plainly() -> None:
    text = table1_verdict(table1_rows(1.5, 5.25, 12.0, 0), "pr2")
    assert text == (
        "**pr2, paccet**: lateral distance 1.50 m (≥ the paper's 1.39 m), 0 intrusions; "
        "distance +5.0% vs traditional (within the +10% bound); "
        "time +20.0% vs traditional (over the +10% bound)."
    )
    text = table1_verdict(table1_rows(1.2, 4.0, 10.5, 2), "pr2")
    assert "lateral distance 1.20 m (< the paper's 1.39 m), 2 intrusions" in text
    assert "distance -20.0% vs traditional (within the +10% bound)" in text
    assert "time +5.0% vs traditional (within the +10% bound)" in text
    assert table1_verdict(table1_rows(1.5, 5.0, 10.0, 0), "pioneer") == ""


def test_build_report_from_rows(tmp_path: Path) -> None:
    rows = table1_rows(1.5, 5.25, 12.0, 0)
    rows.append({**rows[0], "run_id": "broken", "error": "RuntimeError: boom\ntraceback"})
    path = build_report(rows, tmp_path, suite="paper")
    assert path == tmp_path / "report.md"
    text = path.read_text()
    assert (tmp_path / "report.html").is_file()
    assert "| paccet | 5 | 5.25 | 12.00 | 1.50 | 0 | n/a |" in text
    assert "| traditional | 5 | 5.00 | 10.00 | 0.90 | 5 | n/a |" in text
    for label, values in PAPER_TABLE1.items():
        assert f"| {label} | 5 | {values['total_distance']:.2f} |" in text
    # 5 runs: plain counts; more than 5: a Wilson interval in the cell
    assert "| paccet | 5/5 | 5/5 |" in text and "| traditional | 0/5 | 0/5 |" in text
    assert "No baseline passes more runs than `paccet` in any family." in text
    # the failed run and the figures that could not be drawn (no run folders) are listed
    assert "## Errors" in text and "| broken | RuntimeError: boom |" in text
    assert (tmp_path / "figures" / "tradeoff.png").is_file()


def test_build_report_prints_wilson_intervals_above_5_runs(tmp_path: Path) -> None:
    rows = table1_rows(1.5, 5.25, 12.0, 0)
    rows += [{**r, "seed": 5, "run_id": r["run_id"] + "b"} for r in rows if r["seed"] == 0]
    text = build_report(rows, tmp_path).read_text()
    lo, hi = wilson_interval(6, 6)
    assert f"| paccet | 6/6 [{lo:.2f}, {hi:.2f}] | 6/6 |" in text
    lo, hi = wilson_interval(0, 6)
    assert f"| traditional | 0/6 [{lo:.2f}, {hi:.2f}] | 0/6 |" in text


def test_efficiency_statement_names_faster_and_shorter_baselines() -> None:
    from socialnav.report.build import efficiency_statement

    rows = [
        ["traditional", 0.0, 0.7, 1.00, 20.0, 3.0],
        ["paccet", 1.0, 0.96, 1.09, 23.5, 4.1],
        ["hl", 0.4, 0.84, 1.10, 18.7, float("nan")],
    ]
    text = efficiency_statement(rows)
    assert "shorter paths: traditional (1.00 vs 1.09)" in text
    assert "less time to the goal: traditional (20.00 vs 23.50), hl (18.70 vs 23.50)" in text
    assert efficiency_statement([["paccet", 1.0, 1.0, 1.0, 10.0, 1.0]]).startswith("No planner")


def test_build_report_puts_given_and_detected_side_by_side(tmp_path: Path) -> None:
    rows = table1_rows(1.5, 5.25, 12.0, 0)
    detected = [
        {
            **r,
            "context": "detected",
            "run_id": r["run_id"] + "__detected",
            "success": float(r["planner"] == "paccet" and r["seed"] != 0),
            "estimator_ms_median": 0.5,
        }
        for r in rows
    ]
    text = build_report(rows + detected, tmp_path).read_text()
    assert "## Social context: given or detected" in text
    assert "| paccet | 5/5 → 4/5 | 5/5 → 4/5 | 0.50 |" in text
    assert "| traditional | 0/5 → 0/5 | 0/5 → 0/5 | 0.50 |" in text
    # every other section reports the given runs only
    assert "| paccet | 5/5 | 5/5 |" in text

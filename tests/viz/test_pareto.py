"""Decision (Pareto / PaCcET) plots and the trade-off scatter."""

from __future__ import annotations

import numpy as np
import pytest

from socialnav.moo.nondominated import nondominated_mask
from socialnav.viz import plot_decision, plot_tradeoff
from socialnav.viz.pareto import decision_pair


def _by_label(ax, prefix):
    return [c for c in ax.collections if str(c.get_label()).startswith(prefix)]


def _cycle(n: int = 40, seed: int = 1):
    rng = np.random.default_rng(seed)
    F = rng.uniform(0.0, 1.0, size=(n, 2))
    legal = rng.uniform(size=n) > 0.2
    return F, legal


def test_chosen_point_is_marked_at_its_objectives():
    F, legal = _cycle()
    chosen = int(np.flatnonzero(legal)[3])
    fig = plot_decision(F, legal, chosen=chosen, objective_names=["nav", "ID"])
    ax = fig.axes[0]
    (star,) = _by_label(ax, "chosen")
    np.testing.assert_allclose(star.get_offsets()[0], F[chosen])
    assert star.get_label() == f"chosen (#{chosen})"
    assert ax.get_xlabel().startswith("nav") and ax.get_ylabel().startswith("ID")


def test_default_front_is_the_nondominated_legal_rows():
    F, legal = _cycle()
    fig = plot_decision(F, legal)
    ax = fig.axes[0]
    (front,) = _by_label(ax, "non-dominated")
    expected = F[legal][nondominated_mask(F[legal])]
    got = np.asarray(front.get_offsets())
    assert sorted(map(tuple, got)) == sorted(map(tuple, expected))
    (ill,) = _by_label(ax, "illegal")
    assert ill.get_label() == f"illegal ({int((~legal).sum())})"
    assert not _by_label(ax, "chosen")


def test_transformed_panel_with_simplex_and_projection():
    rng = np.random.default_rng(2)
    F = rng.uniform(size=(30, 3))
    legal = np.ones(30, bool)
    T = F / F.sum(axis=1, keepdims=True)
    fit = T @ np.array([0.2, 0.5, 0.3])
    fig = plot_decision(
        F,
        legal,
        transformed=T,
        chosen=int(np.argmin(fit)),
        fitness=fit,
        pair=(0, 2),
        objective_names=["a", "b", "c"],
    )
    ax1, ax2 = fig.axes[:2]
    assert "projection of 3 objectives" in ax1.get_title()
    (star,) = _by_label(ax2, "chosen")
    np.testing.assert_allclose(star.get_offsets()[0], T[np.argmin(fit), [0, 2]])
    simplex = [ln for ln in ax2.lines if "simplex" in ln.get_label()]
    np.testing.assert_allclose(simplex[0].get_xydata(), [[0, 1], [1, 0]])
    assert len(fig.axes) == 3  # two panels + the fitness colour bar


def test_non_finite_rows_are_counted_not_drawn():
    F = np.array([[0.0, 1.0], [1.0, 0.0], [np.inf, 0.5], [0.5, 0.5]])
    legal = np.array([True, True, False, True])
    ax = plot_decision(F, legal).axes[0]
    assert any("1 non-finite rows" in t.get_text() for t in ax.texts)


def test_decision_bad_input():
    F, legal = _cycle(5)
    with pytest.raises(ValueError, match="m >= 2"):
        plot_decision(F[:, :1], legal)
    with pytest.raises(ValueError, match="legal"):
        plot_decision(F, legal[:3])
    with pytest.raises(ValueError, match="chosen"):
        plot_decision(F, legal, chosen=5)
    with pytest.raises(ValueError, match="pair"):
        plot_decision(F, legal, pair=(1, 1))
    with pytest.raises(ValueError, match="transformed"):
        plot_decision(F, legal, transformed=np.zeros((5, 3)))
    with pytest.raises(ValueError, match="names"):
        plot_decision(F, legal, objective_names=["x"])
    bad = F.copy()
    bad[np.flatnonzero(legal)[0], 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        plot_decision(bad, legal)


def test_tradeoff_one_marker_per_planner_with_error_bars():
    rows = [
        {"planner": "traditional", "x": 13.2, "y": 0.9, "xerr": 0.3, "label": "hallway"},
        {"planner": "paccet", "x": 14.4, "y": 1.39, "yerr": 0.1},
        {"planner": "paccet", "x": 20.0, "y": 1.2},
        {"planner": "irl", "x": np.nan, "y": 1.0},
    ]
    fig = plot_tradeoff(rows, "time [s]", "lateral [m]", x_better="min", y_better="max")
    ax = fig.axes[0]
    _handles, labels = ax.get_legend_handles_labels()
    assert labels == ["traditional", "PaCcET"]  # irl had only undefined values
    pac = next(c for c in ax.containers if c.get_label() == "PaCcET")
    np.testing.assert_allclose(pac.lines[0].get_xydata(), [[14.4, 1.39], [20.0, 1.2]])
    assert pac.has_yerr and not pac.has_xerr
    assert "better" in ax.get_xlabel() and "better" in ax.get_ylabel()
    assert any("1 rows" in t.get_text() for t in ax.texts)
    assert "hallway" in [t.get_text() for t in ax.texts]


def test_tradeoff_bad_input():
    with pytest.raises(ValueError, match="at least one"):
        plot_tradeoff([], "x", "y")
    with pytest.raises(ValueError, match="lacks"):
        plot_tradeoff([{"planner": "a", "x": 1.0}], "x", "y")


# --- the decision a reader can see ----------------------------------------------------------------


def _projection_trap():
    """Candidate 0 is non-dominated in 4 objectives, but 20 others beat it on objectives 0 and 1
    (they are worse on 2 and 3): the default projection (0, 1) would make it look dominated."""
    rng = np.random.default_rng(3)
    beaters = np.column_stack(
        [rng.uniform(0.1, 0.4, 20), rng.uniform(0.1, 0.4, 20), rng.uniform(1, 2, (20, 2))]
    )
    others = rng.uniform(0.6, 1.0, size=(30, 4))
    F = np.vstack([[0.5, 0.5, 0.2, 0.3], beaters, others])
    return F, np.ones(len(F), bool)


def _dominated_in_view(fig, F, chosen):
    """How many plotted candidates dominate the chosen one in the first panel's projection."""
    ax = fig.axes[0]
    names = ["nav", "ID", "GD", "SGD"]
    j = names.index(ax.get_xlabel().split(" ")[0])
    k = names.index(ax.get_ylabel().split(" ")[0])
    pts, ref = F[:, [j, k]], F[chosen, [j, k]]
    return int(np.sum(np.all(pts <= ref, axis=1) & np.any(pts < ref, axis=1)))


def test_decision_plots_a_projection_where_the_chosen_candidate_is_not_beaten():
    F, legal = _projection_trap()
    assert nondominated_mask(F)[0]
    names = ["nav", "ID", "GD", "SGD"]
    assert (
        _dominated_in_view(
            plot_decision(F, legal, chosen=0, objective_names=names, pair=(0, 1)), F, 0
        )
        == 20
    )
    fig = plot_decision(F, legal, chosen=0, objective_names=names)
    assert _dominated_in_view(fig, F, 0) == 0
    assert decision_pair(F, legal, 0) != (0, 1)


def test_decision_names_what_beats_the_chosen_one_when_no_projection_clears_it():
    F, legal = _projection_trap()
    fig = plot_decision(F, legal, chosen=0, objective_names=["nav", "ID", "GD", "SGD"], pair=(0, 1))
    notes = " ".join(t.get_text() for t in fig.axes[0].texts)
    assert "20 candidates that beat #0 here are worse in GD, SGD" in notes


@pytest.mark.parametrize("panel", [0, 1])
def test_an_all_zero_objective_is_labelled_constant_not_stretched(panel: int):
    rng = np.random.default_rng(4)
    F = np.column_stack([rng.uniform(1, 2, 50), np.zeros(50)])
    T = np.column_stack([F[:, 0] - 1.0, np.zeros(50)])
    fig = plot_decision(
        F,
        np.ones(50, bool),
        transformed=T,
        chosen=int(np.argmin(F[:, 0])),
        fitness=F[:, 0],
        objective_names=["nav", "ID"],
    )
    ax = fig.axes[panel]
    lo, hi = ax.get_ylim()
    if panel == 0:
        assert -0.06 <= lo < 0 < hi <= 0.06
        assert "constant: 0 for every legal candidate" in ax.get_ylabel()
    else:  # the transformed panel keeps the simplex in view, not a -4…4 range
        assert -0.1 <= lo < 0 and 1.0 < hi <= 1.1
        assert "lowest fitness" in ax.get_title()

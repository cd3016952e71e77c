"""Top-down episode plots: files, limits, social layers, styles, bad input."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
import viz_synthetic as S
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.figure import Figure
from PIL import Image

from socialnav.core.geometry import points_in_polygon
from socialnav.core.scene import Person, SocialContext
from socialnav.viz import _layers as L
from socialnav.viz import plot_comparison, plot_episode, save_figure
from socialnav.viz.style import COLORS, assign_styles, planner_style


def _artists(ax, label):
    found = [a for a in (*ax.patches, *ax.collections, *ax.lines) if a.get_label() == label]
    return found


@pytest.mark.parametrize("name", sorted(S.ALL))
def test_png_is_written_and_not_blank(name, tmp_path):
    fig = plot_episode(S.ALL[name]())
    out = save_figure(fig, tmp_path / f"{name}.png", dpi=60)
    with Image.open(out) as im:
        assert im.format == "PNG"
        w, h = im.size
        pixels = np.asarray(im.convert("L"), dtype=float)
    # The tight-cropped size stays close to figure inches × dpi (the legend fits inside).
    fw, fh = fig.get_size_inches() * 60
    assert 0.6 * fw < w <= 1.05 * fw and 0.6 * fh < h <= 1.05 * fh
    assert pixels.std() > 20.0  # a blank/white canvas has ~0 variance
    assert (pixels < 128).mean() > 0.005  # some dark ink (walls, labels)


@pytest.mark.parametrize("name", sorted(S.ALL))
def test_axes_limits_contain_robot_path_and_goals(name):
    rec = S.ALL[name]()
    ax = plot_episode(rec).axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    pts = np.vstack([rec.robot_xy, rec.goal[None, :2], rec.target[None, :2]])
    assert np.all((pts[:, 0] >= x0) & (pts[:, 0] <= x1))
    assert np.all((pts[:, 1] >= y0) & (pts[:, 1] <= y1))
    # auto-zoom: the group scene does not show the whole 25 m room
    if name == "group":
        assert x1 - x0 < 15 and y1 - y0 < 15
    assert ax.get_aspect() == 1.0


def test_group_o_space_disc_is_fitted_circle_minus_margin():
    pytest.importorskip("socialnav.social.spaces")
    ax = plot_episode(S.group()).axes[0]
    (disc,) = _artists(ax, "o-space")
    # members on a circle of radius 0.9 about (12.5, 12.5) -> o-space radius 0.6
    np.testing.assert_allclose(disc.center, [12.5, 12.5], atol=1e-9)
    assert disc.radius == pytest.approx(0.6)
    (ring,) = _artists(ax, "group circle")
    assert ring.radius == pytest.approx(0.9)


def test_gallery_activity_space_covers_viewer_to_art():
    pytest.importorskip("socialnav.social.spaces")
    ax = plot_episode(S.gallery()).axes[0]
    (poly,) = _artists(ax, "activity space")
    xy = poly.get_xy()
    inside = points_in_polygon(np.array([[13.0, 23.7], [13.0, 24.8]]), xy)
    outside = points_in_polygon(np.array([[13.0, 21.3], [15.0, 23.8]]), xy)
    assert inside.all() and not outside.any()


def test_queue_bands_tail_slot_and_queue_line():
    pytest.importorskip("socialnav.social.spaces")
    rec = S.queue()
    ax = plot_episode(rec).axes[0]
    (bands,) = _artists(ax, "queue cut-in band")
    assert len(bands.get_paths()) == 2  # three members -> two gaps
    (tail,) = _artists(ax, "queue tail slot (target)")
    np.testing.assert_allclose(tail.get_offsets()[0], rec.target[:2])
    (line,) = _artists(ax, "queue line")
    np.testing.assert_allclose(line.get_xydata()[-1], rec.target[:2])  # ends at the tail slot


def test_social_layer_falls_back_to_nothing_without_module(monkeypatch):
    monkeypatch.setattr(L, "social_spaces", lambda: None)
    ax = plot_episode(S.group()).axes[0]
    assert not _artists(ax, "o-space")
    assert _artists(ax, "person")  # the rest of the figure is still there


def test_closest_approach_is_annotated_with_analytic_distance():
    # Robot drives y = -0.45 through x = 3 where a person stands at (3, 0.45): 0.90 m.
    x = np.linspace(1.0, 5.0, 41)
    poses = np.column_stack([x, np.full_like(x, -0.45), np.zeros_like(x)])
    ctx = SocialContext(people=(Person(0, (3.0, 0.45)),))
    rec = S.make_record(
        poses,
        S.static_people([[3.0, 0.45]], 41),
        ctx,
        goal=(5.0, -0.45, 0.0),
        family="hallway",
        scenario="t",
        walls=S.hallway_walls(),
    )
    assert L.closest_approach(rec) == (20, 0, pytest.approx(0.9))
    ax = plot_episode(rec).axes[0]
    assert "0.90 m" in [t.get_text() for t in ax.texts]
    assert any("min 0.90 m" in lab for lab in ax.get_legend_handles_labels()[1])


def test_legend_time_is_the_time_to_goal_metric():
    # Within the 0.3 m tolerance of x = 5 from x = 4.7 (3.7 s) on, then 3 s more of aligning:
    # the legend gives the metric's 3.7 s, not the record's 7.0 s.
    x = np.concatenate([np.linspace(1.0, 5.0, 41), np.full(30, 5.0)])
    poses = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    ctx = SocialContext(people=(Person(0, (3.0, 2.0)),))
    common = {"goal": (5.0, 0.0, 0.0), "family": "hallway", "scenario": "t"}
    rec = S.make_record(poses, S.static_people([[3.0, 2.0]], len(x)), ctx, **common)
    from socialnav.metrics import compute_metrics

    assert compute_metrics(rec, ["time_to_goal"])["time_to_goal"] == pytest.approx(3.7)
    labels = plot_episode(rec).axes[0].get_legend_handles_labels()[1]
    assert any("goal in 3.7 s" in lab for lab in labels)
    assert not any("7.0 s" in lab for lab in labels)
    stalled = S.make_record(poses[:30], S.static_people([[3.0, 2.0]], 30), ctx, **common)
    labels = plot_episode(stalled).axes[0].get_legend_handles_labels()[1]
    assert any("no arrival in 2.9 s" in lab for lab in labels)


def test_given_goal_is_red_star_and_target_only_when_different():
    ax = plot_episode(S.hallway()).axes[0]  # target == goal
    (goal,) = _artists(ax, "given goal")
    assert goal.get_paths()[0].vertices.shape[0] >= 10  # star marker
    assert not [a for a in ax.collections if "target" in str(a.get_label())]
    ax = plot_episode(S.group()).axes[0]
    assert _artists(ax, "free spot (target)")


def test_into_existing_axes_returns_axes():
    fig = Figure()
    ax = fig.add_subplot()
    assert plot_episode(S.hallway(), ax) is ax
    assert fig.legends == []


def test_comparison_overlay_styles_follow_planner_names():
    fig = plot_comparison([S.hallway("traditional"), S.hallway("paccet")])
    ax = fig.axes[0]
    lines = {ln.get_label().split(" (")[0]: ln for ln in ax.lines}
    trad, pac = lines["traditional"], lines["PaCcET"]
    assert trad.get_color() == "#2ca02c" and trad.get_linestyle() == "--"
    assert pac.get_color() == "#1f77b4" and pac.get_linestyle() == "-"
    assert len(fig.legends) == 1


def test_comparison_panels_and_labels():
    recs = [S.queue("traditional"), S.queue("paccet"), S.queue("other")]
    fig = plot_comparison(recs, labels=["A", "B", "C"], mode="panels", show_stats=False)
    visible = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title() for ax in visible] == ["A", "B", "C"]
    assert visible[0].get_xlim() == visible[2].get_xlim()  # shared limits


def test_comparison_bad_input():
    with pytest.raises(ValueError, match="at least one"):
        plot_comparison([])
    with pytest.raises(ValueError, match="labels"):
        plot_comparison([S.group()], labels=["a", "b"])
    with pytest.raises(ValueError, match="one scenario"):
        plot_comparison([S.group(), S.queue()])
    plot_comparison([S.group(), S.queue()], mode="panels")  # fine side by side


def _empty(rec):
    z = np.zeros
    return replace(
        rec,
        times=z(0),
        robot_poses=z((0, 3)),
        robot_twists=z((0, 3)),
        people_positions=z((0, 1, 2)),
        people_velocities=z((0, 1, 2)),
        people_headings=None,
        collision_person=None,
        collision_obstacle=None,
        status=None,
    )


def test_empty_or_nan_record_raises():
    with pytest.raises(ValueError, match="no samples"):
        plot_episode(_empty(S.hallway()))
    rec = S.hallway()
    rec.robot_poses[3, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        plot_episode(rec)
    with pytest.raises(ValueError, match="EpisodeRecord"):
        plot_episode({"times": []})


def test_save_figure_needs_a_suffix(tmp_path):
    with pytest.raises(ValueError, match="suffix"):
        save_figure(plot_episode(S.hallway()), tmp_path / "noext")
    out = save_figure(plot_episode(S.hallway()), tmp_path / "sub" / "f.svg")
    assert out.read_text().lstrip().startswith("<?xml")


def test_every_metres_and_footprints_analytic():
    xy = np.column_stack([np.linspace(0.0, 10.0, 101), np.zeros(101)])
    np.testing.assert_array_equal(L.every_metres(xy, 2.0), [0, 20, 40, 60, 80, 100])
    np.testing.assert_array_equal(L.every_metres(np.zeros((5, 2)), 1.0), [0, 4])
    square = np.array([[1.0, 0.5], [-1.0, 0.5], [-1.0, -0.5], [1.0, -0.5]])
    out = L.footprints(np.array([[2.0, 3.0, np.pi / 2]]), square)[0]
    np.testing.assert_allclose(out[0], [2.0 - 0.5, 3.0 + 1.0], atol=1e-12)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.tuples(st.floats(-50, 50), st.floats(-50, 50)), min_size=1, max_size=20),
    st.floats(0.0, 3.0),
)
def test_region_of_interest_contains_everything_without_walls(points, margin):
    xy = np.array(points)
    poses = np.column_stack([xy, np.zeros(len(xy))])
    rec = S.make_record(
        poses,
        np.zeros((len(xy), 0, 2)),
        SocialContext(),
        goal=(0.0, 0.0, 0.0),
        family="hallway",
        scenario="p",
        walls=np.zeros((0, 2, 2)),
    )
    x0, x1, y0, y1 = L.region_of_interest([rec], margin=margin)
    assert x0 <= xy[:, 0].min() - margin + 1e-9 and x1 >= xy[:, 0].max() + margin - 1e-9
    assert y0 <= xy[:, 1].min() - margin + 1e-9 and y1 >= xy[:, 1].max() + margin - 1e-9
    assert x1 - x0 >= 4.0 - 1e-9 and y1 - y0 >= 4.0 - 1e-9


def test_region_of_interest_shows_the_far_wall_of_a_corridor():
    # a 4 m corridor along x; the robot kept 0.5 m from the lower wall, so path + 1 m margin alone
    # would stop 1.5 m short of the upper wall and hide the room it had
    xy = np.column_stack([np.linspace(0.0, 12.0, 50), np.full(50, 0.5)])
    walls = np.array(
        [[[-1.0, 0.0], [13.0, 0.0]], [[-1.0, 4.0], [13.0, 4.0]], [[-1.0, 9.5], [13.0, 9.5]]]
    )
    rec = S.make_record(
        np.column_stack([xy, np.zeros(50)]),
        np.zeros((50, 0, 2)),
        SocialContext(),
        goal=(12.0, 0.5, 0.0),
        family="hallway",
        scenario="p",
        walls=walls,
    )
    x0, x1, y0, y1 = L.region_of_interest([rec], margin=1.0)
    assert y0 == pytest.approx(-0.3) and y1 == pytest.approx(4.3)  # both walls, not the far one
    assert x0 == pytest.approx(-1.0) and x1 == pytest.approx(13.0)  # paths' x range + margin
    # beyond the reach the region keeps its own extent
    assert L.region_of_interest([rec], margin=1.0, wall_reach=1.0)[3] == pytest.approx(2.5)


def test_planner_styles_are_stable_and_distinct():
    assert planner_style("traditional").color == "#2ca02c"
    assert planner_style("PaCcET").color == "#1f77b4"
    assert planner_style("paccet_social").color == "#1f77b4"
    a, b = planner_style("mystery"), planner_style("mystery")
    assert a == b and a.color not in (COLORS["person"], COLORS["goal"])
    names = [f"p{i}" for i in range(12)]
    colors = [planner_style(n).color for n in names]
    assert len(set(colors)) < len(colors)  # the hash palette does collide...
    resolved = [s.color for s in assign_styles(names[:8])]
    assert len(set(resolved)) == 8  # ...and assign_styles separates up to 8 planners


def test_library_never_imports_pyplot():
    code = (
        "import sys; sys.path.insert(0, 'tests/viz'); import viz_synthetic as S;"
        "from socialnav.viz import plot_episode, plot_decision; import numpy as np;"
        "plot_episode(S.group()).canvas.draw();"
        "plot_decision(np.eye(3)[:, :2], np.ones(3, bool));"
        "assert 'matplotlib.pyplot' not in sys.modules, 'pyplot imported'"
    )
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    res = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr

"""The estimated-context picture: what it draws and what its legend lists."""

from __future__ import annotations

import numpy as np
import pytest

from socialnav.core.scene import Person
from socialnav.social.perception import estimate_once
from socialnav.viz.context import plot_context


def _conversation() -> list[Person]:
    # three people on a 0.7 m circle, each facing its centre
    out = []
    for i in range(3):
        a = 2 * np.pi * i / 3
        out.append(Person(i, (0.7 * np.cos(a), 0.7 * np.sin(a)), yaw=float(a + np.pi)))
    return out


def _legend(ax) -> list[str]:
    legend = ax.get_legend()
    return [] if legend is None else [t.get_text() for t in legend.get_texts()]


def test_the_legend_lists_only_the_kinds_found_and_the_robot_is_drawn():
    est = estimate_once(_conversation())
    assert [s.kind for s in est.structures] == ["fformation"]
    fig = plot_context([est], robot_poses=np.array([[2.0, -1.0, 0.5]]))
    scene, confidence = fig.axes
    assert _legend(confidence) == ["fformation"]
    assert _legend(scene) == ["person (tick: heading)", "robot"]
    xs = [line.get_xdata()[0] for line in scene.get_lines() if line.get_label() == "robot"]
    assert xs == [2.0]


def test_no_structure_gives_no_legend_but_says_so():
    alone = [Person(0, (0.0, 0.0), yaw=0.0)]
    fig = plot_context([estimate_once(alone)])
    assert _legend(fig.axes[1]) == []
    assert any("no structure" in t.get_text() for t in fig.axes[1].texts)


def test_labels_of_structures_at_the_same_place_do_not_overlap():
    est = estimate_once(_conversation())
    twice = type(est)(est.time, est.context, est.structures * 2, est.candidates)
    offsets = [a.xyann for a in plot_context([twice]).axes[0].texts]
    assert len(offsets) == 2 and offsets[0] != offsets[1]


def test_robot_poses_of_another_length_are_refused():
    est = estimate_once(_conversation())
    with pytest.raises(ValueError, match="2 robot poses for 1 estimates"):
        plot_context([est], robot_poses=np.zeros((2, 3)))


def test_the_view_holds_the_robot_as_well_as_the_people():
    fig = plot_context([estimate_once(_conversation())], robot_poses=np.array([[9.0, 0.0, 0.0]]))
    lo, hi = fig.axes[0].get_xlim()
    assert lo < -0.35 and hi > 9.0


def test_the_default_frame_is_a_confident_one_not_a_hand_over_between_tracks():
    est = estimate_once(_conversation())
    (s,) = est.structures
    fading = type(s)(s.kind, s.members, 0.45, s.track_id + 1, s.geometry)
    rising = type(s)(s.kind, s.members, 0.55, s.track_id, s.geometry)
    steady = type(s)(s.kind, s.members, 1.0, s.track_id, s.geometry)
    frames = [
        type(est)(0.0, est.context, (fading, rising), ()),
        type(est)(1.0, est.context, (steady,), ()),
    ]
    assert plot_context(frames).axes[0].get_title().startswith("t = 1.0 s\n")
    assert plot_context(frames, frame=0).axes[0].get_title() == "t = 0.0 s"


def test_the_robot_marker_points_where_the_robot_heads():
    fig = plot_context([estimate_once(_conversation())], robot_poses=np.array([[2.0, 0.0, np.pi]]))
    (robot,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label() == "robot"]
    # matplotlib turns a (sides, style, angle) marker by angle degrees from pointing up
    assert robot.get_marker() == (3, 0, 90.0)


def test_labels_side_by_side_on_one_row_are_stacked():
    est = estimate_once(_conversation())
    (s,) = est.structures
    people = tuple(
        type(p)(p.id + 10, (p.position[0] + 1.5, p.position[1]), yaw=p.yaw)
        for p in est.context.people
    )
    moved = type(s)(s.kind, tuple(m + 10 for m in s.members), 0.8, s.track_id + 1, {})
    ctx = type(est.context)(est.context.people + people, (), (), ())
    twice = type(est)(est.time, ctx, (s, moved), ())
    offsets = [a.xyann for a in plot_context([twice]).axes[0].texts]
    assert len(offsets) == 2 and offsets[0] != offsets[1]

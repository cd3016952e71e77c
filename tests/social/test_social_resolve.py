"""resolve_social_goal on the scenario families."""

import numpy as np
import pytest

from socialnav.core.errors import InvalidInputError
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.social.resolve import resolve_social_goal


def people(points, yaw=0.0):
    return tuple(Person(i, tuple(map(float, p)), yaw=yaw) for i, p in enumerate(points))


def group_ctx(radius, angles, mode="join"):
    a = np.radians(angles)
    pts = np.column_stack([12.5 + radius * np.cos(a), 12.5 + radius * np.sin(a)])
    ppl = people(pts)
    return SocialContext(ppl, groups=(Group(tuple(p.id for p in ppl), mode),))


def test_group_join_and_lead():
    goal = resolve_social_goal(group_ctx(0.9, [90, 180, 270]), (12.5, 12.5, 0.0), (20, 12.5, np.pi))
    assert goal is not None and goal.kind == "o_formation"
    np.testing.assert_allclose(goal.position, [13.4, 12.5], atol=1e-9)
    lead = resolve_social_goal(
        group_ctx(1.2, [150, 180, 210], "lead"), (12.5, 12.5, 0.0), (5, 18, 0.0)
    )
    assert lead is not None and lead.kind == "o_formation_lead"
    np.testing.assert_allclose(lead.position, [13.7, 12.5], atol=1e-9)


def test_group_far_from_goal_is_ignored():
    assert resolve_social_goal(group_ctx(0.9, [90, 180, 270]), (20, 20, 0), (1, 1, 0)) is None


def queue_ctx():
    ppl = people([(12.5, 19.4), (12.5, 18.6), (12.5, 17.8)], yaw=np.pi / 2)
    return SocialContext(ppl, queues=(Queue((0, 1, 2), service_point=(12.5, 20.0)),))


def test_queue_line_goal_is_tail():
    goal = resolve_social_goal(queue_ctx(), (12.5, 19.5, np.pi / 2), (6, 14, 0))
    assert goal is not None and goal.kind == "queue_tail"
    np.testing.assert_allclose(goal.pose, [12.5, 17.0, np.pi / 2], atol=1e-9)


def art_ctx(viewer_xy):
    ppl = (Person(7, viewer_xy, yaw=np.pi / 2),)
    return SocialContext(ppl, artworks=(Artwork((13.0, 25.0), 1.2, -np.pi / 2, (7,)),))


def test_gallery_present_goal_is_presenter_spot():
    goal = resolve_social_goal(art_ctx((13.0, 23.5)), (13, 24.4, np.pi / 2), (5, 17, 0))
    assert goal is not None and goal.kind == "presenter"
    assert goal.position[0] == pytest.approx(12.05)


def test_gallery_activity_waypoint_then_none():
    ctx = art_ctx((13.0, 22.5))
    goal = resolve_social_goal(ctx, (19, 23.8, 0), (7, 23.8, 0))
    assert goal is not None and goal.is_waypoint and goal.kind == "waypoint"
    # behind the viewer, 1.6 m away: just outside the interpersonal-distance objective's 1.5 m
    np.testing.assert_allclose(goal.position, [13.0, 20.9], atol=1e-9)
    # at the waypoint and beyond, the straight line to the goal is clear: no social goal
    assert resolve_social_goal(ctx, (19, 23.8, 0), (13.0, 20.9, 0)) is None
    assert resolve_social_goal(ctx, (19, 23.8, 0), (16.0, 23.0, 0)) is None


def test_nearest_anchor_wins_and_empty_formations_are_skipped():
    ppl = people([(12.5, 19.4), (12.5, 18.6), (2.0, 2.9), (2.0, 1.1), (1.1, 2.0)])
    ctx = SocialContext(
        ppl,
        groups=(Group(()), Group((2, 3, 4))),
        queues=(Queue((), (0.0, 0.0)), Queue((0, 1), (12.5, 20.0))),
    )
    near_group = resolve_social_goal(ctx, (2.0, 2.0, 0.0), (10, 10, 0))
    assert near_group is not None and near_group.kind == "o_formation"
    near_queue = resolve_social_goal(ctx, (12.5, 19.9, 0.0), (10, 10, 0))
    assert near_queue is not None and near_queue.kind == "queue_tail"


def test_no_social_context_gives_none_and_bad_pose_raises():
    assert resolve_social_goal(SocialContext(), (1, 2, 0), (0, 0, 0)) is None
    with pytest.raises(InvalidInputError):
        resolve_social_goal(SocialContext(), (np.nan, 2, 0), (0, 0, 0))
    with pytest.raises(InvalidInputError):
        resolve_social_goal(SocialContext(), (1, 2), (0, 0, 0))

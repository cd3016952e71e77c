"""The social goal is resolved once and kept while the people who define it stay put."""

from __future__ import annotations

import dataclasses

import numpy as np

from socialnav.core.scene import Artwork, Group, Person, SocialContext
from socialnav.planner.presets import StickySocialGoal

GIVEN = np.array([0.93, 2.09, 0.0])
VIEWER = Person(1, (2.326, 2.053), yaw=np.pi)
ART = Artwork((0.0, 2.112), 0.858, 0.0, viewer_ids=(1,))
PAIR = (Person(7, (5.0, 5.0), yaw=0.0), Person(8, (6.0, 5.0), yaw=np.pi))


def context(*extra: Person, viewers=(1,), groups=()) -> SocialContext:
    art = dataclasses.replace(ART, viewer_ids=viewers)
    return SocialContext((VIEWER, *PAIR, *extra), groups=groups, artworks=(art,))


def test_reordered_tracks_and_a_false_positive_keep_the_goal():
    # a detected context: a missed person is coasted last, false positives come and go; the
    # goal re-resolved from the robot's new pose each time used to jump (generated
    # gallery_present dev seed 3, Pioneer: 0.22 m between two presenter spots)
    sticky = StickySocialGoal()
    first = sticky(context(), GIVEN, np.array([8.7, 1.5, np.pi]))
    assert first is not None
    shuffled = SocialContext(
        (PAIR[1], Person(1_000_000, (3.0, 8.0)), VIEWER, PAIR[0]), artworks=(ART,)
    )
    assert sticky(shuffled, GIVEN, np.array([4.0, 0.5, np.pi])) is first


def test_a_structure_change_or_a_member_moving_resolves_again():
    sticky = StickySocialGoal()
    pose = np.array([8.7, 1.5, np.pi])
    first = sticky(context(), GIVEN, pose)
    assert sticky(context(), GIVEN, pose) is first
    group = (Group((7, 8)),)
    assert sticky(context(groups=group), GIVEN, pose) is not first  # a new structure
    second = sticky(context(groups=group), GIVEN, pose)
    moved = SocialContext(
        (Person(1, (2.326, 2.453), yaw=np.pi), *PAIR), groups=group, artworks=(ART,)
    )
    assert sticky(moved, GIVEN, pose) is not second  # the viewer moved 0.4 m


def test_a_settling_estimate_moves_the_goal_from_the_first_pose():
    # with the context detected the viewer's running mean settles over the first seconds; the
    # goal resolved once from an early estimate stayed up to 0.2 m off (generated
    # gallery_present): it now follows the estimate, but keeps the side first chosen
    from socialnav.social.resolve import resolve_social_goal

    sticky = StickySocialGoal()
    pose, later = np.array([8.7, 1.5, np.pi]), np.array([4.0, 5.0, np.pi])
    first = sticky(context(), GIVEN, pose)
    assert first is not None
    still = dataclasses.replace(VIEWER, position=(2.330, 2.053))  # 4 mm: below ``refine``
    assert sticky(SocialContext((still, *PAIR), artworks=(ART,)), GIVEN, later) is first
    settled = SocialContext(
        (dataclasses.replace(VIEWER, position=(2.306, 2.063)), *PAIR), artworks=(ART,)
    )
    goal = sticky(settled, GIVEN, later)
    expected = resolve_social_goal(settled, GIVEN, pose)
    other_side = resolve_social_goal(settled, GIVEN, later)
    assert goal is not None and expected is not None and other_side is not None
    np.testing.assert_allclose(goal.pose, expected.pose)
    assert np.linalg.norm(goal.position - first.position) < 0.1
    assert np.linalg.norm(other_side.position - first.position) > 1.0

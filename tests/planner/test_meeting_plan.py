"""With the meeting layer (``PlannerPreset.meeting_layer``) the global plan goes around
walkers where the robot will meet them, not where they are now."""

from __future__ import annotations

import numpy as np
import pytest

from socialnav.core.robot import PIONEER, PR2
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.presets import build_navigator, meeting_layers, personal_space_layer
from socialnav.world.grid import Costmap, GridGeometry

ROOM = Costmap(np.zeros((200, 200), np.uint8), GridGeometry((200, 200), 0.05, (-5.0, -5.0)))
START = np.array([0.0, -4.0, np.pi / 2])
GOAL = np.array([0.0, 4.0, np.pi / 2])


def plans(robot, social: SocialContext) -> tuple[np.ndarray, np.ndarray]:
    """(meeting-layer plan, plan with every walker's space where they are now), ``(P, 2)``."""
    nav = build_navigator("paccet", robot, ROOM, GOAL, SocialContext())
    nav.global_layer, nav.meeting_layer = meeting_layers(robot)
    new = nav._compute_plan(START, GOAL, social, True)
    nav.global_layer, nav.meeting_layer = personal_space_layer, None
    old = nav._compute_plan(START, GOAL, social, True)
    assert new.path is not None and old.path is not None
    return new.path, old.path


@pytest.mark.parametrize("robot", [PIONEER, PR2], ids=lambda r: r.name)
@pytest.mark.parametrize(
    "walker",
    [((1.0, -1.0), (1.0, 0.0)), ((-1.2, 0.5), (-1.0, 0.0)), ((0.8, 1.5), (0.8, 0.6))],
    ids=["right", "left", "diagonal"],
)
def test_bug_plan_swerves_around_a_walker_where_they_are_now(robot, walker):
    """Generated crowdnav: the plan, replanned every 2 s around the crossing people where
    they were, swung 1.4-3 m sideways (hl: 0.1-0.5 m). A walker who has just crossed the
    robot's line and walks away will be metres off it when the robot gets there: the old
    layer (the Gaussian where they are, stretched ahead) sent the plan 1.1-1.5 m sideways,
    the meeting layer keeps it within 0.6 m of the line."""
    position, velocity = walker
    new, old = plans(robot, SocialContext((Person(1, position, velocity),)))
    assert np.abs(old[:, 0]).max() > 1.0
    assert np.abs(new[:, 0]).max() < 0.6


def test_an_oncoming_walker_on_the_line_is_still_passed_with_room():
    """Head-on on the robot's line the meeting point is on the line too: the plan still
    leaves it by more than a metre (as around the walker's own Gaussian)."""
    new, _ = plans(PR2, SocialContext((Person(1, (0.0, 3.5), (0.0, -1.0)),)))
    assert np.abs(new[:, 0]).max() > 1.0


def test_standing_people_keep_their_gaussian_where_they_are():
    """Nobody walks: the meeting layer draws nothing and the plan is the old one exactly."""
    new, old = plans(PIONEER, SocialContext((Person(1, (0.3, 0.0), (0.1, 0.0)),)))
    assert np.array_equal(new, old)

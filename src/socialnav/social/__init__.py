"""Layer 1: social geometry — group circles and o-spaces, activity spaces, queues, social goals."""

from socialnav.social.goals import (
    SocialGoal,
    activity_space_waypoint,
    o_formation_join_pose,
    presenter_pose,
    queue_tail_pose,
)
from socialnav.social.resolve import resolve_social_goal
from socialnav.social.spaces import (
    activity_space_polygon,
    fit_circle,
    o_space,
    queue_band_polygons,
)

__all__ = [
    "SocialGoal",
    "activity_space_polygon",
    "activity_space_waypoint",
    "fit_circle",
    "o_formation_join_pose",
    "o_space",
    "presenter_pose",
    "queue_band_polygons",
    "queue_tail_pose",
    "resolve_social_goal",
]

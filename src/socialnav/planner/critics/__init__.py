"""Critics: one small unit per cost term, each behind the :class:`Critic` interface.

Importing a critic module registers it in :data:`CRITICS`: navigation critics (arrival_time,
goal_distance, heading, occupancy, path_distance, plan_progress) and social critics
(activity_space, group, interpersonal, social_goal).
"""

from socialnav.planner.critics.activity_space import ActivitySpaceCritic
from socialnav.planner.critics.arrival import ArrivalTimeCritic
from socialnav.planner.critics.base import (
    CRITICS,
    Critic,
    CriticScore,
    CriticUnavailable,
    aggregate_time,
)
from socialnav.planner.critics.goal_distance import GoalDistanceCritic
from socialnav.planner.critics.group import GroupCritic
from socialnav.planner.critics.heading import HeadingCritic
from socialnav.planner.critics.interpersonal import InterpersonalCritic
from socialnav.planner.critics.occupancy import OccupancyCritic
from socialnav.planner.critics.path_distance import PathDistanceCritic
from socialnav.planner.critics.plan_progress import PlanProgressCritic
from socialnav.planner.critics.social_goal import SocialGoalCritic

__all__ = [
    "CRITICS",
    "ActivitySpaceCritic",
    "ArrivalTimeCritic",
    "Critic",
    "CriticScore",
    "CriticUnavailable",
    "GoalDistanceCritic",
    "GroupCritic",
    "HeadingCritic",
    "InterpersonalCritic",
    "OccupancyCritic",
    "PathDistanceCritic",
    "PlanProgressCritic",
    "SocialGoalCritic",
    "aggregate_time",
]

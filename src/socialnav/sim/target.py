"""Where an episode is measured: the scenario's social goal when one resolves, else its goal.

The controller records the target it drives toward every cycle
(:attr:`~socialnav.planner.local_planner.PlannerResult.target`); the episode's success is
measured against the last one recorded. :func:`resolve_target` is the scenario's own answer,
used by controllers that do not resolve a social goal themselves and when none was recorded.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.core.scene import SocialContext
from socialnav.sim.scenario import Scenario
from socialnav.social.resolve import resolve_social_goal_detailed


@dataclass(frozen=True)
class Target:
    """Where success is measured: ``pose (3,)``, optional ``waypoint (2,)``, and why."""

    pose: FloatArray
    waypoint: FloatArray | None
    meta: dict[str, Any]


def resolve_target(
    scenario: Scenario,
    social: SocialContext,
    robot_pose: FloatArray | None = None,
    **options: Any,
) -> Target:
    """The social goal when one resolves (``socialnav.social.resolve``), else the given goal,
    seen from ``robot_pose (3,)`` (default: the scenario's start). ``options`` are keyword
    options of :func:`~socialnav.social.resolve.resolve_social_goal_detailed` (e.g. the
    ``art_clearance`` a controller's own rule uses; default: the rule's defaults).

    A social goal of kind ``waypoint`` (gallery activity) keeps the given goal as the target and
    becomes the waypoint to pass. Structures that were not targets (walking groups, groups that
    fail the sanity limits) are listed with their reason in ``meta["social_goal_rejected"]``.
    """
    goal = np.asarray(scenario.goal, dtype=float)
    start = np.asarray(scenario.start if robot_pose is None else robot_pose, dtype=float)
    resolution = resolve_social_goal_detailed(social, goal, start, **options)
    sg = resolution.goal
    rejected = "; ".join(f"{what}: {why}" for what, why in resolution.rejected) or None
    if sg is None:
        return Target(goal, None, {"social_goal": None, "social_goal_rejected": rejected})
    meta = {
        "social_goal": sg.kind,
        "social_goal_fallback": sg.fallback,
        "social_goal_reason": sg.reason,
        "social_goal_rejected": rejected,
    }
    pose = np.asarray(sg.pose, dtype=float)
    if sg.is_waypoint:
        return Target(goal, pose[:2].copy(), meta)
    return Target(pose, None, meta)

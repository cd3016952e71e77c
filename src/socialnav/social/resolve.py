"""Pick the social goal that applies to a given navigation goal.

Banisetty et al. compute one social goal per scenario by hand-written rules; here the rule is
chosen from the :class:`~socialnav.core.scene.SocialContext` and the goal the robot was given:

1. *Interaction goals* — the given goal is "about" a social formation:
   - a queue whose service point or head member is within ``queue_radius`` (1.5 m) of the given
     goal → its tail slot (:func:`~socialnav.social.goals.queue_tail_pose`);
   - a group whose fitted centre is within ``R + group_margin`` (1.0 m) of the given goal → the
     join spot, or the leader's spot when ``Group.mode == "lead"``; walking groups and groups
     that fail the sanity limits of :mod:`socialnav.social.plausibility` (implausible circle,
     a member far from the others) are never join targets: they are listed, with the reason,
     in :attr:`Resolution.rejected`;
   - an artwork viewer within ``viewer_radius`` (1.6 m, the presenter distance range's upper end)
     of the given goal, or a given goal inside that viewer's activity space → the presenter spot.
   - a structure of a registered kind (:mod:`socialnav.social.structures`) whose own rule says
     the given goal is about it → its social goal.
   When several apply, the one whose anchor (service point/head, centre, viewer) is nearest the
   given goal wins; ties go in the order queue, group, artwork, registered structures.
2. Otherwise, *passing*: if the straight robot→goal segment comes within ``activity_margin``
   (0.3 m) of an activity space, a waypoint behind that viewer (the crossed space nearest the
   robot); the rule is stateless, so the waypoint disappears once the straight segment is clear.
   The waypoint keeps ``waypoint_clearance`` (1.6 m) from the viewer: outside the 1.5 m range of
   the interpersonal-distance objective, so reaching the waypoint does not fight that objective.
3. Otherwise ``None``: navigate to the given goal.

Empty groups/queues are skipped; degenerate ones get the goal functions' fallbacks. NaN or
malformed poses raise :class:`~socialnav.core.errors.InvalidInputError`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.geometry import as_pose, points_in_polygon
from socialnav.core.scene import SocialContext
from socialnav.social.goals import (
    FreeFn,
    SocialGoal,
    activity_space_waypoint,
    o_formation_join_pose,
    presenter_pose,
    queue_tail_pose,
)
from socialnav.social.plausibility import group_plausibility
from socialnav.social.spaces import activity_space_polygon, fit_circle, segment_polygon_distance
from socialnav.social.structures import structure_social_goals


@dataclass(frozen=True)
class Resolution:
    """``goal`` (``None``: drive to the given goal) and ``rejected``: ``(structure, reason)``
    for every structure that was not considered a target, e.g. ``("group 0", "walking group")``.
    """

    goal: SocialGoal | None
    rejected: tuple[tuple[str, str], ...] = ()


def resolve_social_goal(
    social: SocialContext,
    given_goal: ArrayLike,
    robot_pose: ArrayLike,
    *,
    queue_radius: float = 1.5,
    group_margin: float = 1.0,
    viewer_radius: float = 1.6,
    activity_margin: float = 0.3,
    waypoint_clearance: float = 1.6,
    free_fn: FreeFn | None = None,
    art_clearance: float = 0.35,
    queue_front: float = 0.0,
) -> SocialGoal | None:
    """The applicable social goal for ``given_goal (3,)`` seen from ``robot_pose (3,)``, or None.

    See the module docstring for the rules and distances (m). ``free_fn`` (points ``(M, 2)`` →
    free ``(M,)``) is passed to the goal functions so spots inside walls are avoided;
    ``art_clearance`` (m) is the presenter spot's clearance from the activity space
    (:func:`~socialnav.social.goals.presenter_pose`; a robot's circumscribed radius keeps its
    footprint outside at any yaw); ``queue_front`` (m) is the robot's footprint extent ahead of
    its centre, with which the tail slot keeps the queue's body gap
    (:func:`~socialnav.social.goals.queue_tail_pose` ``robot_front``; 0: the people's spacing).
    :func:`resolve_social_goal_detailed` also says which structures were rejected and why.
    """
    return resolve_social_goal_detailed(
        social,
        given_goal,
        robot_pose,
        queue_radius=queue_radius,
        group_margin=group_margin,
        viewer_radius=viewer_radius,
        activity_margin=activity_margin,
        waypoint_clearance=waypoint_clearance,
        free_fn=free_fn,
        art_clearance=art_clearance,
        queue_front=queue_front,
    ).goal


def resolve_social_goal_detailed(
    social: SocialContext,
    given_goal: ArrayLike,
    robot_pose: ArrayLike,
    *,
    queue_radius: float = 1.5,
    group_margin: float = 1.0,
    viewer_radius: float = 1.6,
    activity_margin: float = 0.3,
    waypoint_clearance: float = 1.6,
    free_fn: FreeFn | None = None,
    art_clearance: float = 0.35,
    queue_front: float = 0.0,
) -> Resolution:
    """:func:`resolve_social_goal` with the structures it rejected, each with a reason."""
    rejected: list[tuple[str, str]] = []
    goal = as_pose(given_goal, "given_goal")
    pose = as_pose(robot_pose, "robot_pose")
    g, robot = goal[:2], pose[:2]
    # (distance of the anchor to the given goal, priority, thunk)
    found: list[tuple[float, int, SocialGoal]] = []

    for queue in social.queues:
        if not queue.member_ids:
            continue
        members = social.positions(queue.member_ids)
        anchor = min(
            float(np.linalg.norm(g - np.asarray(queue.service_point))),
            float(np.linalg.norm(g - members[0])),
        )
        if anchor <= queue_radius:
            found.append(
                (
                    anchor,
                    0,
                    queue_tail_pose(
                        members,
                        queue.service_point,
                        queue.spacing,
                        robot_position=robot,
                        free_fn=free_fn,
                        robot_front=queue_front,
                        member_radius=social.person(queue.member_ids[-1]).radius,
                    ),
                )
            )

    for k, group in enumerate(social.groups):
        if not group.member_ids:
            continue
        if group.is_walking:
            rejected.append((f"group {k}", "walking group: kept whole, never joined"))
            continue
        members = social.positions(group.member_ids)
        check = group_plausibility(members)
        if not check.ok:
            rejected.append((f"group {k}", f"not a join target: {check.reason}"))
            continue
        center, radius = fit_circle(members)
        anchor = float(np.linalg.norm(g - center))
        if anchor <= radius + group_margin:
            spot = o_formation_join_pose(
                members, "lead" if group.mode == "lead" else "join", robot, free_fn=free_fn
            )
            found.append((anchor, 1, spot))

    for art in social.artworks:
        for vid in art.viewer_ids:
            viewer = social.person(vid)
            v = np.asarray(viewer.position, dtype=float)
            poly = activity_space_polygon(art.center, art.width, art.facing, v)
            anchor = float(np.linalg.norm(g - v))
            if anchor <= viewer_radius or bool(points_in_polygon(g, poly)):
                others = [social.person(o).position for o in art.viewer_ids if o != vid]
                spot = presenter_pose(
                    art.center,
                    art.width,
                    art.facing,
                    v,
                    viewer.yaw,
                    robot_position=robot,
                    art_clearance=art_clearance,
                    other_viewers=np.asarray(others, dtype=float).reshape(-1, 2),
                    free_fn=free_fn,
                )
                found.append((anchor, 2, spot))

    for anchor, spot in structure_social_goals(social, goal, pose):
        found.append((anchor, 3, spot))

    if found:
        found.sort(key=lambda item: (item[0], item[1]))
        return Resolution(found[0][2], tuple(rejected))

    crossing: list[tuple[float, SocialGoal]] = []
    for art in social.artworks:
        for vid in art.viewer_ids:
            v = np.asarray(social.person(vid).position, dtype=float)
            poly = activity_space_polygon(art.center, art.width, art.facing, v)
            if segment_polygon_distance(robot, g, poly) < activity_margin:
                wp = activity_space_waypoint(
                    art.center,
                    art.width,
                    art.facing,
                    v,
                    robot,
                    g,
                    clearance=waypoint_clearance,
                    margin=activity_margin,
                )
                crossing.append((float(np.linalg.norm(poly.mean(axis=0) - robot)), wp))
    if crossing:
        crossing.sort(key=lambda item: item[0])
        return Resolution(crossing[0][1], tuple(rejected))
    return Resolution(None, tuple(rejected))

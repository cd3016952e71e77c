"""The approach rule on the footprint polygon: turning counts, corners count.

A robot that turns on the spot does not move its centre, so the disc rule of
``critics.interpersonal.approaches`` never sees it close on anyone; its corners, beyond the
inscribed circle, still sweep into a person beside it. On the recorded crowds (dev seeds 0–89)
most active contacts under the footprint metric (``socialnav.metrics.crowd``) happened while
the robot turned at 0.5–1 rad/s. ``footprint_approaches`` judges what the metric judges.
"""

from __future__ import annotations

import numpy as np
import pytest
from _planner_helpers import blank, context
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.geometry import body_to_world, signed_distance_to_polygon
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import HUMAN_RADIUS, Person, SocialContext
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.interpersonal import (
    InterpersonalCritic,
    approaches,
    footprint_approaches,
    min_squared_distances,
)
from socialnav.planner.rollout import RolloutParams, rollout

SPEED = 0.02


def _ctx(people: tuple[Person, ...], robot: RobotModel = PR2) -> PlanningContext:
    return context(blank(4, 4, 1.0), robot, social=SocialContext(people))


def _rollouts(twists, robot: RobotModel = PR2, sim_time: float = 1.5):
    twists = np.asarray(twists, dtype=float).reshape(-1, 3)
    params = RolloutParams(sim_time=sim_time)
    return rollout(np.zeros(3), np.zeros(3), twists, robot, params)


def _rule(trajs, ctx):
    radii = ctx.social.radii()
    reach = radii + ctx.robot.circumscribed_radius
    return footprint_approaches(trajs, ctx, min_squared_distances(trajs, ctx, reach), radii, SPEED)


def _disc_rule(trajs, ctx):
    contact = ctx.social.radii() + ctx.robot.inscribed_radius
    return approaches(trajs, ctx, min_squared_distances(trajs, ctx, contact), contact, SPEED)


@pytest.mark.parametrize("robot", [PR2, PIONEER])
def test_turning_on_the_spot_sweeps_a_corner_into_a_person_ahead(robot):
    # The person stands 1 cm clear of the front face: not touching now. A turn either way
    # swings a front corner (farther out than the face) into them: an approach, which the
    # disc rule cannot see (the centre does not move). Backing away never touches them.
    front = float(robot.polygon[:, 0].max())
    ctx = _ctx((Person(1, (front + HUMAN_RADIUS + 0.01, 0.0)),), robot)
    trajs = _rollouts([(0.0, 0.0, 0.6), (0.0, 0.0, -0.6), (-0.2, 0.0, 0.0), (0.0, 0.0, 0.0)])
    np.testing.assert_array_equal(_rule(trajs, ctx), [True, True, False, False])
    np.testing.assert_array_equal(_disc_rule(trajs, ctx), [False, False, False, False])


def test_sliding_the_flank_past_a_touching_person_is_not_an_approach():
    # PR2 (square, 0.325 m half side) touching a person at its left flank's middle: driving
    # straight on keeps the flank's distance, then the rear corner leaves them.
    half = float(PR2.polygon[:, 1].max())
    ctx = _ctx((Person(1, (0.0, half + HUMAN_RADIUS - 0.02)),))
    trajs = _rollouts([(0.3, 0.0, 0.0), (0.0, 0.0, 0.5), (0.0, 0.3, 0.0)])
    # forward: no; turning swings a corner further in: yes; sideways into them: yes
    np.testing.assert_array_equal(_rule(trajs, ctx), [False, True, True])


def test_the_critic_uses_the_polygon_only_when_asked():
    front = float(PR2.polygon[:, 0].max())
    ctx = _ctx((Person(1, (front + HUMAN_RADIUS + 0.01, 0.0)),))
    trajs = _rollouts([(0.0, 0.0, 0.6), (-0.2, 0.0, 0.0)])
    disc = InterpersonalCritic(evaluation="max_over_time").score(trajs, ctx)
    poly = InterpersonalCritic(evaluation="max_over_time", approach_footprint="polygon")
    np.testing.assert_array_equal(disc.illegal["person_approach"], [False, False])
    np.testing.assert_array_equal(poly.score(trajs, ctx).illegal["person_approach"], [True, False])


def _oracle(trajs, ctx):
    """The rule over every trajectory, sample and person, on the footprint placed in the world
    (the polygon moved, not the person mapped into the body frame)."""
    poly, radii = ctx.robot.polygon, ctx.social.radii()
    forecast = ctx.people_at(trajs.t)  # (T, K, 2)
    dt = np.maximum(np.diff(trajs.t), 1e-9)
    out = np.zeros(len(trajs), dtype=bool)

    def sd(point: np.ndarray, pose: np.ndarray) -> float:
        return float(signed_distance_to_polygon(point, body_to_world(poly, pose)))

    for n, poses in enumerate(trajs.poses):
        for i in range(len(trajs.t)):
            for k, p in enumerate(forecast[i]):
                if sd(p, poses[i]) >= radii[k]:
                    continue
                into = (sd(p, poses[i - 1]) - sd(p, poses[i])) / dt[i - 1] if i > 0 else 0.0
                last = i + 1 == len(trajs.t)
                leave = 0.0 if last else (sd(p, poses[i]) - sd(p, poses[i + 1])) / dt[i]
                out[n] |= max(into, leave) > SPEED
    return out


@given(st.integers(0, 2**32 - 1), st.integers(1, 4), st.sampled_from(["PR2", "PIONEER"]))
@settings(max_examples=40, deadline=None)
def test_the_culled_footprint_rule_equals_the_rule_over_every_pair(seed, k, name):
    robot = {"PR2": PR2, "PIONEER": PIONEER}[name]
    rng = np.random.default_rng(seed)
    people = tuple(
        Person(i, tuple(rng.uniform(-0.9, 0.9, 2)), tuple(rng.uniform(-1.0, 1.0, 2)))
        for i in range(k)
    )
    ctx = _ctx(people, robot)
    twists = np.column_stack([rng.uniform(-0.2, 0.6, 12), np.zeros(12), rng.uniform(-1.0, 1.0, 12)])
    trajs = _rollouts(twists, robot, sim_time=1.0)
    np.testing.assert_array_equal(_rule(trajs, ctx), _oracle(trajs, ctx))

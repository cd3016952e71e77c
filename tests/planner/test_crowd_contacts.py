"""Contacts with people who walk into the robot: passive at worst, never active.

In replayed crowds (ETH/UCY) pedestrians walk at 1.3–2 m/s, about three times the robots'
speed, and appear in the recording close to the robot; some contacts are then unavoidable. What
the robot must never do is close on a person it touches (an *active* contact, Francis et al.
2023, ``socialnav.metrics.crowd``). These cases failed when every overlap over the rollout was a
hard constraint: with a person walking into every candidate, nothing was legal, and the
recovery's evasive move or the next legal command drove into them.
"""

from __future__ import annotations

import numpy as np
import pytest
from _planner_helpers import step_pose, world
from _planner_helpers import straight_lines as _lines
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.geometry import body_to_world, signed_distance_to_polygon
from socialnav.core.robot import PIONEER, PR2, RobotModel
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.interpersonal import (
    InterpersonalCritic,
    approaches,
    min_squared_distances,
    passing_distances,
)
from socialnav.planner.objectives import Objective, evaluate
from socialnav.planner.presets import build_navigator
from socialnav.world.grid import Costmap, GridGeometry

DT = 0.1


def _ctx(social: SocialContext, robot: RobotModel = PR2) -> PlanningContext:
    costmap = Costmap(np.zeros((4, 4), np.uint8), GridGeometry((4, 4), 1.0))
    return PlanningContext(
        pose=np.zeros(3),
        velocity=np.zeros(3),
        goal=np.zeros(3),
        global_path=np.zeros((0, 2)),
        costmap=costmap,
        robot=robot,
        social=social,
    )


def test_standing_or_retreating_before_a_runner_is_passive_closing_is_active():
    # A runner 1.5 m ahead at 2 m/s reaches every candidate: standing still, stepping aside and
    # driving at them all overlap, but only driving at them closes on them. (Backing away along
    # their line closes on them too once the forecast — people replayed from a recording do
    # not stop — has carried them past the robot's centre.)
    ctx = _ctx(SocialContext((Person(1, (1.5, 0.0), (-2.0, 0.0)),)))
    trajs = _lines([(0.0, 0.0), (0.0, 0.3), (0.4, 0.0)])
    score = InterpersonalCritic(evaluation="max_over_time").score(trajs, ctx)
    np.testing.assert_array_equal(score.illegal["person_collision"], [True, True, True])
    np.testing.assert_array_equal(score.illegal["person_approach"], [False, False, True])


def test_a_sidestep_past_a_person_is_not_an_approach():
    # Moving across a person's path at a distance never touches them: no reason at all.
    ctx = _ctx(SocialContext((Person(1, (0.0, 2.0), (0.0, 0.0)),)))
    score = InterpersonalCritic().score(_lines([(0.5, 0.0)]), ctx)
    assert not score.illegal["person_approach"].any()
    assert not score.illegal["person_collision"].any()


def test_overlap_yields_when_nothing_avoids_it_but_closing_never_does():
    ctx = _ctx(SocialContext((Person(1, (1.5, 0.0), (-2.0, 0.0)),)))
    objective = Objective("ID", ((InterpersonalCritic(evaluation="max_over_time"), 1.0),))
    ev = evaluate([objective], _lines([(0.0, 0.0), (0.0, 0.3), (0.4, 0.0)]), ctx)
    np.testing.assert_array_equal(ev.legal, [True, True, False])
    assert ev.rejected[("objectives", "soft_relaxed")] == 2
    # With an overlap-free candidate (a sidestep ahead of a runner farther away), overlap is a
    # constraint again.
    ctx = _ctx(SocialContext((Person(1, (3.0, 0.0), (-2.0, 0.0)),)))
    ev = evaluate([objective], _lines([(0.0, 0.0), (0.0, 0.5)]), ctx)
    np.testing.assert_array_equal(ev.legal, [False, True])


def _run(robot: RobotModel, scene, steps: int = 120):
    """``paccet`` from (2, 3) to (10, 3); per step the footprint gap to each person after the
    step and the robot's speed toward them over the step."""
    cm, _ = world(12.0, 6.0, [], robot)
    nav = build_navigator("paccet", robot, cm, np.array([10.0, 3.0, 0.0]), scene(0.0))
    pose, vel = np.array([2.0, 3.0, 0.0]), np.zeros(3)
    events = []
    for k in range(steps):
        res = nav.step(k * DT, pose, vel, scene(k * DT))
        vel = res.cmd
        new = step_pose(pose, vel)
        footprint = body_to_world(robot.polygon, new)
        for p in scene((k + 1) * DT).people:
            gap = signed_distance_to_polygon(np.array(p.position), footprint) - p.radius
            u = np.asarray(p.position) - new[:2]
            toward = float((new[:2] - pose[:2]) @ u / np.linalg.norm(u)) / DT
            events.append((k, gap, toward, res.status))
        pose = new
    return events


@pytest.mark.parametrize("robot", [PR2, PIONEER])
@pytest.mark.parametrize("lateral", [0.0, 0.3])
def test_a_runner_appearing_ahead_never_meets_a_robot_closing_on_them(robot, lateral):
    # A pedestrian appears 2.2 m ahead at 1 s (as people appear in the recordings) and runs
    # at the robot at 1.8 m/s: the robot cannot get out of the way in time, but while they
    # touch it must be stopped or moving away.
    def scene(t: float) -> SocialContext:
        if t < 1.0:
            return SocialContext()
        x = 2.0 + 0.5 * 1.0 + 2.2 - 1.8 * (t - 1.0)
        return SocialContext((Person(7, (x, 3.0 + lateral), (-1.8, 0.0), np.pi),))

    events = _run(robot, scene)
    touching = [(k, g, v, s) for k, g, v, s in events if g < 0.0]
    assert all(v <= 0.05 for _, _, v, _ in touching), touching


def test_evasion_judges_closing_only_over_the_next_second():
    # Over the 3 s evasion horizon the constant-velocity forecast carries a runner through the
    # robot, after which backing away along their line "closes" on them; the loop replans
    # every cycle, so only the first second counts and the move stays available.
    from socialnav.planner.local_planner import traditional_planner
    from socialnav.planner.recovery import APPROACH_HORIZON, RecoveringPlanner

    ctx = _ctx(SocialContext((Person(1, (3.0, 0.0), (-2.0, 0.0)),)))
    backing = _lines([(-0.1, 0.0)], duration=3.0, steps=31)
    planner = RecoveringPlanner(traditional_planner(PR2))
    assert APPROACH_HORIZON == 1.0
    assert not planner._approaching(ctx, backing)[0]
    full = InterpersonalCritic(footprint_disc="circumscribed").score(backing, ctx)
    assert full.illegal["person_approach"][0]  # over the whole 3 s it does close on them


def _random_walkers(rng, k: int, spread: float) -> PlanningContext:
    """``k`` people within ``spread`` m of the robot, walking at up to 1.5 m/s per axis."""
    people = tuple(
        Person(i, tuple(rng.uniform(-spread, spread, 2)), tuple(rng.uniform(-1.5, 1.5, 2)))
        for i in range(k)
    )
    return _ctx(SocialContext(people))


def _approaches_oracle(trajs, ctx, d2min, contact, speed):
    """The rule written out over every trajectory and person (no cull): the reference the
    culled :func:`approaches` must reproduce exactly."""
    xy, t = trajs.xy, trajs.t
    forecast = ctx.people_at(t)
    step = np.diff(xy, axis=1) / np.maximum(np.diff(t), 1e-9)[None, :, None]
    zero = np.zeros((len(trajs), 1, 2))
    into, out_of = np.concatenate([zero, step], axis=1), np.concatenate([step, zero], axis=1)
    out = np.zeros(len(trajs), dtype=bool)
    for k in range(forecast.shape[1]):
        rel = forecast[None, :, k] - xy
        dist = np.sqrt((rel * rel).sum(axis=-1))
        unit = rel / np.maximum(dist, 1e-9)[..., None]
        closing = np.maximum((into * unit).sum(axis=-1), (out_of * unit).sum(axis=-1))
        out |= ((dist < contact[k]) & (closing > speed)).any(axis=1)
    return out


@given(st.integers(0, 2**32 - 1), st.integers(1, 6))
@settings(max_examples=60, deadline=None)
def test_the_culled_approach_rule_equals_the_rule_over_every_pair(seed, k):
    rng = np.random.default_rng(seed)
    ctx = _random_walkers(rng, k, spread=1.5)
    trajs = _lines(rng.uniform(-0.6, 0.6, (40, 2)))
    contact = ctx.social.radii() + PR2.inscribed_radius
    d2min = min_squared_distances(trajs, ctx, contact)
    got = approaches(trajs, ctx, d2min, contact, 0.02)
    np.testing.assert_array_equal(got, _approaches_oracle(trajs, ctx, d2min, contact, 0.02))


@given(st.integers(0, 2**32 - 1), st.integers(1, 8), st.floats(0.3, 2.0))
@settings(max_examples=60, deadline=None)
def test_culled_passing_distances_are_exact_within_reach_and_beyond_it_elsewhere(seed, k, r):
    rng = np.random.default_rng(seed)
    ctx = _random_walkers(rng, k, spread=4.0)
    trajs = _lines(rng.uniform(-0.6, 0.6, (30, 2)))
    full = passing_distances(trajs, ctx, 2.5)
    culled = passing_distances(trajs, ctx, 2.5, np.full(k, r))
    kept = np.isfinite(culled)
    np.testing.assert_array_equal(culled[kept], full[kept])
    assert (full[~kept] > r).all()

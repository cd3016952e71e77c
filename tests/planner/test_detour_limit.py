"""The detour limit (``Navigator.detour_limit``): a social plan that goes the long way round
walkers gives way to the plan around standing people only; a plan that only shifts within a
corridor, or goes round people standing still, is kept."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.robot import PR2
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.global_planner import path_length
from socialnav.planner.navigator import Navigator
from socialnav.planner.presets import DETOUR_LIMIT, PRESETS, build_navigator
from socialnav.sim.stack import StackController
from socialnav.world.grid import LETHAL, Costmap, GridGeometry

START, GOAL = np.array([0.0, -4.0, np.pi / 2]), np.array([0.0, 4.0, np.pi / 2])


def room() -> Costmap:
    """12 m × 12 m of free space centred on the origin."""
    geo = GridGeometry((240, 240), 0.05, (-6.0, -6.0))
    return Costmap(np.zeros(geo.shape, np.uint8), geo)


def crossing(speed: float = 1.0) -> SocialContext:
    """Five people 3 m from the centre of the robot's 8 m run, walking at ``speed`` m/s
    toward it (CrowdNav's circle crossing, part way in)."""
    angles = np.deg2rad([30.0, 80.0, 130.0, 200.0, 320.0])
    return SocialContext(
        tuple(
            Person(i, (3.0 * np.cos(a), 3.0 * np.sin(a)), (-speed * np.cos(a), -speed * np.sin(a)))
            for i, a in enumerate(angles)
        )
    )


def plan(costmap: Costmap, start, goal, people: SocialContext, limit: float) -> np.ndarray:
    nav = build_navigator("paccet", PR2, costmap, goal, SocialContext())
    assert nav.detour_limit == DETOUR_LIMIT > 0  # on in paccet
    nav.detour_limit = limit
    result = nav._compute_plan(start, goal, people, True)
    assert result.status == "OK" and result.path is not None
    return result.path


def test_path_length_of_a_polyline():
    assert path_length([[0.0, 0.0], [3.0, 4.0], [3.0, 5.0]]) == pytest.approx(6.0)
    assert path_length(np.zeros((1, 2))) == 0.0


def test_bug_the_plan_round_crossing_walkers_is_twice_as_long_and_gives_way():
    """Generated crowdnav: the plan round the walkers' forecast lanes was 2–2.5 times as long
    as the straight run, and the robot turned round to follow it. Without the limit the plan
    here is about 16 m for an 8 m run; with it, the plan is the straight one."""
    people = crossing()
    long_way = plan(room(), START, GOAL, people, 0.0)
    short = plan(room(), START, GOAL, people, DETOUR_LIMIT)
    assert path_length(long_way) > 1.5 * 8.0
    assert path_length(short) < (1.0 + DETOUR_LIMIT) * 8.0
    assert np.abs(short[:, 0]).max() < 0.5


def test_standing_people_still_shape_the_plan():
    """The same five standing still: their personal space is in both plans, so the social
    plan is kept however it bends."""
    people = crossing(speed=0.0)
    with_limit = plan(room(), START, GOAL, people, DETOUR_LIMIT)
    without = plan(room(), START, GOAL, people, 0.0)
    np.testing.assert_array_equal(with_limit, without)


def test_a_plan_that_moves_aside_in_a_corridor_is_kept():
    """An oncoming walker in a 2.5 m corridor: the social plan moves to the far side (a small
    detour) and is kept; the plan without walkers would run through the walker's lane."""
    geo = GridGeometry((60, 240), 0.05, (0.0, -1.5))
    costs = np.zeros(geo.shape, np.uint8)
    costs[np.abs(geo.cell_centers()[1]) > 1.25] = LETHAL
    hall = Costmap(costs, geo)
    start, goal = np.array([1.0, 0.0, 0.0]), np.array([11.0, 0.0, 0.0])
    walker = SocialContext((Person(1, (7.0, 0.3), (-1.0, 0.0)),))
    kept = plan(hall, start, goal, walker, DETOUR_LIMIT)
    np.testing.assert_array_equal(kept, plan(hall, start, goal, walker, 0.0))
    assert kept[:, 1].min() < -0.5  # moved aside


def test_path_length_names_a_malformed_path():
    with pytest.raises(InvalidInputError, match="path"):
        path_length([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])  # poses, not points
    with pytest.raises(InvalidInputError, match="path"):
        path_length([[0.0, 0.0], [np.nan, 1.0]])


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf"), "0.5", True, None])
def test_detour_limit_must_be_a_finite_non_negative_number(bad):
    """Checked where it is set: the navigator, the preset (named in the error), the
    builders' overrides; a limit without the plan to compare with is refused too."""
    nav = build_navigator("paccet", PR2, room(), GOAL, SocialContext())
    with pytest.raises(ValueError, match="detour_limit"):
        Navigator(PR2, nav.local_planner, nav.costmap, GOAL, detour_limit=bad)
    with pytest.raises(ConfigurationError, match=r"PaCcET.*detour_limit"):
        replace(PRESETS.get("paccet"), detour_limit=bad)
    if bad is not None:  # None is the builders' "the preset's own"
        with pytest.raises(ConfigurationError, match="detour_limit"):
            StackController("paccet", detour_limit=bad)
        with pytest.raises(ConfigurationError, match="detour_limit"):
            build_navigator("paccet", PR2, room(), GOAL, SocialContext(), detour_limit=bad)


def test_a_detour_limit_needs_the_plan_it_is_compared_with():
    nav = build_navigator("paccet", PR2, room(), GOAL, SocialContext())
    with pytest.raises(ValueError, match="detour_layer"):
        Navigator(PR2, nav.local_planner, nav.costmap, GOAL, detour_limit=0.5)
    for build in (
        lambda: StackController("traditional", detour_limit=0.5),
        lambda: build_navigator("traditional", PR2, room(), GOAL, SocialContext(), detour_limit=1),
    ):
        with pytest.raises(ConfigurationError, match="no social global plan"):
            build()
    # A preset derived without the social global plan keeps working: the limit has no plan.
    static = replace(PRESETS.get("paccet"), social_global_path=False)
    assert static.detour_limit == DETOUR_LIMIT


def test_the_builders_switch_the_limit_off_and_keep_the_preset_otherwise():
    assert build_navigator("paccet", PR2, room(), GOAL, SocialContext()).detour_limit == 0.5
    off = build_navigator("paccet", PR2, room(), GOAL, SocialContext(), detour_limit=0.0)
    assert off.detour_limit == 0.0
    long_way = off._compute_plan(START, GOAL, crossing(), True)
    assert long_way.path is not None and path_length(long_way.path) > 12.0
    assert StackController("paccet", detour_limit=0.0).detour_limit == 0.0
    assert PRESETS.get("paccet").detour_limit == DETOUR_LIMIT  # the registry is untouched


def test_the_pioneer_no_longer_turns_round_in_generated_crowdnav():
    """Development seed 0 of generated crowdnav: the Pioneer faced away from its goal for
    5.4 s, following a plan round the crossing people, and arrived after 26.4 s (hl: 16.1 s).
    With the limit it never faces away by more than 90° and arrives in under 21 s."""
    from socialnav.metrics import measure_episode
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode

    record = run_episode(generate("crowdnav", 0), "paccet", "pioneer", seed=0).record
    poses = np.asarray(record.robot_poses)
    bearing = np.arctan2(GOAL[1] - poses[:, 1], GOAL[0] - poses[:, 0])
    away = np.abs((bearing - poses[:, 2] + np.pi) % (2 * np.pi) - np.pi) > np.pi / 2
    near_goal = np.hypot(*(poses[:, :2] - GOAL[:2]).T) < 0.5
    assert (away & ~near_goal).sum() * record.dt <= 0.5
    failed = [c.name for c in measure_episode(record).conditions if c.required and not c.passed]
    assert failed == []
    assert len(poses) * record.dt < 21.0


@pytest.fixture
def registries():
    """The preset and controller registries, restored after the test."""
    from socialnav.sim.controller import CONTROLLERS

    saved = [(r, dict(r._items)) for r in (PRESETS, CONTROLLERS)]
    yield
    for registry, items in saved:
        registry._items.clear()
        registry._items.update(items)


def test_a_preset_derived_at_run_time_runs_as_a_planner(registries):
    """A newcomer's variant (paccet without the limit) runs by name once registered, and a
    name taken by another preset or controller is refused."""
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode
    from socialnav.sim.stack import register_preset

    name = "paccet_no_detour_test"
    variant = replace(PRESETS.get("paccet"), detour_limit=0.0)
    register_preset(name, variant, compared=False)
    register_preset(name, variant, compared=False)  # the same object again: a no-op
    record = run_episode(generate("crowdnav", 0), name, "pioneer", seed=0).record
    assert len(record.robot_poses) * record.dt > 24.0  # the long way round, as before the limit
    with pytest.raises(ConfigurationError, match="already registered"):
        register_preset(name, replace(variant, detour_limit=0.2))
    with pytest.raises(ConfigurationError, match="already registered"):
        register_preset("hl", variant)

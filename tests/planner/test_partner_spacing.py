"""Interaction partners in the global plan (``Navigator.partner_spacing``): the people the robot
joins, queues behind or presents to are drawn at the interaction's own distance, as the ID
objective scores them, so the plan to a free spot in a group does not go round the group."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.robot import PR2
from socialnav.core.scene import HUMAN_RADIUS, Group, Person, Queue, SocialContext
from socialnav.planner.navigator import Navigator
from socialnav.planner.presets import (
    PARTNER_SPACING,
    PRESETS,
    build_navigator,
    personal_space_layer,
    spacing_on,
)
from socialnav.sim.stack import StackController
from socialnav.social.goals import interaction_distances
from socialnav.social.proxemics import PERSONAL
from socialnav.world.grid import Costmap, GridGeometry


def room() -> Costmap:
    """8 m × 8 m of free space, 0.05 m cells, centred on the origin."""
    geo = GridGeometry((160, 160), 0.05, (-4.0, -4.0))
    return Costmap(np.zeros(geo.shape, np.uint8), geo)


def cost_at(costmap: Costmap, x: float, y: float) -> int:
    row, col = costmap.geometry.world_to_cell(np.array([x, y]))
    return int(costmap.costs[int(row), int(col)])


def test_members_near_the_spot_keep_the_spots_own_distance_less_the_margin():
    """A queue (ids 1, 2) with the spot 0.8 m behind its last member, a group member 1.4 m
    from the spot, a stranger 0.5 m from it and a member beyond the threshold."""
    social = SocialContext(
        (
            Person(1, (0.0, 0.0)),
            Person(2, (0.8, 0.0)),
            Person(3, (1.6, 1.4)),
            Person(4, (1.6, -0.5)),
            Person(5, (1.6, -2.0)),
            Person(6, (1.6, -3.0)),
        ),
        groups=(Group((3, 5, 6)),),
        queues=(Queue((1, 2), service_point=(-1.0, 0.0)),),
    )
    own = interaction_distances(social, (1.6, 0.0), threshold=1.5, margin=0.05)
    np.testing.assert_allclose(own, [1.5, 0.75, 1.35, 1.5, 1.5, 1.5])
    # a member standing on the spot keeps a positive distance
    on_spot = interaction_distances(social, (0.8, 0.0), threshold=1.5, margin=0.05)
    assert on_spot[1] == pytest.approx(1e-3)
    assert interaction_distances(SocialContext(), (0.0, 0.0), 1.5, 0.05).shape == (0,)


def test_a_partners_space_costs_at_their_distance_what_a_strangers_costs_at_personal():
    """Two standing people 3 m apart, on cell centres: the partner (own distance 0.8 m) costs
    at ``d`` what the stranger costs at ``d · 1.2 / 0.8`` (so at 0.8 m what the stranger costs
    at 1.2 m), less than the stranger at every distance up to 1.2 m; the stranger's side is
    the same with or without partners, and so is everything when nobody is a partner."""
    x_partner, x_stranger, y = 1.525, -1.475, 0.025
    social = SocialContext((Person(1, (x_stranger, y)), Person(2, (x_partner, y))))
    plain = personal_space_layer(room(), social)
    narrowed = personal_space_layer(room(), social, partners={2: 0.8})
    for d in (0.2, 0.4, 0.6, 0.8):
        stranger = cost_at(plain, x_stranger, y + d * PERSONAL / 0.8)
        assert cost_at(narrowed, x_partner, y + d) == pytest.approx(stranger, abs=1)
    assert 70 < cost_at(narrowed, x_partner, y + 0.8) < 90  # about 250 · exp(-1.125) = 81
    for d in (0.5, 0.8, 1.0, 1.2):
        assert cost_at(narrowed, x_partner, y + d) < cost_at(plain, x_partner, y + d)
    left = plain.geometry.cell_centers()[0] < 0.0
    np.testing.assert_array_equal(narrowed.costs[left], plain.costs[left])
    for nobody in ({}, {2: PERSONAL}, {2: 1.4}, {7: 0.5}):
        np.testing.assert_array_equal(
            personal_space_layer(room(), social, partners=nobody).costs, plain.costs
        )


def test_bug_the_plan_to_a_free_spot_went_round_the_group():
    """Generated group_join development seed 45, Pioneer: the partners' full personal space
    made every way into the free spot dear, and the robot drove round the group, a 7.65 m path
    and 15.4 s to the spot. With the partners at their own distance it takes 6.1 m."""
    from socialnav.metrics import measure_episode
    from socialnav.sim.generate import generate
    from socialnav.sim.runner import run_episode

    assert PARTNER_SPACING and PRESETS.get("paccet").partner_spacing
    record = run_episode(generate("group_join", 45), "paccet", "pioneer", seed=0).record
    poses = np.asarray(record.robot_poses)[:, :2]
    length = float(np.hypot(*np.diff(poses, axis=0).T).sum())
    assert length < 6.6
    failed = [c.name for c in measure_episode(record).conditions if c.required and not c.passed]
    assert failed == []


def test_partner_spacing_needs_layers_that_take_partners_and_a_bool():
    nav = build_navigator("paccet", PR2, room(), np.zeros(3), SocialContext())
    assert nav.partner_spacing is True
    assert (
        build_navigator("traditional", PR2, room(), np.zeros(3), SocialContext()).partner_spacing
        is False
    )

    def old_layer(costmap: Costmap, social: SocialContext) -> Costmap:
        return costmap

    with pytest.raises(
        ValueError, match=r"global_layer that takes partners=.*partner_spacing=False"
    ):
        Navigator(
            PR2,
            nav.local_planner,
            room(),
            np.zeros(3),
            global_layer=old_layer,
            partner_spacing=True,
        )
    with pytest.raises(ValueError, match="partner_spacing must be a bool"):
        Navigator(PR2, nav.local_planner, room(), np.zeros(3), partner_spacing="yes")  # type: ignore[arg-type]
    # without partner_spacing any layer goes
    Navigator(PR2, nav.local_planner, room(), np.zeros(3), global_layer=old_layer)


def test_only_a_stopping_social_goal_has_partners():
    """The navigator's partners: none without the option, without a social goal or for a
    waypoint; the members near a stopping goal otherwise."""
    from socialnav.social.goals import SocialGoal

    social = SocialContext(
        (Person(1, (0.0, 0.0)), Person(2, (1.0, 0.0)), Person(3, (0.5, 0.9))),
        groups=(Group((1, 2, 3)),),
    )
    spot = SocialGoal(np.array([0.5, -0.8, 1.57]), "o_formation")
    nav = build_navigator("paccet", PR2, room(), np.zeros(3), SocialContext())
    partners = nav._partners(social, spot)
    assert set(partners) == {1, 2}  # the third member is 1.7 m from the spot
    assert partners[1] == pytest.approx(np.hypot(0.5, 0.8) - 0.05)
    assert nav._partners(social, None) == {}
    waypoint = SocialGoal(np.array([0.5, -0.8, 1.57]), "waypoint", is_waypoint=True)
    assert nav._partners(social, waypoint) == {}
    nav.partner_spacing = False
    assert nav._partners(social, spot) == {}


@pytest.mark.parametrize("bad", [0.0, -0.5, float("nan"), float("inf"), "0.8", True, None])
@pytest.mark.parametrize("person", [2, 999])  # in view or not: checked alike
def test_a_partners_distance_must_be_a_finite_positive_number(bad, person):
    social = SocialContext((Person(1, (0.0, 0.0)), Person(2, (1.5, 0.0))))
    with pytest.raises(InvalidInputError, match=f"partners: person {person}'s distance"):
        personal_space_layer(room(), social, partners={person: bad})


@pytest.mark.parametrize(
    ("bad", "match"),
    [
        ({"2": 0.8}, "person ids are ints"),
        ({True: 0.8}, "person ids are ints"),
        ([(2, 0.8)], "must be a mapping"),
    ],
)
def test_partners_is_a_mapping_of_int_ids(bad, match):
    """Newcomer trial: a string id or a list of pairs changed nothing, without a word."""
    social = SocialContext((Person(1, (0.0, 0.0)), Person(2, (1.5, 0.0))))
    with pytest.raises(InvalidInputError, match=match):
        personal_space_layer(room(), social, partners=bad)
    assert personal_space_layer(room(), social, partners={np.int64(2): 0.8}).costs.any()


def test_a_partner_is_never_drawn_narrower_than_their_body_and_strangers_ids_are_ignored():
    """A member standing on the spot (``interaction_distances``' 1 mm floor) stays on the map:
    a Gaussian narrower than a cell vanished from it. A partner id not in view changes
    nothing (the navigator's partners are the whole scene's)."""
    social = SocialContext((Person(1, (0.0, 0.0)),))
    on_spot = personal_space_layer(room(), social, partners={1: 1e-3})
    body = personal_space_layer(room(), social, partners={1: HUMAN_RADIUS})
    np.testing.assert_array_equal(on_spot.costs, body.costs)
    assert cost_at(on_spot, 0.1, 0.1) > 150
    plain = personal_space_layer(room(), social)
    np.testing.assert_array_equal(
        personal_space_layer(room(), social, partners={9: 0.5}).costs, plain.costs
    )


def test_bug_a_truthy_non_bool_switched_partner_spacing_on():
    """Newcomer trial: ``replace(paccet, partner_spacing="no")`` was accepted and built a
    navigator with the option on. Every way in now refuses a non-bool, naming the field;
    NumPy's bool is stored as Python's."""
    paccet = PRESETS.get("paccet")
    with pytest.raises(ConfigurationError, match="partner_spacing must be a bool"):
        replace(paccet, partner_spacing="no")
    assert replace(paccet, partner_spacing=np.bool_(False)).partner_spacing is False
    with pytest.raises(ConfigurationError, match="partner_spacing"):
        StackController("paccet", partner_spacing="no")  # type: ignore[arg-type]
    with pytest.raises(ConfigurationError, match="partner_spacing"):
        build_navigator("paccet", PR2, room(), np.zeros(3), SocialContext(), partner_spacing=0)  # type: ignore[arg-type]


def test_the_builders_switch_partner_spacing_off_and_only_the_personal_space_layers_use_it():
    off = build_navigator(
        "paccet", PR2, room(), np.zeros(3), SocialContext(), partner_spacing=False
    )
    assert off.partner_spacing is False
    assert StackController("paccet", partner_spacing=False).partner_spacing is False
    assert PRESETS.get("paccet").partner_spacing is True  # the registry is untouched
    paccet = PRESETS.get("paccet")
    assert spacing_on(paccet)
    # A variant on the proxemic layer (no partners there) builds with the option off rather
    # than failing at run time; without the social global plan there is nothing to draw.
    assert not spacing_on(replace(paccet, proxemic_layer=True))
    assert not spacing_on(replace(paccet, social_global_path=False))
    assert not spacing_on(PRESETS.get("traditional"))


def test_a_layer_taking_keyword_arguments_takes_partners():
    nav = build_navigator("paccet", PR2, room(), np.zeros(3), SocialContext())

    def by_kwargs(costmap: Costmap, social: SocialContext, **options: object) -> Costmap:
        return costmap

    kept = Navigator(
        PR2, nav.local_planner, room(), np.zeros(3), global_layer=by_kwargs, partner_spacing=True
    )
    assert kept.partner_spacing is True

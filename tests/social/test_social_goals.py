"""Social goals against hand-computed geometry, rigid-motion equivariance and degenerate inputs."""

import itertools

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from socialnav.core.errors import InvalidInputError
from socialnav.core.geometry import points_in_polygon, signed_distance_to_polygon, wrap_angle
from socialnav.social.goals import (
    PRESENTER_STIFFNESS,
    SocialGoal,
    activity_space_waypoint,
    o_formation_join_pose,
    presenter_pose,
    queue_tail_pose,
)
from socialnav.social.spaces import activity_space_polygon


def on_circle(center, radius, degrees):
    a = np.radians(np.asarray(degrees, dtype=float))
    return np.asarray(center, dtype=float) + radius * np.column_stack([np.cos(a), np.sin(a)])


def rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def assert_pose(goal: SocialGoal, xy, yaw, atol=1e-6):
    np.testing.assert_allclose(goal.pose[:2], xy, atol=atol)
    assert abs(float(wrap_angle(goal.pose[2] - yaw))) < max(atol, 1e-9)


def assert_same_pose_under(goal, goal_t, theta, shift, atol=1e-6):
    np.testing.assert_allclose(goal_t.pose[:2], rot(theta) @ goal.pose[:2] + shift, atol=atol)
    assert abs(float(wrap_angle(goal_t.pose[2] - goal.pose[2] - theta))) < atol


# ------------------------------------------------------------------------------ O-formation

GROUP_CASES = [
    # (scenario, radius, member angles (deg), mode, expected spot, expected yaw)
    ("group_join", 0.9, [90, 180, 270], "join", (13.4, 12.5), np.pi),
    ("group_join_back", 0.9, [0, 90, 270], "join", (11.6, 12.5), 0.0),
    ("group_lead", 1.2, [150, 180, 210], "lead", (13.7, 12.5), np.pi),
]


@pytest.mark.parametrize(("name", "radius", "angles", "mode", "spot", "yaw"), GROUP_CASES)
def test_group_scenarios(name, radius, angles, mode, spot, yaw):
    members = on_circle((12.5, 12.5), radius, angles)
    goal = o_formation_join_pose(members, mode)
    assert_pose(goal, spot, yaw)
    assert goal.fallback is None and goal.reason is None
    assert goal.kind == ("o_formation" if mode == "join" else "o_formation_lead")
    assert not goal.is_waypoint
    np.testing.assert_allclose(goal.geometry["center"], [12.5, 12.5], atol=1e-9)
    assert goal.geometry["radius"] == pytest.approx(radius)
    # every member order gives the same spot
    for perm in itertools.permutations(range(3)):
        assert_pose(o_formation_join_pose(members[list(perm)], mode), spot, yaw)


def test_join_construction_matches_paper():
    # group_join: widest gap 180° (from 270° to 90°), θ_a = 90°, c = sqrt(2R²(1 − cos θ_a)) = R√2
    goal = o_formation_join_pose(on_circle((12.5, 12.5), 0.9, [90, 180, 270]), "join")
    g = goal.geometry
    assert g["widest_gap"] == pytest.approx(np.pi)
    assert g["approach_angle"] == pytest.approx(np.pi / 2)
    assert g["chord_radius"] == pytest.approx(0.9 * np.sqrt(2))
    np.testing.assert_allclose(g["edge_member"], [12.5, 11.6], atol=1e-9)  # the 270° member
    sols = g["intersections"]
    assert sols.shape == (2, 2)
    # the two solutions: the gap middle (kept) and the 180° member's place (outside the gap)
    kept = np.linalg.norm(sols - [13.4, 12.5], axis=1).min()
    other = np.linalg.norm(sols - [11.6, 12.5], axis=1).min()
    assert kept < 1e-9 and other < 1e-9
    # the paper's law of cosines with D squared: adjacent members 90° apart
    np.testing.assert_allclose(np.sort(g["law_of_cosines_angles"]), [np.pi / 2, np.pi / 2, np.pi])


def test_join_and_lead_agree_on_exact_circles_but_differ_in_kind():
    members = on_circle((0, 0), 1.5, [10, 100, 200])
    join = o_formation_join_pose(members, "join")
    lead = o_formation_join_pose(members, "lead")
    np.testing.assert_allclose(join.pose, lead.pose, atol=1e-9)
    assert join.kind == "o_formation" and lead.kind == "o_formation_lead"
    # widest gap 200° → 370°: middle at 285°
    np.testing.assert_allclose(join.position, on_circle((0, 0), 1.5, [285])[0], atol=1e-9)


def test_reflex_gap_uses_bearings_not_law_of_cosines():
    # members squeezed on one side: widest gap 300° (> π), law of cosines would report 60°
    goal = o_formation_join_pose(on_circle((0, 0), 1.0, [150, 180, 210]), "join")
    assert goal.geometry["widest_gap"] == pytest.approx(np.radians(300))
    assert_pose(goal, (1.0, 0.0), np.pi)


@settings(max_examples=60, deadline=None)
@given(
    radius=st.floats(0.6, 2.5),
    angles=st.lists(st.floats(0, 360), min_size=3, max_size=6),
    noise=st.lists(st.floats(-0.05, 0.05), min_size=6, max_size=6),
    theta=st.floats(-np.pi, np.pi),
    shift=st.tuples(st.floats(-50, 50), st.floats(-50, 50)),
    robot=st.tuples(st.floats(-10, 10), st.floats(-10, 10)),
    mode=st.sampled_from(["join", "lead"]),
    data=st.data(),
)
def test_o_formation_rigid_motion_equivariance(
    radius, angles, noise, theta, shift, robot, mode, data
):
    a = np.sort(np.mod(angles, 360.0))
    gaps = np.diff(np.append(a, a[0] + 360.0))
    assume(np.min(gaps) > 15.0)
    top = np.sort(gaps)
    assume(top[-1] - top[-2] > 1.0)  # a unique widest gap (ties are broken by proximity)
    members = on_circle((0, 0), radius, a) * (1 + np.asarray(noise[: len(a)]))[:, None]
    goal = o_formation_join_pose(members, mode, robot_position=robot)
    shift = np.asarray(shift)
    moved = members @ rot(theta).T + shift
    perm = data.draw(st.permutations(range(len(a))))
    goal_t = o_formation_join_pose(
        moved[list(perm)], mode, robot_position=rot(theta) @ np.asarray(robot) + shift
    )
    assert_same_pose_under(goal, goal_t, theta, shift, atol=1e-6)
    assert goal.fallback == goal_t.fallback
    # the spot keeps the clearance to every member
    assert np.linalg.norm(members - goal.position, axis=1).min() >= 0.75 - 1e-9


def test_single_member_stands_at_social_distance_toward_robot():
    goal = o_formation_join_pose([[2.0, 3.0]], robot_position=(2.0, 10.0))
    assert goal.fallback == "single_member" and goal.reason
    assert_pose(goal, (2.0, 4.2), -np.pi / 2)
    no_robot = o_formation_join_pose([[2.0, 3.0]])
    assert_pose(no_robot, (3.2, 3.0), np.pi)


def test_coincident_members_are_one_member():
    goal = o_formation_join_pose(np.tile([[1.0, 1.0]], (4, 1)), robot_position=(-5.0, 1.0))
    assert goal.fallback == "single_member"
    assert_pose(goal, (-0.2, 1.0), 0.0)


def test_collinear_members_face_the_row_from_the_robot_side():
    members = np.array([[0.0, 0.0], [0.6, 0.0], [1.2, 0.0]])
    goal = o_formation_join_pose(members, robot_position=(0.6, -5.0))
    assert goal.fallback == "collinear" and goal.reason
    assert goal.position[0] == pytest.approx(0.6)
    assert goal.position[1] < 0
    assert np.linalg.norm(members - goal.position, axis=1).min() == pytest.approx(0.75)
    assert goal.yaw == pytest.approx(np.pi / 2)


def test_pair_uses_diameter_circle_and_robot_side():
    members = np.array([[0.0, 0.0], [2.0, 0.0]])
    goal = o_formation_join_pose(members, robot_position=(1.0, 4.0))
    assert goal.geometry["fit"] == "diameter_pair"
    assert_pose(goal, (1.0, 1.0), -np.pi / 2)
    below = o_formation_join_pose(members, robot_position=(1.0, -4.0))
    assert_pose(below, (1.0, -1.0), np.pi / 2)


def test_full_circle_widens_instead_of_failing():
    members = on_circle((0, 0), 0.9, np.arange(0, 360, 30))  # 12 people, 0.47 m apart
    goal = o_formation_join_pose(members)
    assert goal.fallback == "widened" and "moved out" in goal.reason
    assert np.linalg.norm(members - goal.position, axis=1).min() == pytest.approx(0.75)
    assert np.linalg.norm(goal.position) > 0.9


def test_free_fn_skips_spot_in_wall():
    # gaps 100°, 80°, 80°, 100°: the two 100° gaps tie; without a robot the tie goes to the
    # smaller bisector bearing (-50°), which this "wall" (y < -0.5) rejects
    members = on_circle((0, 0), 1.0, [0, 100, 180, 260])
    assert o_formation_join_pose(members).position[1] < -0.5
    goal = o_formation_join_pose(members, free_fn=lambda pts: pts[:, 1] > -0.5)
    assert goal.fallback == "next_gap" and goal.reason
    np.testing.assert_allclose(goal.position, on_circle((0, 0), 1.0, [50])[0], atol=1e-9)
    blocked = o_formation_join_pose(members, free_fn=lambda p: np.zeros(len(p), bool))
    assert blocked.fallback == "no_free_spot" and blocked.reason
    np.testing.assert_allclose(blocked.position, on_circle((0, 0), 1.0, [-50])[0], atol=1e-9)


def test_o_formation_rejects_bad_input():
    with pytest.raises(InvalidInputError):
        o_formation_join_pose([[np.nan, 1.0], [0.0, 0.0]])
    with pytest.raises(InvalidInputError):
        o_formation_join_pose(np.zeros((0, 2)))
    with pytest.raises(InvalidInputError):
        o_formation_join_pose([[0.0, 0.0]], mode="sideways")
    with pytest.raises(InvalidInputError):
        o_formation_join_pose([[0.0, 0.0]], robot_position=(np.nan, 0.0))


# ------------------------------------------------------------------------------ queue

QUEUE_CASES = [
    ("queue_line", [(12.5, 19.4), (12.5, 18.6), (12.5, 17.8)], (12.5, 20.3), (12.5, 17.0)),
    ("queue_shifted", [(8, 19.4), (8, 18.6), (8, 17.8), (8, 17.0)], (8, 20.3), (8, 16.2)),
    (
        "queue_rotated",
        [(17.36, 17.36), (16.80, 16.80), (16.23, 16.23), (15.67, 15.67)],
        (17.43, 17.43),
        (15.67 - 0.8 / np.sqrt(2), 15.67 - 0.8 / np.sqrt(2)),
    ),
]


@pytest.mark.parametrize(("name", "members", "service", "tail"), QUEUE_CASES)
def test_queue_scenarios(name, members, service, tail):
    goal = queue_tail_pose(members, service, spacing=0.8)
    assert goal.kind == "queue_tail" and goal.fallback is None
    np.testing.assert_allclose(goal.position, tail, atol=1e-9 if name != "queue_rotated" else 5e-3)
    last = np.asarray(members[-1], dtype=float)
    assert np.linalg.norm(goal.position - last) == pytest.approx(0.8)
    # faces the last member, i.e. along the line toward the desk
    d = last - goal.position
    assert goal.yaw == pytest.approx(np.arctan2(d[1], d[0]))
    assert np.linalg.norm(goal.position - service) > np.linalg.norm(last - np.asarray(service))


def test_queue_line_tail_faces_plus_y():
    goal = queue_tail_pose(QUEUE_CASES[0][1], QUEUE_CASES[0][2])
    assert_pose(goal, (12.5, 17.0), np.pi / 2)


@settings(max_examples=60, deadline=None)
@given(
    k=st.integers(2, 6),
    spacing=st.floats(0.5, 1.2),
    heading=st.floats(-np.pi, np.pi),
    theta=st.floats(-np.pi, np.pi),
    shift=st.tuples(st.floats(-50, 50), st.floats(-50, 50)),
    jitter=st.lists(st.floats(-0.05, 0.05), min_size=12, max_size=12),
)
def test_queue_rigid_motion_equivariance(k, spacing, heading, theta, shift, jitter):
    direction = np.array([np.cos(heading), np.sin(heading)])
    members = np.arange(1, k + 1)[:, None] * 0.8 * direction + np.reshape(jitter, (6, 2))[:k]
    service = np.zeros(2)
    goal = queue_tail_pose(members, service, spacing)
    shift = np.asarray(shift)
    goal_t = queue_tail_pose(members @ rot(theta).T + shift, rot(theta) @ service + shift, spacing)
    assert_same_pose_under(goal, goal_t, theta, shift, atol=1e-6)
    assert np.linalg.norm(goal.position - members[-1]) == pytest.approx(spacing)
    assert np.dot(goal.position - members[-1], direction) > 0  # beyond the last member


def test_queue_single_member_goes_away_from_desk():
    goal = queue_tail_pose([[0.0, 1.0]], (0.0, 2.0), 0.8)
    assert goal.fallback == "single_member"
    assert_pose(goal, (0.0, 0.2), np.pi / 2)


def test_queue_all_coincident_on_service_point_uses_robot():
    goal = queue_tail_pose([[1.0, 1.0]] * 3, (1.0, 1.0), 0.8, robot_position=(1.0, -3.0))
    assert goal.fallback == "single_member"
    assert_pose(goal, (1.0, 0.2), np.pi / 2)
    nowhere = queue_tail_pose([[1.0, 1.0]] * 3, (1.0, 1.0), 0.8)
    assert_pose(nowhere, (1.8, 1.0), np.pi)


def test_queue_tail_swings_away_from_wall():
    members = [(0.0, 3.0), (0.0, 2.2), (0.0, 1.4)]
    goal = queue_tail_pose(members, (0.0, 4.0), 0.8, free_fn=lambda p: p[:, 1] > 1.0)
    assert goal.fallback == "rotated"
    assert goal.position[1] > 1.0
    assert np.linalg.norm(goal.position - [0.0, 1.4]) == pytest.approx(0.8)
    stuck = queue_tail_pose(members, (0.0, 4.0), 0.8, free_fn=lambda p: np.zeros(len(p), bool))
    assert stuck.fallback == "no_free_spot"
    assert_pose(stuck, (0.0, 0.6), np.pi / 2)


def test_queue_rejects_bad_input():
    with pytest.raises(InvalidInputError):
        queue_tail_pose([[0.0, 0.0]], (np.nan, 0.0))
    with pytest.raises(InvalidInputError):
        queue_tail_pose([[0.0, 0.0]], (1.0, 0.0), spacing=0.0)


# ------------------------------------------------------------------------------ art gallery

ART = dict(art_center=(13.0, 25.0), art_width=1.2, art_facing=-np.pi / 2)


def brute_force_presenter(viewer, lmin, r=1.2, k=PRESENTER_STIFFNESS, wc=0.5, r_max=1.6):
    """The minimiser of k(ρ − r)² + d over a 2 mm grid of the feasible set of :data:`ART`
    (lateral toward −x, mirrored so the side is +; depth from the wall at y = 25)."""
    xv, dv = 13.0 - viewer[0], 25.0 - viewer[1]
    x, d = np.meshgrid(np.arange(lmin, lmin + 1.6, 0.002), np.arange(wc, wc + 2.5, 0.002))
    rho = np.hypot(x - xv, d - dv)
    cost = np.where(rho <= r_max, k * (rho - r) ** 2 + d, np.inf)
    i = np.unravel_index(np.argmin(cost), cost.shape)
    return np.array([13.0 - x[i], 25.0 - d[i]])


@pytest.mark.parametrize(
    "viewer",
    [
        (13.0, 23.5),  # the 1.2 m circle stays above the wall band beside the art: edge x = L
        (13.0, 24.0),  # it reaches the band: the spot is on the circle, 0.5 m from the wall
        (13.3, 23.2),  # farther from the robot's side: a larger distance
    ],
)
def test_presenter_spot_minimises_its_cost(viewer):
    viewer = np.array(viewer)
    goal = presenter_pose(
        **ART, viewer_position=viewer, viewer_yaw=np.pi / 2, robot_position=(5, 17)
    )
    assert goal.kind == "presenter" and goal.fallback is None
    poly = activity_space_polygon(ART["art_center"], 1.2, -np.pi / 2, viewer)
    lmin = float((13.0 - poly[:, 0]).max()) + 0.35  # the robot's side is −x
    assert goal.geometry["lateral_min"] == pytest.approx(lmin)
    np.testing.assert_allclose(goal.position, brute_force_presenter(viewer, lmin), atol=4e-3)
    # the constraints of scenarios.md
    dist = np.linalg.norm(goal.position - viewer)
    assert 0.9 <= dist <= 1.6
    assert signed_distance_to_polygon(goal.position, poly) >= 0.35 - 1e-9
    assert 25.0 - goal.position[1] >= 0.5 - 1e-9  # clear of the wall
    assert goal.position[0] < 12.4  # beside the artwork, not in front of it
    d = viewer - goal.position
    assert goal.yaw == pytest.approx(np.arctan2(d[1], d[0]))  # faces the viewer


def test_presenter_spot_on_the_circle_when_it_reaches_the_wall_band():
    # hand computation: viewer 1.0 m from the wall, the 1.2 m circle meets the band's edge
    # (0.5 m from the wall) at lateral 13 − sqrt(1.2² − 0.5²) = 11.909, beside 12.05
    goal = presenter_pose(
        **ART, viewer_position=(13.0, 24.0), viewer_yaw=np.pi / 2, robot_position=(5, 17)
    )
    np.testing.assert_allclose(goal.position, [13.0 - np.sqrt(1.2**2 - 0.5**2), 24.5], atol=1e-9)


@settings(max_examples=60, deadline=None)
@given(
    lateral=st.floats(-1.0, 1.0),
    depth=st.floats(0.8, 2.5),
    width=st.floats(0.4, 2.0),
    clearance=st.floats(0.35, 0.6),
    angle=st.floats(-np.pi, np.pi),
    step=st.floats(1e-4, 2e-3),
    robot_x=st.sampled_from([-8.0, 8.0]),
)
def test_presenter_spot_is_continuous_in_the_viewer(
    lateral, depth, width, clearance, angle, step, robot_x
):
    # a 2 mm change of the viewer moved the stepped-radius spot by ~0.2 m (generated
    # gallery_present with the context detected); the spot now moves at most a few times as
    # far as the viewer (away from a change of side, a discrete choice)
    art, facing = np.array([0.0, 0.0]), np.pi / 2
    viewer = np.array([lateral, depth])
    moved = viewer + step * np.array([np.cos(angle), np.sin(angle)])
    kw = dict(robot_position=(robot_x, 3.0), art_clearance=clearance)
    a = presenter_pose(art, width, facing, viewer, -np.pi / 2, **kw)
    b = presenter_pose(art, width, facing, moved, -np.pi / 2, **kw)
    assume(a.geometry.get("side") == b.geometry.get("side") and a.fallback == b.fallback)
    assert np.linalg.norm(b.position - a.position) <= 4.0 * step + 1e-9
    assert abs(float(wrap_angle(b.yaw - a.yaw))) <= 4.0 * step / 0.9 + 1e-9


def test_presenter_spot_keeps_out_of_every_viewer_and_faces_the_nearest():
    # generated gallery_present dev seed 28 (Pioneer, context given): the spot faced the
    # viewer it was built for while another viewer stood nearer (facing_viewer failed)
    viewer, other = np.array([13.3, 23.8]), np.array([12.6, 23.0])
    kw = dict(**ART, viewer_yaw=np.pi / 2, robot_position=(5, 17))
    goal = presenter_pose(**kw, viewer_position=viewer, other_viewers=[other])
    for v in (viewer, other):
        poly = activity_space_polygon(ART["art_center"], 1.2, -np.pi / 2, v)
        assert signed_distance_to_polygon(goal.position, poly) >= 0.35 - 1e-9
    nearest = min((viewer, other), key=lambda v: np.linalg.norm(v - goal.position))
    d = nearest - goal.position
    assert abs(float(wrap_angle(goal.yaw - np.arctan2(d[1], d[0])))) <= 0.5  # facing_viewer
    alone = presenter_pose(**kw, viewer_position=viewer)
    assert nearest is other  # the other viewer is the nearer one here
    d = other - alone.position
    assert abs(float(wrap_angle(alone.yaw - np.arctan2(d[1], d[0])))) > 0.5  # the old failure


def test_presenter_facing_holds_near_the_spot_between_two_viewers():
    # generated gallery_present dev seed 28 (PR2, context given): the spot is about as far from
    # viewers 1 and 2 (0.64 rad apart); facing the strictly nearest one failed ``facing_viewer``
    # for a robot 6 cm off the spot, where the other was the nearest
    viewers = np.array([[3.584, 1.955], [4.049, 1.172], [4.202, 2.424]])
    goal = presenter_pose(
        (3.717, 0.0),
        1.12,
        1.571,
        viewers[1],
        -1.718,
        robot_position=(1.97, 7.778),
        art_clearance=0.51,
        other_viewers=viewers[[0, 2]],
    )
    dist = np.sort(np.linalg.norm(viewers - goal.position, axis=1))
    assert dist[1] - dist[0] < 0.05  # the tie of the seed
    for a in np.linspace(0, 2 * np.pi, 16, endpoint=False):
        p = goal.position + 0.1 * np.array([np.cos(a), np.sin(a)])
        near = viewers[np.argmin(np.linalg.norm(viewers - p, axis=1))] - p
        assert abs(float(wrap_angle(goal.yaw - np.arctan2(near[1], near[0])))) <= 0.5


def test_presenter_side_follows_robot_and_mirrors():
    kw = dict(**ART, viewer_position=(13.0, 23.5), viewer_yaw=np.pi / 2)
    left = presenter_pose(**kw, robot_position=(5, 17))
    right = presenter_pose(**kw, robot_position=(21, 17))
    np.testing.assert_allclose(right.position, [26.0 - left.position[0], left.position[1]])


@settings(max_examples=40, deadline=None)
@given(
    theta=st.floats(-np.pi, np.pi),
    shift=st.tuples(st.floats(-30, 30), st.floats(-30, 30)),
    lateral=st.floats(-0.5, 0.5),
    depth=st.floats(0.8, 2.5),
    width=st.floats(0.4, 2.0),
    robot=st.tuples(st.floats(-10, 10), st.floats(-10, 10)),
)
def test_presenter_rigid_motion_equivariance(theta, shift, lateral, depth, width, robot):
    assume(abs(robot[0]) > 1e-3)  # the robot exactly on the art's axis is a side tie
    art, facing = np.array([0.0, 0.0]), np.pi / 2  # wall along x, room toward +y
    viewer = np.array([lateral, depth])
    goal = presenter_pose(art, width, facing, viewer, -np.pi / 2, robot_position=robot)
    shift = np.asarray(shift)
    goal_t = presenter_pose(
        rot(theta) @ art + shift,
        width,
        facing + theta,
        rot(theta) @ viewer + shift,
        -np.pi / 2 + theta,
        robot_position=rot(theta) @ np.asarray(robot) + shift,
    )
    assert_same_pose_under(goal, goal_t, theta, shift, atol=1e-6)
    if goal.fallback is None:
        poly = activity_space_polygon(art, width, facing, viewer)
        assert signed_distance_to_polygon(goal.position, poly) > 0
        assert 0.9 - 1e-9 <= np.linalg.norm(goal.position - viewer) <= 1.6 + 1e-9
        assert goal.position[1] >= 0.5 - 1e-9


def test_presenter_viewer_in_wall_and_blocked_fallbacks():
    inwall = presenter_pose(**ART, viewer_position=(13.0, 25.5), viewer_yaw=np.pi / 2)
    assert inwall.fallback is not None and inwall.reason
    blocked = presenter_pose(
        **ART,
        viewer_position=(13.0, 23.5),
        viewer_yaw=np.pi / 2,
        robot_position=(5, 17),
        free_fn=lambda p: p[:, 0] > 13.0,
    )
    assert blocked.fallback == "other_side" and blocked.position[0] > 13.0
    none = presenter_pose(
        **ART,
        viewer_position=(13.0, 23.5),
        viewer_yaw=np.pi / 2,
        free_fn=lambda p: np.zeros(len(p), bool),
    )
    assert none.fallback == "no_free_spot"


def segment_points(a, b, n=200):
    s = np.linspace(0.0, 1.0, n)[:, None]
    return np.asarray(a) + s * (np.asarray(b) - np.asarray(a))


def test_activity_waypoint_keeps_space_free():
    viewer, start, goal_xy = (13.0, 22.5), (7.0, 23.8), (19.0, 23.8)
    wp = activity_space_waypoint(
        **ART, viewer_position=viewer, robot_position=start, goal_position=goal_xy
    )
    assert wp.is_waypoint and wp.kind == "waypoint" and wp.fallback is None
    assert wp.geometry["direct_crosses"]
    assert_pose(wp, (13.0, 21.3), np.arctan2(2.5, 6.0))  # 1.2 m behind the viewer
    poly = activity_space_polygon(ART["art_center"], 1.2, -np.pi / 2, viewer)
    assert points_in_polygon(segment_points(start, goal_xy), poly).any()  # the direct line crosses
    legs = np.vstack([segment_points(start, wp.position), segment_points(wp.position, goal_xy)])
    assert (signed_distance_to_polygon(legs, poly) >= 0.4 - 1e-9).all()


def test_activity_waypoint_moves_farther_back_when_needed():
    # robot close behind the viewer's shoulder line: 1.2 m behind is not enough for 0.4 m margin
    viewer, start, goal_xy = (13.0, 22.5), (11.0, 22.0), (15.0, 22.0)
    wp = activity_space_waypoint(
        **ART, viewer_position=viewer, robot_position=start, goal_position=goal_xy
    )
    poly = activity_space_polygon(ART["art_center"], 1.2, -np.pi / 2, viewer)
    legs = np.vstack([segment_points(start, wp.position), segment_points(wp.position, goal_xy)])
    assert (signed_distance_to_polygon(legs, poly) >= 0.4 - 1e-9).all()
    assert wp.geometry["behind_distance"] >= 1.2

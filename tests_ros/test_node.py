"""The lifecycle node in this process: activation needs a map, parameters are typed, ranged and
partly dynamic, stale inputs stop the robot within its limits with an ERROR diagnostic."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator

import numpy as np
import pytest
import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import Pose, PoseArray, PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, qos_profile_sensor_data

from socialnav.core.robot import PIONEER
from socialnav.core.scene import Person
from socialnav.integrations.ros2.node import SocialNavNode

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


@pytest.fixture
def graph() -> Iterator[tuple[SocialNavNode, Node, SingleThreadedExecutor]]:
    rclpy.init()
    node = SocialNavNode(
        parameter_overrides=[
            Parameter("autostart", value=False),
            Parameter("odom_timeout", value=0.3),
            Parameter("people_timeout", value=0.5),
        ]
    )
    peer = rclpy.create_node("peer")
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    executor.add_node(peer)
    yield node, peer, executor
    executor.shutdown()
    node.destroy_node()
    peer.destroy_node()
    rclpy.try_shutdown()


def spin_until(executor: SingleThreadedExecutor, done: Callable[[], bool], timeout: float) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.01)
        if done():
            return True
    return False


def open_map() -> OccupancyGrid:
    msg = OccupancyGrid()
    msg.header.frame_id = "map"
    msg.info.resolution, msg.info.width, msg.info.height = 0.1, 100, 60
    msg.info.origin.position.x, msg.info.origin.position.y = -1.0, -3.0
    msg.info.origin.orientation.w = 1.0
    msg.data = [0] * (100 * 60)
    return msg


def test_refuses_to_activate_without_a_map(graph) -> None:
    node, peer, executor = graph
    diags: list[DiagnosticStatus] = []
    peer.create_subscription(DiagnosticArray, "/diagnostics", lambda m: diags.extend(m.status), 10)
    assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
    spin_until(executor, lambda: False, 0.3)  # discovery
    assert node.trigger_activate() == TransitionCallbackReturn.FAILURE
    assert node.state == "inactive"
    assert spin_until(executor, lambda: any("no map" in d.message for d in diags), 2.0)
    assert diags[-1].level == DiagnosticStatus.ERROR
    # with the map (latched, published before the node listened) it activates
    peer.create_publisher(OccupancyGrid, "map", LATCHED).publish(open_map())
    assert spin_until(executor, lambda: node.costmap is not None, 3.0)
    assert node.trigger_activate() == TransitionCallbackReturn.SUCCESS
    assert node.trigger_deactivate() == TransitionCallbackReturn.SUCCESS
    assert node.trigger_cleanup() == TransitionCallbackReturn.SUCCESS
    assert node.state == "unconfigured" and node.costmap is None
    assert node.trigger_shutdown() == TransitionCallbackReturn.SUCCESS


def test_parameters_are_typed_ranged_and_weights_dynamic(graph) -> None:
    node, _, _ = graph
    assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
    d = node.describe_parameter("max_vel_x")
    assert d.read_only and d.floating_point_range[0].to_value == 10.0 and "m/s" in d.description
    ok = node.set_parameters(
        [Parameter("path_distance_bias", value=1.5), Parameter("xy_goal_tolerance", value=0.3)]
    )
    assert all(r.successful for r in ok)
    assert node.planner_params.path_distance_bias == 1.5
    assert node.planner_params.xy_goal_tolerance == 0.3
    assert node._dirty  # the next cycle rebuilds the planner with them
    (bad,) = node.set_parameters([Parameter("path_distance_bias", value=-1.0)])
    assert not bad.successful
    (readonly,) = node.set_parameters([Parameter("max_vel_x", value=0.2)])
    assert not readonly.successful and node.robot.max_vel_x == PIONEER.max_vel_x
    (wrong_type,) = node.set_parameters([Parameter("heading_scale", value="high")])
    assert not wrong_type.successful
    assert node.planner_params.heading_scale == 0.2


def odom(node: Node, x: float, v: float) -> Odometry:
    msg = Odometry()
    msg.header.frame_id = "map"
    msg.header.stamp = node.get_clock().now().to_msg()
    msg.pose.pose.position.x = x
    msg.pose.pose.orientation.w = 1.0
    msg.twist.twist.linear.x = v
    return msg


def people(node: Node) -> PoseArray:
    msg = PoseArray(poses=[Pose()])
    msg.header.frame_id = "map"
    msg.header.stamp = node.get_clock().now().to_msg()
    msg.poses[0].position.x, msg.poses[0].position.y = 4.0, 2.0
    return msg


def activate_with_goal(node: SocialNavNode, peer: Node, executor: SingleThreadedExecutor):
    """Map, configure, activate, a goal 7 m ahead; the odometry and people publishers."""
    peer.create_publisher(OccupancyGrid, "map", LATCHED).publish(open_map())
    odom_pub = peer.create_publisher(Odometry, "odom", qos_profile_sensor_data)
    people_pub = peer.create_publisher(PoseArray, "people", qos_profile_sensor_data)
    goal_pub = peer.create_publisher(PoseStamped, "goal_pose", 10)
    assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
    assert spin_until(executor, lambda: node.costmap is not None, 3.0)
    assert node.trigger_activate() == TransitionCallbackReturn.SUCCESS
    spin_until(executor, lambda: goal_pub.get_subscription_count() > 0, 2.0)
    goal = PoseStamped()
    goal.header.frame_id = "map"
    goal.pose.position.x, goal.pose.orientation.w = 7.0, 1.0
    goal_pub.publish(goal)
    assert spin_until(executor, lambda: node.goal is not None, 2.0)
    return odom_pub, people_pub


@pytest.mark.parametrize("stale", ["odometry", "people"])
def test_stale_input_stops_within_the_limits(graph, stale: str) -> None:
    node, peer, executor = graph
    cmds: list[tuple[float, np.ndarray]] = []
    diags: list[DiagnosticStatus] = []
    peer.create_subscription(
        Twist,
        "cmd_vel",
        lambda m: cmds.append((time.monotonic(), np.array([m.linear.x, m.linear.y, m.angular.z]))),
        10,
    )
    peer.create_subscription(DiagnosticArray, "/diagnostics", lambda m: diags.extend(m.status), 10)
    odom_pub, people_pub = activate_with_goal(node, peer, executor)
    # drive with fresh inputs: the robot reports moving at 0.4 m/s
    x, end = 0.0, time.monotonic() + 1.0
    while time.monotonic() < end:
        x += 0.02
        odom_pub.publish(odom(peer, x, 0.4))
        people_pub.publish(people(peer))
        spin_until(executor, lambda: False, 0.05)
    moving = [c for _, c in cmds if c[0] > 0.2]
    assert moving, f"the robot never drove: {[d.message for d in diags[-3:]]}"
    n_before = len(cmds)
    end = time.monotonic() + 1.5
    while time.monotonic() < end:  # now one input goes quiet
        if stale == "people":
            x += 0.02
            odom_pub.publish(odom(peer, x, 0.4))
        else:
            people_pub.publish(people(peer))
        spin_until(executor, lambda: False, 0.05)
    after = np.array([c for _, c in cmds[n_before - 1 :]])
    assert np.allclose(after[-1], 0.0), after[-5:]
    period = 1.0 / node.values["controller_frequency"]
    steps = np.abs(np.diff(after, axis=0))
    # decelerating at most acc_lim per cycle (2 periods of slack for watchdog jitter)
    assert np.all(steps[:, 0] <= PIONEER.acc_lim_x * 2 * period + 1e-9), steps[:, 0]
    errors = [d for d in diags if d.level == DiagnosticStatus.ERROR]
    assert errors and f"{stale} older than" in errors[-1].message


def test_periodic_replan_runs_off_the_control_cycle(graph) -> None:
    """With the default ``replan_mode`` the periodic global replan runs on the navigator's
    worker thread, not in the cycle; a rebuilt planner's worker is stopped."""
    node, peer, executor = graph
    odom_pub, people_pub = activate_with_goal(node, peer, executor)
    assert node.values["replan_mode"] == "deferred"
    threads: list[str] = []
    x, end, patched = 0.0, time.monotonic() + 3.0, None
    while time.monotonic() < end:
        nav = node.navigator
        if nav is not None and nav is not patched:  # record where each plan is computed
            compute = nav._compute_plan

            def traced(*args, _compute=compute):
                threads.append(threading.current_thread().name)
                return _compute(*args)

            nav._compute_plan, patched = traced, nav
        x += 0.02
        odom_pub.publish(odom(peer, x, 0.4))
        people_pub.publish(people(peer))
        spin_until(executor, lambda: False, 0.05)
    assert patched is node.navigator and patched.global_search == "compiled"
    # (the first plan, inline, came before the patch) every later one ran on the worker
    assert threads and all(name.startswith("socialnav-replan") for name in threads), threads
    ok = node.set_parameters([Parameter("path_distance_bias", value=1.5)])
    assert all(r.successful for r in ok)
    spin_until(executor, lambda: node.navigator is not patched, 1.0)  # no odometry: watchdog
    x += 0.02
    odom_pub.publish(odom(peer, x, 0.4))
    people_pub.publish(people(peer))
    assert spin_until(executor, lambda: node.navigator is not patched, 2.0)
    assert patched._executor is None  # closed when the planner was rebuilt


@pytest.mark.parametrize("good", [True, False])
def test_context_file_is_read_at_configure(tmp_path, good: bool) -> None:
    path = tmp_path / "context.yaml"
    path.write_text("groups:\n  - members: [[1, 1], [2, 1]]\n" if good else "groups: 3\n")
    rclpy.init()
    node = SocialNavNode(
        parameter_overrides=[
            Parameter("autostart", value=False),
            Parameter("social_context_file", value=str(path)),
        ]
    )
    try:
        result = node.trigger_configure()
        if good:
            assert result == TransitionCallbackReturn.SUCCESS
            social = node.context_file.resolve((Person(1, (1.0, 1.1)), Person(2, (2.0, 0.9))))
            assert social.groups[0].member_ids == (1, 2)
        else:
            assert result == TransitionCallbackReturn.FAILURE and node.state == "unconfigured"
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


@pytest.mark.parametrize(("context_file", "detect"), [(False, True), (False, False), (True, True)])
def test_without_a_context_file_the_estimator_supplies_groups(
    tmp_path, context_file: bool, detect: bool
) -> None:
    path = tmp_path / "context.yaml"
    path.write_text("groups:\n  - members: [[1, 1], [2, 1]]\n")
    overrides = [
        Parameter("autostart", value=False),
        Parameter("detect_social_context", value=detect),
    ]
    if context_file:
        overrides.append(Parameter("social_context_file", value=str(path)))
    rclpy.init()
    node = SocialNavNode(parameter_overrides=overrides)
    try:
        assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
        if context_file or not detect:
            assert node.estimator is None
            return
        assert node.estimator is not None
        # two people facing each other 1.2 m apart: a conversation once hysteresis is on
        pair = (Person(1, (1.0, 1.0), yaw=0.0), Person(2, (2.2, 1.0), yaw=np.pi))
        for k in range(6):
            social = node.estimator.update(0.1 * k, pair).context
        assert [g.member_ids for g in social.groups] == [(1, 2)]
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


def test_topics_are_remappable() -> None:
    rclpy.init()
    node = SocialNavNode(
        cli_args=["--ros-args", "-r", "odom:=/wheel/odom", "-r", "cmd_vel:=/base/cmd_vel"],
        parameter_overrides=[Parameter("autostart", value=False)],
    )
    try:
        assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
        assert "/wheel/odom" in [sub.topic_name for sub in node._subs]
        assert node._pubs["cmd_vel"].topic_name == "/base/cmd_vel"
        assert node._pubs["plan"].topic_name == "/plan"
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


def test_people_entering_and_leaving_keep_the_planner(graph, monkeypatch) -> None:
    """The planner is built once per goal: people entering and leaving the view change its
    objective set, not the planner (a rebuild would drop its plan and the replan in flight)."""
    import socialnav.integrations.ros2.node as node_module

    built: list[object] = []
    real_build = node_module.build_navigator

    def counting_build(*args, **kwargs):
        built.append(real_build(*args, **kwargs))
        return built[-1]

    monkeypatch.setattr(node_module, "build_navigator", counting_build)
    node, peer, executor = graph
    odom_pub, people_pub = activate_with_goal(node, peer, executor)
    seen: list[tuple[int, tuple[str, ...]]] = []
    patched = None
    x, k, end = 0.0, 0, time.monotonic() + 4.5
    while time.monotonic() < end:
        nav = node.navigator
        if nav is not None and nav is not patched:
            step = nav.step

            def traced(t, pose, velocity, social, _step=step):
                result = _step(t, pose, velocity, social)
                names = result.record.objective_names if result.record is not None else ()
                seen.append((len(social.people), names))
                return result

            nav.step, patched = traced, nav
        x += 0.02
        odom_pub.publish(odom(peer, x, 0.4))
        if (k // 30) % 2 == 0:  # 1.5 s with a person in view, 1.5 s without (tracks: 1 s)
            people_pub.publish(people(peer))
        else:
            empty = PoseArray()
            empty.header.frame_id = "map"
            empty.header.stamp = peer.get_clock().now().to_msg()
            people_pub.publish(empty)
        k += 1
        spin_until(executor, lambda: False, 0.05)
    counts = {n for n, _ in seen}
    assert 0 in counts and 1 in counts, counts
    assert len(built) == 1 and node.navigator is built[0]
    with_people = {names for n, names in seen if n and names}
    without = {names for n, names in seen if not n and names}
    assert with_people and without and with_people.isdisjoint(without)

"""The socialnav lifecycle node: the planner in a ROS 2 control loop (rclpy, extra ``ros``).

A managed node like Nav2's servers (``configure``, ``activate``, ``deactivate``, ``cleanup``,
``shutdown``; with ``autostart`` it brings itself up, as Nav2's lifecycle manager would).
Topics (names relative, so remappable with ``--ros-args -r odom:=/wheel/odom``):

========================  ===================================  ==================================
``odom``                  nav_msgs/Odometry (sub)              robot pose and body twist
``map``                   nav_msgs/OccupancyGrid (sub)         transient-local, like map_server
``goal_pose``             geometry_msgs/PoseStamped (sub)      a new goal replaces the old one
``people``                geometry_msgs/PoseArray (sub)        detections; ids and velocities are
                                                               estimated (:mod:`.people`)
``cmd_vel``               geometry_msgs/Twist or TwistStamped  body twist; stamped by parameter
``plan``                  nav_msgs/Path                        the global plan being followed
``local_plan``            nav_msgs/Path                        the chosen trajectory's rollout
``social_goal``           geometry_msgs/PoseStamped            the target the planner drives to
``socialnav/candidates``  visualization_msgs/MarkerArray       every rollout: legal green, illegal
                                                               red, chosen blue
``socialnav/people``      visualization_msgs/MarkerArray       tracked people, velocity, id
``/diagnostics``          diagnostic_msgs/DiagnosticArray      status, ms per cycle, legal count,
                                                               rejection reasons, input ages
========================  ===================================  ==================================

Decisions:
- A control cycle runs on each odometry message once ``1 / controller_frequency`` s have passed
  since the last one, so a command answers the freshest pose; a watchdog timer at the same rate
  runs the cycle when odometry stops arriving. A stamped command carries the stamp of the
  odometry it answers (Nav2 stamps ``now``), so a subscriber measures odometry-to-command
  latency.
- Safety: odometry older than ``odom_timeout`` s, or people older than ``people_timeout`` s
  (with ``require_people``; a robot that cannot see people must not drive among them), turn
  the command into a stop within the acceleration limits and an ERROR diagnostic; the goal is
  kept and the robot resumes when the input is fresh again.
- No map: activation is refused with a log line saying which topic to publish; ``autostart``
  retries every second.
- There is no tf listener (the ROS wheels carry no tf2): odometry, goals and people must be in
  ``global_frame`` or in ``odom_frame``, placed by the fixed ``odom_to_global`` transform.
  Messages in other frames are refused with a throttled error.
- Groups, queues and artworks come from ``social_context_file`` (:mod:`.context`): structures
  placed by their members' positions and attached to the tracked people every cycle. Without
  a file and with ``detect_social_context`` (the default), conversational groups, walking
  groups and queues are estimated from the tracked people every cycle
  (:class:`~socialnav.social.perception.ContextEstimator`, as ``--context detected`` in the
  simulator); the planner then receives the estimator's context.
- The global replan runs off the control cycle (``replan_mode``, default ``deferred``: the
  compiled search on a worker thread, its plan used two cycles later and planned from where
  the robot will be then, as Nav2 separates its planner and controller servers; a new goal
  or leaving the plan still replans inside the cycle).
- The planner is rebuilt (``build_navigator``) on a new goal, a new map or a parameter change,
  and only then: its objective set follows the people, groups, queues and viewed artworks in
  view every cycle, so people entering or leaving the view keep its global plan, social goal
  and recovery state.
- Weights (``path_distance_bias``, ``goal_distance_bias``, ``occdist_scale``, ``heading_scale``)
  and tolerances (``xy_goal_tolerance``, ``yaw_goal_tolerance``) may change at run time; every
  other parameter is read-only once declared.
"""

from __future__ import annotations

import math
import time as wall
from collections.abc import Sequence
from typing import Any

import numpy as np
import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import Point, Pose, PoseArray, PoseStamped, Twist, TwistStamped, Vector3
from nav_msgs.msg import OccupancyGrid, Odometry, Path
from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    SetParametersResult,
)
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
from std_msgs.msg import ColorRGBA, Header
from visualization_msgs.msg import Marker, MarkerArray

from socialnav.core.errors import SocialNavError
from socialnav.core.geometry import FloatArray
from socialnav.core.scene import SocialContext
from socialnav.integrations.ros2.context import ContextFile, load_context_file
from socialnav.integrations.ros2.convert import (
    compose,
    costmap_from_occupancy,
    decelerate,
    quaternion_from_yaw,
    yaw_from_quaternion,
)
from socialnav.integrations.ros2.params import (
    DEFAULT_NODE_NAME,
    ParamSpec,
    local_planner_params,
    param_specs,
    robot_from_params,
    validate_value,
)
from socialnav.integrations.ros2.people import PeopleTracker, TrackerParams
from socialnav.planner.presets import build_navigator
from socialnav.planner.rollout import rollout
from socialnav.social.perception import ContextEstimator

__all__ = ["SocialNavNode", "main"]

LEVELS = {
    "OK": DiagnosticStatus.OK,
    "GOAL_REACHED": DiagnosticStatus.OK,
    "ROTATING_TO_GOAL": DiagnosticStatus.OK,
    "ROTATING_TO_PLAN": DiagnosticStatus.OK,
    "WAITING": DiagnosticStatus.OK,
    "INVALID_INPUT": DiagnosticStatus.ERROR,
    "CRITIC_UNAVAILABLE": DiagnosticStatus.ERROR,
}
DIAGNOSTIC_NAME = "socialnav: controller"
CANDIDATE_POINTS = 6  # points per drawn candidate rollout


def _descriptor(spec: ParamSpec) -> ParameterDescriptor:
    d = ParameterDescriptor(description=spec.description, read_only=not spec.dynamic)
    if spec.kind is float and spec.min is not None and spec.max is not None:
        d.floating_point_range = [
            FloatingPointRange(from_value=float(spec.min), to_value=float(spec.max), step=0.0)
        ]
    elif spec.kind is int and spec.min is not None and spec.max is not None:
        d.integer_range = [IntegerRange(from_value=int(spec.min), to_value=int(spec.max), step=1)]
    if spec.choices:
        d.additional_constraints = "one of: " + ", ".join(spec.choices)
    return d


def _seconds(stamp: Any) -> float:
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def _pose2d(pose: Pose) -> FloatArray:
    q = pose.orientation
    return np.array([pose.position.x, pose.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w)])


def _pose_msg(x: float, y: float, yaw: float) -> Pose:
    msg = Pose()
    msg.position.x, msg.position.y = float(x), float(y)
    qx, qy, qz, qw = quaternion_from_yaw(float(yaw))
    msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = qx, qy, qz, qw
    return msg


class SocialNavNode(LifecycleNode):  # type: ignore[misc]
    """The lifecycle node (see the module docstring). Construct after ``rclpy.init``."""

    def __init__(self, node_name: str = DEFAULT_NODE_NAME, **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        # The robot model and the planner set other parameters' defaults: declared first.
        first = {s.name: s for s in param_specs() if s.name in ("robot_model", "planner")}
        chosen: dict[str, Any] = {
            name: self.declare_parameter(name, spec.default, _descriptor(spec)).value
            for name, spec in first.items()
        }
        self.specs = {
            s.name: s for s in param_specs(str(chosen["robot_model"]), str(chosen["planner"]))
        }
        for spec in self.specs.values():
            if spec.name not in first:
                self.declare_parameter(spec.name, spec.default, _descriptor(spec))
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.state = "unconfigured"
        self._subs: list[Any] = []
        self._pubs: dict[str, Any] = {}
        self._timer: Any = None
        self._reset_state()
        self._autostart = None
        if self.get_parameter("autostart").value:
            self._autostart = self.create_timer(1.0, self._bring_up)
            self._bring_up()

    # ---- lifecycle ------------------------------------------------------------------------
    def _bring_up(self) -> None:
        if self.state == "unconfigured":
            self.trigger_configure()
        if self.state == "inactive":
            self.trigger_activate()
        if self.state in ("active", "finalized") and self._autostart is not None:
            self.destroy_timer(self._autostart)
            self._autostart = None

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        try:
            self._read_parameters()
        except SocialNavError as exc:
            self.get_logger().error(f"configure failed: {exc}")
            return TransitionCallbackReturn.FAILURE
        twist = TwistStamped if self.values["enable_stamped_cmd_vel"] else Twist
        latched = QoSProfile(
            depth=1,
            durability=DurabilityPolicy.TRANSIENT_LOCAL,
            reliability=ReliabilityPolicy.RELIABLE,
        )
        self._pubs = {
            "cmd_vel": self.create_lifecycle_publisher(twist, "cmd_vel", 10),
            "plan": self.create_lifecycle_publisher(Path, "plan", 1),
            "local_plan": self.create_lifecycle_publisher(Path, "local_plan", 1),
            "social_goal": self.create_lifecycle_publisher(PoseStamped, "social_goal", latched),
            "candidates": self.create_lifecycle_publisher(MarkerArray, "socialnav/candidates", 1),
            "people": self.create_lifecycle_publisher(MarkerArray, "socialnav/people", 1),
            # a plain publisher: diagnostics explain an inactive node too
            "diagnostics": self.create_publisher(DiagnosticArray, "/diagnostics", 10),
        }
        self._subs = [
            self.create_subscription(Odometry, "odom", self._on_odom, qos_profile_sensor_data),
            self.create_subscription(OccupancyGrid, "map", self._on_map, latched),
            self.create_subscription(PoseStamped, "goal_pose", self._on_goal, 10),
            self.create_subscription(PoseArray, "people", self._on_people, qos_profile_sensor_data),
        ]
        self.state = "inactive"
        self.get_logger().info(
            f"configured: planner {self.values['planner']}, robot {self.robot.name}, "
            f"{self.values['controller_frequency']:g} Hz"
        )
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.costmap is None:
            topic = self.resolve_topic_name("map")
            self.get_logger().error(
                f"refusing to activate: no map received on {topic} (nav_msgs/OccupancyGrid, "
                "transient-local, as map_server publishes it)"
            )
            self._publish_diagnostics(DiagnosticStatus.ERROR, "inactive: no map", {})
            return TransitionCallbackReturn.FAILURE
        result = super().on_activate(state)
        if result != TransitionCallbackReturn.SUCCESS:
            return result
        self._timer = self.create_timer(self.period, self._on_watchdog)
        self.state = "active"
        self.get_logger().info("active")
        return TransitionCallbackReturn.SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._publish_cmd(np.zeros(3), None)  # as Nav2's controller: stop before going quiet
        if self._timer is not None:
            self.destroy_timer(self._timer)
            self._timer = None
        self.state = "inactive"
        return super().on_deactivate(state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._teardown()
        self.state = "unconfigured"
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.state == "active":
            self._publish_cmd(np.zeros(3), None)
        self._teardown()
        self.state = "finalized"
        return TransitionCallbackReturn.SUCCESS

    def _teardown(self) -> None:
        if self._timer is not None:
            self.destroy_timer(self._timer)
            self._timer = None
        for sub in self._subs:
            self.destroy_subscription(sub)
        for name, pub in self._pubs.items():
            if name == "diagnostics":
                self.destroy_publisher(pub)
            else:
                self.destroy_lifecycle_publisher(pub)
        self._subs, self._pubs = [], {}
        self._reset_state()

    # ---- parameters -----------------------------------------------------------------------
    def _read_parameters(self) -> None:
        self.values = {name: self.get_parameter(name).value for name in self.specs}
        self.values["odom_to_global"] = list(self.values["odom_to_global"])
        self.robot = robot_from_params(self.values)
        self.planner_params = local_planner_params(self.values)
        self.period = 1.0 / float(self.values["controller_frequency"])
        self.context_file: ContextFile | None = None
        if self.values["social_context_file"]:
            self.context_file = load_context_file(
                self.values["social_context_file"], self.values["social_match_radius"]
            )
        self.estimator: ContextEstimator | None = None
        if self.context_file is None and self.values["detect_social_context"]:
            self.estimator = ContextEstimator()
        self.tracker = PeopleTracker(
            TrackerParams(
                gate=self.values["people_gate"],
                timeout=self.values["people_track_timeout"],
                max_speed=self.values["people_max_speed"],
                radius=self.values["person_radius"],
            )
        )

    def _on_set_parameters(self, params: Sequence[Parameter]) -> SetParametersResult:
        changes: dict[str, Any] = {}
        for p in params:
            spec = self.specs.get(p.name)
            if spec is None:
                return SetParametersResult(successful=False, reason=f"unknown parameter {p.name}")
            try:
                changes[p.name] = validate_value(spec, p.value)
            except SocialNavError as exc:
                return SetParametersResult(successful=False, reason=str(exc))
        if not hasattr(self, "values"):  # not configured: read at configure
            return SetParametersResult(successful=True)
        merged = {**self.values, **changes}
        try:
            planner_params = local_planner_params(merged)
        except SocialNavError as exc:
            return SetParametersResult(successful=False, reason=str(exc))
        self.values, self.planner_params = merged, planner_params
        self._dirty = True
        self.get_logger().info(
            "parameters changed: " + ", ".join(f"{k}={v}" for k, v in changes.items())
        )
        return SetParametersResult(successful=True)

    # ---- state ----------------------------------------------------------------------------
    def _close_navigator(self) -> None:
        if getattr(self, "navigator", None) is not None:
            self.navigator.close()

    def _reset_state(self) -> None:
        self._close_navigator()
        self.costmap: Any = None
        self.goal: FloatArray | None = None
        self.navigator: Any = None
        self._dirty = True
        self._odom: tuple[FloatArray, FloatArray, float, Any] | None = None
        self._odom_rx = -math.inf
        self._people_rx = -math.inf
        self._last_cycle = -math.inf
        self._last_cmd = np.zeros(3)
        self.cycle_ms: list[float] = []
        self.last_status = "IDLE"
        if hasattr(self, "tracker"):
            self.tracker.reset()

    def _now(self) -> float:
        return float(self.get_clock().now().nanoseconds) * 1e-9

    def _to_global(self, header: Header, pose: FloatArray, what: str) -> FloatArray | None:
        frame = header.frame_id.lstrip("/")
        if frame in ("", self.values["global_frame"]):
            return pose
        if frame == self.values["odom_frame"]:
            return compose(self.values["odom_to_global"], pose)
        self.get_logger().error(
            f"{what} in frame {frame!r}: expected {self.values['global_frame']!r} or "
            f"{self.values['odom_frame']!r} (no tf listener)",
            throttle_duration_sec=2.0,
        )
        return None

    # ---- subscriptions --------------------------------------------------------------------
    def _on_map(self, msg: OccupancyGrid) -> None:
        info = msg.info
        origin = _pose2d(info.origin)
        try:
            self.costmap = costmap_from_occupancy(
                np.asarray(msg.data, dtype=np.int8),
                info.width,
                info.height,
                info.resolution,
                origin,
                self.robot,
                self.values["inflation_radius"],
                self.values["cost_scaling_factor"],
            )
        except SocialNavError as exc:
            self.get_logger().error(f"map refused: {exc}")
            return
        self._dirty = True
        self.get_logger().info(f"map {info.width} x {info.height} at {info.resolution:g} m/cell")

    def _on_goal(self, msg: PoseStamped) -> None:
        goal = self._to_global(msg.header, _pose2d(msg.pose), "goal")
        if goal is None or not np.all(np.isfinite(goal)):
            return
        self.goal = goal
        self._dirty = True
        self.get_logger().info(f"new goal ({goal[0]:.2f}, {goal[1]:.2f}, {goal[2]:.2f})")

    def _on_people(self, msg: PoseArray) -> None:
        stamp = _seconds(msg.header.stamp) or self._now()
        poses = [_pose2d(p) for p in msg.poses]
        yaws = [
            np.nan
            if (p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w)
            == (0.0, 0.0, 0.0, 0.0)
            else pose[2]
            for p, pose in zip(msg.poses, poses, strict=True)
        ]
        converted = []
        for pose in poses:
            g = self._to_global(msg.header, pose, "people")
            if g is None:
                return
            converted.append(g)
        xy = np.array(converted, dtype=float).reshape(-1, 3)
        yaw = xy[:, 2].copy()
        yaw[np.isnan(np.asarray(yaws, dtype=float))] = np.nan
        self.tracker.update(stamp, xy[:, :2], yaw)
        self._people_rx = self._now()

    def _on_odom(self, msg: Odometry) -> None:
        pose = self._to_global(msg.header, _pose2d(msg.pose.pose), "odometry")
        if pose is None:
            return
        tw = msg.twist.twist
        velocity = np.array([tw.linear.x, tw.linear.y, tw.angular.z])
        self._odom = (pose, velocity, _seconds(msg.header.stamp), msg.header.stamp)
        self._odom_rx = self._now()
        if self.state == "active" and self._odom_rx - self._last_cycle >= 0.95 * self.period:
            self._cycle()

    def _on_watchdog(self) -> None:
        if self._now() - self._last_cycle >= 1.5 * self.period:
            self._cycle()

    # ---- the control cycle ----------------------------------------------------------------
    def _cycle(self) -> None:
        now = self._now()
        dt = min(max(now - self._last_cycle, 0.0), 2 * self.period)
        self._last_cycle = now
        ages = {
            "odom_age_s": now - self._odom_rx,
            "people_age_s": now - self._people_rx,
        }
        if self.goal is None:
            self._publish_diagnostics(DiagnosticStatus.OK, "idle: no goal", ages)
            return
        stale = []
        if self._odom is None or ages["odom_age_s"] > self.values["odom_timeout"]:
            stale.append(f"odometry older than {self.values['odom_timeout']:g} s")
        if self.values["require_people"] and ages["people_age_s"] > self.values["people_timeout"]:
            stale.append(f"people older than {self.values['people_timeout']:g} s")
        if stale:
            cmd = decelerate(self._last_cmd, self.robot, dt)
            self._publish_cmd(cmd, self._odom[3] if self._odom else None)
            self.last_status = "STALE_INPUT"
            self._publish_diagnostics(DiagnosticStatus.ERROR, "stopping: " + "; ".join(stale), ages)
            return
        assert self._odom is not None
        pose, velocity, t, stamp = self._odom
        start = wall.perf_counter()
        people = self.tracker.people(time=t)
        if self.context_file is None and self.estimator is not None:
            social = self.estimator.update(t, people).context
        elif self.context_file is None:
            social = SocialContext(people)
        else:
            social = self.context_file.resolve(people)
        # Rebuilt only when what it was built for changes: its objective set follows the
        # people in view every cycle, so people entering or leaving keep its global plan,
        # social goal, recovery state and the replan in flight.
        if self._dirty or self.navigator is None:
            self._close_navigator()  # its replan in flight is for the old configuration
            self.navigator = build_navigator(
                str(self.values["planner"]),
                self.robot,
                self.costmap,
                self.goal,
                social,
                record=True,
                params=self.planner_params,
                global_search="compiled",
                replan_mode=self.values["replan_mode"],  # validated: one of the choices
            )
            self._dirty = False
        result = self.navigator.step(t, pose, velocity, social)
        ms = (wall.perf_counter() - start) * 1e3
        self.cycle_ms = [*self.cycle_ms[-99:], ms]
        self._publish_cmd(result.cmd, stamp)
        status = str(result.status)
        self.last_status = status
        record = result.record
        header = Header(stamp=stamp, frame_id=self.values["global_frame"])
        self._publish_plans(header, pose, velocity, result)
        self._publish_people(header, social)
        if record is not None and self.values["publish_candidates"]:
            self._publish_candidates(header, pose, velocity, record)
        values: dict[str, Any] = {
            **ages,
            "status": status,
            "ms_per_cycle": round(ms, 2),
            "people": len(social.people),
        }
        if record is not None:
            values["legal"] = f"{record.num_legal}/{record.num_samples}"
            values["rejections"] = record.rejection_summary()
        message = status + (f": {result.message}" if result.message else "")
        self._publish_diagnostics(LEVELS.get(status, DiagnosticStatus.WARN), message, values)
        if status == "GOAL_REACHED":
            self.get_logger().info("goal reached")
            self.goal = None
            self._publish_cmd(np.zeros(3), stamp)

    # ---- publications ---------------------------------------------------------------------
    def _publish_cmd(self, cmd: FloatArray, stamp: Any) -> None:
        pub = self._pubs.get("cmd_vel")
        c = np.asarray(cmd, dtype=float)
        self._last_cmd = c.copy()
        if pub is None:
            return
        twist = Twist(
            linear=Vector3(x=float(c[0]), y=float(c[1]), z=0.0),
            angular=Vector3(x=0.0, y=0.0, z=float(c[2])),
        )
        if self.values["enable_stamped_cmd_vel"]:
            header = Header(frame_id=self.values["robot_base_frame"])
            header.stamp = stamp if stamp is not None else self.get_clock().now().to_msg()
            pub.publish(TwistStamped(header=header, twist=twist))
        else:
            pub.publish(twist)

    def _path_msg(self, header: Header, xy: FloatArray, yaw: FloatArray | None = None) -> Path:
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        if yaw is None:
            d = np.diff(xy, axis=0)
            yaw = np.arctan2(d[:, 1], d[:, 0]) if len(d) else np.zeros(0)
            yaw = np.append(yaw, yaw[-1] if len(yaw) else 0.0)
        return Path(
            header=header,
            poses=[
                PoseStamped(header=header, pose=_pose_msg(x, y, a))
                for (x, y), a in zip(xy, yaw, strict=True)
            ],
        )

    def _publish_plans(
        self, header: Header, pose: FloatArray, velocity: FloatArray, result: Any
    ) -> None:
        path = self.navigator.global_path
        if path is not None:
            self._pubs["plan"].publish(self._path_msg(header, path))
        cmd = np.asarray(result.cmd, dtype=float).reshape(1, 3)
        local = rollout(pose, velocity, cmd, self.robot, self.planner_params)
        poses = local.poses[0]
        self._pubs["local_plan"].publish(self._path_msg(header, poses[:, :2], poses[:, 2]))
        target = result.target
        if target is None and result.record is not None:
            target = result.record.goal
        if target is not None:
            g = np.asarray(target, dtype=float)
            self._pubs["social_goal"].publish(
                PoseStamped(header=header, pose=_pose_msg(g[0], g[1], g[2]))
            )

    def _marker(
        self, header: Header, ns: str, mid: int, kind: int, rgba: Sequence[float]
    ) -> Marker:
        m = Marker(header=header, ns=ns, id=mid, type=kind, action=Marker.ADD)
        m.pose.orientation.w = 1.0
        m.color = ColorRGBA(r=rgba[0], g=rgba[1], b=rgba[2], a=rgba[3])
        return m

    def _publish_candidates(
        self, header: Header, pose: FloatArray, velocity: FloatArray, record: Any
    ) -> None:
        if record.num_samples == 0 or self._pubs["candidates"].get_subscription_count() == 0:
            return
        traj = rollout(pose, velocity, record.twists, self.robot, self.planner_params)
        idx = np.unique(np.linspace(0, traj.poses.shape[1] - 1, CANDIDATE_POINTS).astype(int))
        xy = traj.poses[:, idx, :2]
        markers = []
        for mid, (mask, rgba) in enumerate(
            ((record.legal, (0.1, 0.8, 0.2, 0.5)), (~record.legal, (0.9, 0.1, 0.1, 0.25)))
        ):
            m = self._marker(header, "candidates", mid, Marker.LINE_LIST, rgba)
            m.scale.x = 0.01
            segs = np.stack([xy[mask, :-1], xy[mask, 1:]], axis=2).reshape(-1, 2)
            m.points = [Point(x=float(x), y=float(y), z=0.0) for x, y in segs]
            markers.append(m)
        chosen = self._marker(header, "candidates", 2, Marker.LINE_STRIP, (0.1, 0.3, 1.0, 1.0))
        chosen.scale.x = 0.04
        if record.chosen is not None:
            chosen.points = [Point(x=float(x), y=float(y), z=0.0) for x, y in xy[record.chosen]]
        else:
            chosen.action = Marker.DELETE
        markers.append(chosen)
        self._pubs["candidates"].publish(MarkerArray(markers=markers))

    def _publish_people(self, header: Header, social: SocialContext) -> None:
        if self._pubs["people"].get_subscription_count() == 0:
            return
        clear = Marker(header=header, ns="people", action=Marker.DELETEALL)
        markers = [clear]
        for p in social.people:
            body = self._marker(header, "people", 3 * p.id, Marker.CYLINDER, (0.2, 0.4, 0.9, 0.7))
            body.pose = _pose_msg(p.position[0], p.position[1], p.yaw)
            body.pose.position.z = 0.85
            body.scale = Vector3(x=2 * p.radius, y=2 * p.radius, z=1.7)
            arrow = self._marker(header, "people", 3 * p.id + 1, Marker.ARROW, (1.0, 0.6, 0.0, 1.0))
            arrow.scale = Vector3(x=0.05, y=0.1, z=0.1)
            x, y = p.position
            arrow.points = [
                Point(x=x, y=y, z=0.1),
                Point(x=x + p.velocity[0], y=y + p.velocity[1], z=0.1),
            ]
            text = self._marker(
                header, "people", 3 * p.id + 2, Marker.TEXT_VIEW_FACING, (1.0, 1.0, 1.0, 1.0)
            )
            text.pose = _pose_msg(x, y, 0.0)
            text.pose.position.z = 1.9
            text.scale.z = 0.3
            text.text = str(p.id)
            markers += [body, arrow, text]
        self._pubs["people"].publish(MarkerArray(markers=markers))

    def _publish_diagnostics(self, level: bytes, message: str, values: dict[str, Any]) -> None:
        pub = self._pubs.get("diagnostics")
        if pub is None:
            return
        status = DiagnosticStatus(
            level=level,
            name=DIAGNOSTIC_NAME,
            message=message,
            hardware_id=self.get_name(),
            values=[KeyValue(key="lifecycle_state", value=self.state)]
            + [
                KeyValue(key=k, value=f"{v:.3f}" if isinstance(v, float) else str(v))
                for k, v in values.items()
            ],
        )
        pub.publish(
            DiagnosticArray(header=Header(stamp=self.get_clock().now().to_msg()), status=[status])
        )


def main(params_file: str | None = None, ros_args: Sequence[str] = ()) -> int:
    """Run the node until Ctrl-C / SIGTERM; ``params_file`` is passed to rcl as
    ``--params-file`` (after :func:`~socialnav.integrations.ros2.params.load_params_file` has
    validated it). Returns the process exit code."""
    import signal

    from rclpy.executors import SingleThreadedExecutor
    from rclpy.signals import SignalHandlerOptions

    args = ["--ros-args", *ros_args]
    if params_file:
        args += ["--params-file", str(params_file)]
    stop: list[int] = []
    # Our handlers, not rclpy's: the node must still publish its stop after Ctrl-C / SIGTERM.
    signal.signal(signal.SIGINT, lambda signum, _: stop.append(signum))
    signal.signal(signal.SIGTERM, lambda signum, _: stop.append(signum))
    rclpy.init(args=["socialnav", *args], signal_handler_options=SignalHandlerOptions.NO)
    node = SocialNavNode()
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    try:
        while not stop and rclpy.ok():
            executor.spin_once(timeout_sec=0.1)
    finally:
        if rclpy.ok() and node.state != "finalized":
            node.trigger_shutdown()  # publishes a zero command when active
        node.destroy_node()
        rclpy.try_shutdown()
    return 0

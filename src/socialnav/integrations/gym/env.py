"""``SocialNavEnv``: one robot among people in a socialnav scenario, as a Gymnasium 1.x ``Env``.

The simulation is the one ``socialnav compare`` runs (``socialnav.sim``: navground world,
scripted or reactive people, footprint collisions), stepped one control period ``dt`` (the
scenario's, 0.1 s) per ``step``. The episode is recorded as an
:class:`~socialnav.core.episode.EpisodeRecord` with the same timing as ``run_episode``, so
:meth:`SocialNavEnv.episode_record` gives exactly what ``socialnav compare`` measures, and at the
end of an episode ``info["metrics"]`` / ``info["success"]`` hold ``compute_metrics`` and
``evaluate_success`` of it.

Spaces (all ``float32`` unless said; "robot frame": x forward, y left, origin at the robot):

- ``action``: ``Box(3)``, the body twist ``(vx, vy, wz)`` in m/s, rad/s, within the robot's
  box limits (``[min_vel_x, max_vel_x] × [−max_vel_y, max_vel_y] × [−max_vel_theta,
  max_vel_theta]``; ``vy`` is 0 for a differential drive). Out-of-range actions are clipped.
  Commands act at once (as in Stage); acceleration limits are the policy's business.
- ``observation``: a ``Dict``:

  - ``robot (3,)``: the robot's body twist (the last command);
  - ``goal (3,)``: the given goal ``(x, y, yaw)`` in the robot frame;
  - ``social_goal (4,)``: the target of the episode (the social goal where the scenario's
    structure yields one — a queue's tail, a group's free spot, the presenter spot — else the
    goal; resolved from the scenario at reset, ``socialnav.sim.target.resolve_target``, and the
    target success is measured at) in the robot frame, and ``1`` if a social goal applies,
    else ``0``;
  - ``people (N, 5)``: the ``N = max_people`` nearest people (nearest first): relative position
    ``(x, y)`` and velocity ``(vx, vy)`` (theirs minus the robot's) in the robot frame, and ``1``
    for a row that holds a person (rows beyond the people present are zeros);
  - ``costmap (C, C)`` ``uint8`` (only with ``costmap_cells > 0``): the static inflated costmap
    (costmap_2d values) in a ``C × C`` world-aligned window centred on the robot (a ROS rolling
    window, row 0 at the lowest y), cells off the map ``255``.
- ``reward``: :mod:`socialnav.integrations.gym.reward` (documented term by term).
- ``terminated``: the robot stopped (``|cmd| < 1e-3``) at the target: within the success
  tolerance (``max(goal_tolerance, the reached_goal condition's tolerance)``: 0.3 m at least
  for a social spot) and facing its yaw within the social goal's own yaw tolerance (0.25 rad)
  or else ``yaw_tolerance`` (0.1 rad, ROS ``yaw_goal_tolerance``) — the tolerances our local
  planner arrives with, so a planner that stops to turn in place is not done; or, with
  ``terminate_on_collision`` (CrowdNav's rule), the robot collided.
- ``truncated``: the scenario's time limit was reached.
- ``info``: ``time``, ``scenario``, ``family``, ``reward_terms``; at the episode's end also
  ``metrics``, ``success`` (the conditions of ``socialnav compare``) and ``is_success``.

Seeding: ``reset(seed=s)`` seeds the env's ``np_random``, which draws the scenario, its jitter and
the world's seed, so the same seed replays the same episode. ``reset(options={"scenario": name,
"planner": label})`` picks a scenario of the pool by name and labels the record.

Rendering: ``render_mode="rgb_array"`` returns the top-down figure of the episode so far
(``socialnav.viz.topdown.plot_episode``) as an ``(H, W, 3)`` ``uint8`` array.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import FloatArray, body_to_world, wrap_angle
from socialnav.core.robot import ROBOT_MODELS, RobotModel
from socialnav.core.scene import SocialContext
from socialnav.integrations.gym.reward import RewardConfig, SocialGeometry, reward_terms
from socialnav.integrations.gym.scenes import ScenarioPool, SceneSource
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.sim.controller import clamp_to_robot
from socialnav.sim.engine import ControllerBehavior, SimWorld, build_world, pose_of
from socialnav.sim.recorder import EpisodeRecorder, StaticGeometry, context_at, person_collisions
from socialnav.sim.runner import STOP_EPS
from socialnav.sim.scenario import Scenario
from socialnav.sim.target import resolve_target
from socialnav.social.resolve import resolve_social_goal
from socialnav.social.spaces import activity_space_polygon, o_space, queue_band_polygons

__all__ = ["SocialNavEnv"]

BIG = np.float32(1e4)  # m: bound of relative positions (scenes are tens of metres)


class _ActionController:
    """The controller the env puts in the navground world: it returns the env's action."""

    def __init__(self) -> None:
        self.cmd = np.zeros(3)

    def reset(self, scenario: Scenario, robot: RobotModel) -> None:
        self.cmd = np.zeros(3)

    def step(
        self, time: float, pose: FloatArray, velocity: FloatArray, social: SocialContext
    ) -> PlannerResult:
        return PlannerResult(self.cmd.copy(), PlannerStatus.OK)


def _rotation(yaw: float) -> FloatArray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


class SocialNavEnv(gym.Env[dict[str, np.ndarray], np.ndarray]):
    """Social navigation in socialnav's scenario families (see the module docstring).

    ``scenes``: a scene source ``(rng) -> Scenario`` (default: a :class:`ScenarioPool` of
    ``scenarios`` / ``families``, jittered when ``randomize``); ``robot``: ``pr2`` or
    ``pioneer``; ``humans``: ``scripted`` (the paper's) or ``reactive`` (navground HL);
    ``max_people`` rows of ``people``; ``costmap_cells`` (0: no ``costmap`` key) at the
    costmap's resolution (0.05 m); ``reward``: a :class:`RewardConfig` or field overrides;
    ``yaw_tolerance`` (rad) of the arrival that terminates an episode.

    Raises :class:`~socialnav.core.errors.ConfigurationError` for an unknown robot, family or
    scenario, ``ValueError`` for a bad reward field or ``render_mode``.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}  # noqa: RUF012 (Gymnasium API)

    def __init__(
        self,
        scenes: SceneSource | None = None,
        *,
        scenarios: Sequence[str | Path] | None = None,
        families: Sequence[str] | None = None,
        randomize: bool = True,
        robot: str = "pr2",
        humans: str = "scripted",
        max_people: int = 6,
        costmap_cells: int = 0,
        reward: RewardConfig | dict[str, Any] | None = None,
        terminate_on_collision: bool = True,
        metrics_on_end: bool = True,
        yaw_tolerance: float = 0.1,
        render_mode: str | None = None,
    ) -> None:
        from socialnav.experiments.run import check_robot

        check_robot(robot)
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be one of {self.metadata['render_modes']}")
        if max_people < 0 or costmap_cells < 0:
            raise ValueError("max_people and costmap_cells must be >= 0")
        self.pool = ScenarioPool(scenarios, families, randomize) if scenes is None else None
        self.scenes: SceneSource = scenes if scenes is not None else self.pool  # type: ignore[assignment]
        self.robot: RobotModel = ROBOT_MODELS[robot]
        self.humans = humans
        self.max_people = int(max_people)
        self.costmap_cells = int(costmap_cells)
        self.reward_config = RewardConfig.from_any(reward)
        self.terminate_on_collision = terminate_on_collision
        self.metrics_on_end = metrics_on_end
        self.yaw_tolerance = float(yaw_tolerance)
        self.render_mode = render_mode

        r = self.robot
        vy = r.max_vel_y if r.holonomic else 0.0
        low = np.array([r.min_vel_x, -vy, -r.max_vel_theta], dtype=np.float32)
        high = np.array([r.max_vel_x, vy, r.max_vel_theta], dtype=np.float32)
        self.action_space = spaces.Box(low, high, dtype=np.float32)
        pose_bound = np.array([BIG, BIG, np.pi], dtype=np.float32)
        obs: dict[str, spaces.Space[Any]] = {
            "robot": spaces.Box(low, high, dtype=np.float32),
            "goal": spaces.Box(-pose_bound, pose_bound, dtype=np.float32),
            "social_goal": spaces.Box(
                np.append(-pose_bound, 0.0).astype(np.float32),
                np.append(pose_bound, 1.0).astype(np.float32),
                dtype=np.float32,
            ),
            "people": spaces.Box(
                np.tile(np.array([-BIG, -BIG, -BIG, -BIG, 0.0], np.float32), (self.max_people, 1)),
                np.tile(np.array([BIG, BIG, BIG, BIG, 1.0], np.float32), (self.max_people, 1)),
                dtype=np.float32,
            ),
        }
        if self.costmap_cells:
            shape = (self.costmap_cells, self.costmap_cells)
            obs["costmap"] = spaces.Box(0, 255, shape=shape, dtype=np.uint8)
        self.observation_space = spaces.Dict(obs)  # type: ignore[assignment]

        self.scenario: Scenario | None = None
        self._sim: SimWorld | None = None

    # -- episode state --------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        super().reset(seed=seed)
        options = options or {}
        if "scenario" in options:
            if self.pool is None:
                raise ValueError("options['scenario'] needs the built-in scenario pool")
            scn = self.pool.draw(self.np_random, self.pool.by_name(str(options["scenario"])))
        else:
            scn = self.scenes(self.np_random)
        self.scenario = scn
        self._social0 = scn.social_context(scn.start)
        self._target = resolve_target(scn, self._social0)
        self._controller = _ActionController()
        behavior = ControllerBehavior()
        behavior.controller, behavior.robot_model = self._controller, self.robot
        world_seed = int(self.np_random.integers(2**31))
        self._behavior = behavior
        self._sim = build_world(scn, self.robot, behavior, self.humans, seed=world_seed)
        self._static = StaticGeometry(
            scn.walls_array(), tuple(scn.obstacle_polygons()), scn.discs_array()
        )
        self._radii = np.array([p.radius for p in scn.people], dtype=float)
        self._recorder = EpisodeRecorder(
            self.robot.polygon, self._sim.people_ids, self._radii, self._static
        )
        self._success_spec = scn.success_spec(self.robot.name)
        # Arrival as the reached_goal condition judges it: max(goal_tolerance, its tolerance).
        reached = [c.tolerance for c in self._success_spec if c.name == "reached_goal"]
        self._arrival_tolerance = max([float(scn.goal_tolerance)] + [t for t in reached if t])
        # A social goal says when it counts as reached (as the local planner reads it).
        goal = resolve_social_goal(self._social0, np.asarray(scn.goal, dtype=float), scn.start)
        spot = goal is not None and not goal.is_waypoint
        self._arrival_yaw = float(goal.yaw_tolerance) if goal and spot else self.yaw_tolerance
        self._costmap = scn.static_costmap(self.robot) if self.costmap_cells else None
        self._geometry = self._social_geometry()
        self._step = 0
        self._cmd = np.zeros(3)
        self._done = False
        self._final_status = "OK"
        self._meta = {"planner": options.get("planner", "gym"), "seed": world_seed}
        self._distance = self._target_distance()
        return self._observation(), self._info()

    def _time(self) -> float:
        assert self.scenario is not None
        return self._step * float(self.scenario.control_period)

    def _people(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        assert self._sim is not None
        return self._sim.people_state()

    def planner_input(self) -> tuple[float, FloatArray, FloatArray, SocialContext]:
        """``(time, pose (3,), body velocity (3,), social context)``: what a planner of ours is
        given by ``socialnav compare`` (the scenario's ground truth) at the current state."""
        assert self._sim is not None, "reset() first"
        pos, vel, yaw = self._people()
        social = context_at(self._social0, pos, vel, yaw)
        return self._time(), pose_of(self._sim.robot), self._cmd.copy(), social

    def _social_geometry(self) -> SocialGeometry:
        pos = {p.id: np.asarray(p.position, dtype=float) for p in self._social0.people}

        def members(ids: Sequence[int]) -> FloatArray:
            return np.array([pos[i] for i in ids if i in pos], dtype=float).reshape(-1, 2)

        discs = [
            [*o_space(members(g.member_ids))[0], o_space(members(g.member_ids))[1]]
            for g in self._social0.groups
            if len(members(g.member_ids))
        ]
        bands = [
            b for q in self._social0.queues for b in queue_band_polygons(members(q.member_ids))
        ]
        activity = [
            activity_space_polygon(a.center, a.width, a.facing, v)
            for a in self._social0.artworks
            for v in members(a.viewer_ids)
        ]
        return SocialGeometry(
            np.asarray(discs, dtype=float).reshape(-1, 3), tuple(bands), tuple(activity)
        )

    def _target_distance(self) -> float:
        assert self._sim is not None
        return float(np.hypot(*(pose_of(self._sim.robot)[:2] - self._target.pose[:2])))

    # -- observation ----------------------------------------------------------------------

    def _relative_pose(self, pose: FloatArray, target: FloatArray) -> FloatArray:
        rot = _rotation(float(pose[2]))
        xy = rot.T @ (np.asarray(target[:2], dtype=float) - pose[:2])
        return np.array([xy[0], xy[1], wrap_angle(float(target[2]) - float(pose[2]))])

    def _observation(self) -> dict[str, np.ndarray]:
        assert self._sim is not None and self.scenario is not None
        pose = pose_of(self._sim.robot)
        rot = _rotation(float(pose[2]))
        pos, vel, _ = self._people()
        people = np.zeros((self.max_people, 5), dtype=np.float32)
        if len(pos) and self.max_people:
            rel = (pos - pose[:2]) @ rot  # rows: R^T (p - x)
            robot_world_v = rot @ self._cmd[:2]
            rel_v = (vel - robot_world_v) @ rot
            order = np.argsort(np.hypot(*rel.T), kind="stable")[: self.max_people]
            people[: len(order), :2] = rel[order]
            people[: len(order), 2:4] = rel_v[order]
            people[: len(order), 4] = 1.0
        goal = self._relative_pose(pose, np.asarray(self.scenario.goal, dtype=float))
        social = self._relative_pose(pose, self._target.pose)
        active = 0.0 if self._target.meta.get("social_goal") is None else 1.0
        obs = {
            "robot": self._cmd.astype(np.float32),
            "goal": np.clip(goal, -BIG, BIG).astype(np.float32),
            "social_goal": np.append(np.clip(social, -BIG, BIG), active).astype(np.float32),
            "people": np.clip(people, -BIG, BIG),
        }
        if self._costmap is not None:
            from socialnav.world.costmap import crop

            size = self.costmap_cells * self._costmap.geometry.resolution
            obs["costmap"] = crop(self._costmap, pose[:2], size).costs.astype(np.uint8)
        return obs

    def _info(self) -> dict[str, Any]:
        assert self.scenario is not None
        return {
            "time": self._time(),
            "scenario": self.scenario.name,
            "family": self.scenario.family,
        }

    # -- stepping -------------------------------------------------------------------------

    def _collided(self, pose: FloatArray) -> bool:
        footprint = body_to_world(self.robot.polygon, pose)
        pos, _, _ = self._people()
        # Only people whose disc reaches the robot's circumscribed disc can touch the footprint.
        near = np.hypot(*(pos - pose[:2]).T) <= self._radii + self.robot.circumscribed_radius
        if near.any() and person_collisions(footprint, pos[near], self._radii[near]):
            return True
        return self._static.collides(footprint, pose[:2], self.robot.circumscribed_radius)

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        if self._sim is None or self.scenario is None:
            raise RuntimeError("call reset() before step()")
        if self._done:
            raise RuntimeError("the episode is over: call reset()")
        scn = self.scenario
        dt = float(scn.control_period)
        pose0 = pose_of(self._sim.robot)
        pos0, vel0, _ = self._people()
        cmd = clamp_to_robot(np.asarray(action, dtype=float), self.robot)
        self._controller.cmd = cmd
        self._behavior.observe = lambda _dt: (self._time(), SocialContext())
        self._sim.world.update(dt)
        self._cmd = self._behavior.last_cmd.copy()
        self._recorder.add(self._time(), pose0, self._cmd, pos0, vel0, "OK")
        self._step += 1

        pose = pose_of(self._sim.robot)
        collided = self._collided(pose)
        distance = self._target_distance()
        tolerance = self._arrival_tolerance
        stopped = bool(np.all(np.abs(self._cmd) < STOP_EPS))
        facing = abs(wrap_angle(float(self._target.pose[2]) - float(pose[2]))) <= self._arrival_yaw
        succeeded = bool(distance <= tolerance and facing and stopped and not collided)
        terminated = succeeded or (collided and self.terminate_on_collision)
        truncated = not terminated and self._time() >= float(scn.time_limit) - 1e-9

        pos, _, _ = self._people()
        if len(pos):
            centre = np.hypot(*(pos - pose[:2]).T)
            centre_distance = float(centre.min())
            gap = float((centre - self._radii - self.robot.circumscribed_radius).min())
        else:
            centre_distance = gap = math.inf
        terms = reward_terms(
            self.reward_config,
            dt=dt,
            progress=self._distance - distance,
            gap=gap,
            centre_distance=centre_distance,
            collided=collided,
            succeeded=succeeded,
            timed_out=truncated,
            centre=pose[:2],
            footprint=body_to_world(self.robot.polygon, pose),
            geometry=self._geometry,
        )
        self._distance = distance
        info = self._info()
        info["reward_terms"] = terms
        if terminated or truncated:
            self._done = True
            status = "GOAL_REACHED" if succeeded else ("COLLISION" if collided else "TIME_LIMIT")
            self._final_status = status
            if self.metrics_on_end:
                from socialnav.metrics import compute_metrics, evaluate_success

                record = self.episode_record()
                info["metrics"] = compute_metrics(record)
                info["success"] = evaluate_success(record)
                info["is_success"] = bool(info["success"]["success"])
        return self._observation(), float(sum(terms.values())), terminated, truncated, info

    # -- records and rendering ------------------------------------------------------------

    def episode_record(self) -> EpisodeRecord:
        """The episode so far as ``socialnav compare`` records it (the arguments of
        ``run_episode``'s record): every state with the command applied after it, then the
        current state with a zero command — except after a success, where the record ends, as
        ``run_episode``'s does, at the sample whose command was zero."""
        if self._sim is None or self.scenario is None:
            raise RuntimeError("call reset() first")
        scn = self.scenario
        recorder = copy.copy(self._recorder)
        for name, value in vars(recorder).items():
            if isinstance(value, list):
                setattr(recorder, name, list(value))
        status = self._final_status if self._done else "OK"
        if status == "GOAL_REACHED":
            # As run_episode: the record ends at the sample whose command was zero.
            recorder.status[-1] = status
        else:
            pos, vel, _ = self._people()
            recorder.add(self._time(), pose_of(self._sim.robot), np.zeros(3), pos, vel, status)
        return recorder.build(
            dt=float(scn.control_period),
            robot_radius=self.robot.circumscribed_radius,
            start=np.asarray(scn.start, dtype=float),
            goal=np.asarray(scn.goal, dtype=float),
            target=self._target.pose,
            waypoint=self._target.waypoint,
            goal_tolerance=float(scn.goal_tolerance),
            time_limit=float(scn.time_limit),
            family=scn.family,
            success=self._success_spec,
            scenario=scn.name,
            context=self._social0,
            meta={
                **self._meta,
                "target_source": "scenario",
                "robot": self.robot.name,
                "humans": self.humans,
                "engine": "gymnasium",
                **self._target.meta,
            },
        )

    def render(self) -> np.ndarray | None:
        if self.render_mode != "rgb_array" or self._sim is None:
            return None
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from socialnav.viz.topdown import plot_episode

        fig = plot_episode(self.episode_record(), legend=False, show_stats=False)
        assert isinstance(fig, Figure)
        canvas = FigureCanvasAgg(fig)  # the figures are Agg-only (no pyplot state)
        canvas.draw()  # type: ignore[no-untyped-call]
        return np.asarray(canvas.buffer_rgba())[..., :3].copy()  # type: ignore[no-untyped-call]

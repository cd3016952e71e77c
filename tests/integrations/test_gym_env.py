"""The Gymnasium environments: registry, env checker, spaces, seeding, reward, termination,
vectorization, rendering, and the same record and metrics as ``socialnav compare``."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import socialnav.integrations.gym as sg  # noqa: E402
from socialnav.integrations.gym.reward import (  # noqa: E402
    RewardConfig,
    SocialGeometry,
    reward_terms,
)
from socialnav.metrics import compute_metrics, evaluate_success  # noqa: E402
from socialnav.sim.runner import run_episode  # noqa: E402
from socialnav.sim.scenario import Jitter, load_scenario  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def _rollout(env, policy, seed=0, options=None):
    obs, info = env.reset(seed=seed, options=options)
    policy.reset()
    steps = []
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs))
        steps.append((obs, reward, terminated, truncated, info))
        if terminated or truncated:
            return steps


def test_every_id_is_in_gymnasiums_registry_with_the_env_entry_point() -> None:
    assert set(sg.ENV_IDS) >= {
        "socialnav/SocialNav-v0",
        "socialnav/SocialNavHallway-v0",
        "socialnav/SocialNavGallery-v0",
        "socialnav/SocialNavQueue-v0",
        "socialnav/SocialNavGroup-v0",
    }
    for env_id in sg.ENV_IDS:
        spec = gym.spec(env_id)
        assert spec.entry_point == "socialnav.integrations.gym.env:SocialNavEnv"
    env = gym.make("socialnav/SocialNavQueue-v0")
    assert env.unwrapped.pool.names and {s.family for s in env.unwrapped.pool.scenarios} == {
        "queue"
    }


def test_make_with_the_module_in_the_id_works_in_a_fresh_process() -> None:
    code = (
        "import gymnasium as gym\n"
        "env = gym.make('socialnav.integrations.gym:socialnav/SocialNavGroup-v0')\n"
        "print(env.reset(seed=0)[1]['family'])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "group"


@pytest.mark.parametrize(
    ("env_id", "kwargs"),
    [
        ("socialnav/SocialNav-v0", {"costmap_cells": 32, "render_mode": "rgb_array"}),
        ("socialnav/SocialNavGallery-v0", {"robot": "pioneer", "humans": "reactive"}),
    ],
)
def test_gymnasiums_env_checker_passes(env_id: str, kwargs: dict) -> None:
    env = gym.make(env_id, **kwargs)
    check_env(env.unwrapped, skip_render_check=False)


def test_the_action_space_is_the_robots_box_and_actions_are_clipped() -> None:
    env = gym.make("socialnav/SocialNavHallway-v0", robot="pioneer").unwrapped
    np.testing.assert_allclose(env.action_space.low, [-0.1, 0.0, -1.0])
    np.testing.assert_allclose(env.action_space.high, [0.5, 0.0, 1.0])
    obs, _ = env.reset(seed=1)
    obs, *_ = env.step(np.array([5.0, 3.0, -9.0], dtype=np.float32))
    np.testing.assert_allclose(obs["robot"], [0.5, 0.0, -1.0], atol=1e-6)


def test_observation_is_in_the_robot_frame_nearest_people_first() -> None:
    env = gym.make("socialnav/SocialNav-v0", randomize=False, max_people=2).unwrapped
    obs, _ = env.reset(seed=0, options={"scenario": "queue_shifted"})
    scn = env.scenario
    x, y, yaw = scn.start
    c, s = math.cos(yaw), math.sin(yaw)
    dx, dy = scn.goal[0] - x, scn.goal[1] - y
    np.testing.assert_allclose(obs["goal"][:2], [c * dx + s * dy, -s * dx + c * dy], atol=1e-5)
    people = np.array([p.position for p in scn.people])
    d = np.hypot(*(people - [x, y]).T)
    nearest = people[np.argsort(d)[:2]]
    rel = (nearest - [x, y]) @ np.array([[c, -s], [s, c]])
    seen = obs["people"][:, :2]
    assert np.all(np.diff(np.hypot(*seen.T)) >= -1e-5)  # nearest first
    by_x = np.argsort(seen[:, 0])
    np.testing.assert_allclose(seen[by_x], rel[np.argsort(rel[:, 0])], atol=1e-5)
    np.testing.assert_allclose(obs["people"][:, 4], 1.0)
    assert obs["social_goal"][3] == 1.0  # the queue's tail is a social goal
    target = env._target.pose
    rel_t = np.array([[c, s], [-s, c]]) @ (target[:2] - [x, y])
    np.testing.assert_allclose(obs["social_goal"][:2], rel_t, atol=1e-5)


def test_the_same_seed_replays_the_episode_and_another_seed_does_not() -> None:
    env = gym.make("socialnav/SocialNav-v0")

    def run(seed: int) -> list[np.ndarray]:
        obs, info = env.reset(seed=seed)
        env.action_space.seed(7)
        out = [obs["people"]]
        for _ in range(15):
            obs, *_ = env.step(env.action_space.sample())
            out.append(obs["people"])
        return [info["scenario"], *out]

    a, b, c = run(11), run(11), run(12)
    assert a[0] == b[0]
    for x, y in zip(a[1:], b[1:], strict=True):
        np.testing.assert_array_equal(x, y)
    assert a[0] != c[0] or not np.array_equal(a[1], c[1])


@pytest.mark.parametrize(
    ("name", "planner"),
    [
        ("hallway_passing", "traditional"),
        pytest.param("group_join", "paccet", marks=pytest.mark.slow),
    ],
)
def test_a_planner_policy_gets_the_record_and_metrics_socialnav_compare_gets(
    name: str, planner: str
) -> None:
    scenario = load_scenario(name).model_copy(update={"jitter": Jitter()})
    env = sg.SocialNavEnv(scenes=lambda rng: scenario)
    steps = _rollout(env, sg.PlannerPolicy(env, planner))
    _, _, terminated, truncated, info = steps[-1]
    assert terminated and not truncated  # stopped at the (social) goal
    record = env.episode_record()
    reference = run_episode(scenario, planner, "pr2", seed=0).record
    assert info["success"] == evaluate_success(reference)
    assert record.num_steps == reference.num_steps
    np.testing.assert_allclose(record.robot_poses, reference.robot_poses, atol=1e-4)
    np.testing.assert_allclose(record.target, reference.target)
    ours, theirs = info["metrics"], compute_metrics(reference)
    assert ours.keys() == theirs.keys()
    for key in ours:
        assert ours[key] == pytest.approx(theirs[key], rel=1e-3, abs=1e-3, nan_ok=True), key


def test_driving_into_a_wall_terminates_with_the_collision_penalty() -> None:
    env = gym.make("socialnav/SocialNav-v0", randomize=False).unwrapped
    env.reset(seed=0, options={"scenario": "hallway_stationary"})
    for _ in range(200):  # full speed to the robot's left: the hallway wall
        _obs, _reward, terminated, truncated, info = env.step(np.array([0.0, 0.3, 0.0], np.float32))
        if terminated:
            break
    assert terminated and not truncated and not info["is_success"]
    assert info["reward_terms"]["collision"] == -0.25
    assert info["metrics"]["collisions_obstacle"] >= 1


def test_the_time_limit_truncates() -> None:
    scenario = load_scenario("hallway_stationary").model_copy(update={"time_limit": 1.0})
    env = sg.SocialNavEnv(scenes=lambda rng: scenario)
    env.reset(seed=0)
    flags = [env.step(np.zeros(3, np.float32))[2:4] for _ in range(10)]
    assert flags[-1] == (False, True) and all(f == (False, False) for f in flags[:-1])
    record = env.episode_record()
    assert record.times[-1] == pytest.approx(1.0)
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.zeros(3, np.float32))


def test_progress_pays_the_distance_gained_toward_the_target() -> None:
    env = gym.make("socialnav/SocialNav-v0", randomize=False).unwrapped
    obs, _ = env.reset(seed=0, options={"scenario": "hallway_stationary"})
    d0 = float(np.hypot(*obs["social_goal"][:2]))
    obs, _, _, _, info = env.step(np.array([0.5, 0.0, 0.0], np.float32))
    gained = d0 - float(np.hypot(*obs["social_goal"][:2]))
    assert gained == pytest.approx(0.05, abs=2e-3)
    assert info["reward_terms"]["progress"] == pytest.approx(0.1 * gained, abs=1e-6)


def _terms(**kw):
    base = dict(
        dt=0.1,
        progress=0.0,
        gap=math.inf,
        centre_distance=math.inf,
        collided=False,
        succeeded=False,
        timed_out=False,
        centre=np.zeros(2),
        footprint=np.array([[0.2, 0.2], [-0.2, 0.2], [-0.2, -0.2], [0.2, -0.2]]),
        geometry=SocialGeometry(np.zeros((0, 3)), (), ()),
    )
    base.update(kw)
    return reward_terms(RewardConfig(), **base)


def test_reward_terms_against_hand_values() -> None:
    # CrowdNav's discomfort: (0.1 - 0.2) * 0.5 * 0.1
    assert _terms(gap=0.1)["discomfort"] == pytest.approx(-0.005)
    assert _terms(gap=0.3)["discomfort"] == 0.0
    # personal space: (0.7 - 1.2) * 0.25 * 0.1
    assert _terms(centre_distance=0.7)["personal_space"] == pytest.approx(-0.0125)
    # the robot centre 0.4 m deep in an o-space of radius 1.0
    group = SocialGeometry(np.array([[0.6, 0.0, 1.0]]), (), ())
    assert _terms(geometry=group)["group"] == pytest.approx(-0.04)
    # a queue band overlapping the footprint by 0.1 m
    band = np.array([[0.1, -1.0], [1.0, -1.0], [1.0, 1.0], [0.1, 1.0]])
    queue = SocialGeometry(np.zeros((0, 3)), (band,), ())
    assert _terms(geometry=queue)["queue"] == pytest.approx(-0.01)
    assert _terms(succeeded=True)["success"] == 1.0
    assert sum(_terms().values()) == 0.0
    with pytest.raises(ValueError, match="unknown term"):
        RewardConfig.from_any({"sucess_reward": 2.0})


@pytest.mark.parametrize("mode", ["sync", pytest.param("async", marks=pytest.mark.slow)])
def test_the_vectorized_env_steps_every_copy(mode: str) -> None:
    envs = gym.make_vec("socialnav/SocialNav-v0", num_envs=2, vectorization_mode=mode)
    obs, _ = envs.reset(seed=[0, 1])
    assert obs["people"].shape == (2, 6, 5) and obs["goal"].shape == (2, 3)
    single = gym.make("socialnav/SocialNav-v0")
    first, _ = single.reset(seed=1)
    np.testing.assert_array_equal(obs["people"][1], first["people"])  # copy 1 got seed 1
    envs.action_space.seed(0)
    for _ in range(5):
        obs, rewards, terminated, _truncated, _infos = envs.step(envs.action_space.sample())
    assert rewards.shape == (2,) and terminated.shape == (2,)
    envs.close()


def test_render_returns_the_topdown_figure_as_rgb() -> None:
    env = gym.make("socialnav/SocialNavQueue-v0", render_mode="rgb_array")
    env.reset(seed=0)
    env.step(env.action_space.sample())
    image = env.render()
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3
    assert image.std() > 10  # not a blank canvas


@pytest.mark.slow
def test_the_example_evaluates_planners_beside_a_random_policy() -> None:
    out = subprocess.run(
        [
            sys.executable,
            str(ROOT / "examples" / "gym_evaluate.py"),
            "--episodes",
            "1",
            "--policies",
            "random,paccet",
            "--scenario",
            "hallway_passing",
        ],
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    rows = {line.split("|")[1].strip(): line for line in out.stdout.splitlines()[2:]}
    assert set(rows) == {"random", "paccet"}
    paccet = [c.strip() for c in rows["paccet"].split("|")[1:-1]]
    assert paccet[2] == "1.00" and paccet[3] == "0.00"  # success, collisions

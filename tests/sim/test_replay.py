"""Replay: people follow their recorded tracks to the control period, appear and disappear as
recorded, never react (unless switched to HL), and the scene is the annotated area."""

from __future__ import annotations

import numpy as np
import pytest

from socialnav.core.errors import ConfigurationError
from socialnav.core.robot import ROBOT_MODELS
from socialnav.core.scene import SocialContext
from socialnav.crowds import Recording, Track, open_space_costmap
from socialnav.metrics import compute_metrics, evaluate_success
from socialnav.planner.local_planner import PlannerResult, PlannerStatus
from socialnav.sim.replay import CrowdTask, crowd_scenario, run_crowd_episode


def crowd() -> Recording:
    """A 20 × 10 m area; person 1 crosses the robot's line, person 2 appears at 3 s and leaves
    at 6 s, person 3 walks head-on at the robot, persons 9/10 only mark the area's corners."""
    t = 0.4 * np.arange(41)  # 0 … 16 s
    tracks = [
        Track(1, t, np.c_[np.full_like(t, 6.0), 1.0 + 0.5 * t]),
        Track(2, t[7:16], np.c_[10.0 + 0 * t[7:16], 8.0 - 0.2 * t[7:16]]),
        Track(3, t, np.c_[16.0 - 1.0 * t, np.full_like(t, 5.0)]),
        Track(9, t[:2], np.array([[0.0, 0.0], [0.0, 0.0]])),
        Track(10, t[:2], np.array([[20.0, 10.0], [20.0, 10.0]])),
    ]
    return Recording(tuple(tracks), 0.04)


TASK = CrowdTask(t0=0.0, start=(2.0, 5.0, 0.0), goal=(12.0, 5.0, 0.0), time_limit=15.0)


def test_people_follow_their_recorded_tracks_and_presence() -> None:
    rec = crowd()
    result = run_crowd_episode(rec, TASK, "straight_line", "pr2")
    r = result.record
    assert r.family == "crowd"
    expected = rec.states(r.times, r.people_ids)
    np.testing.assert_allclose(r.people_positions, expected.positions, atol=1e-9)
    np.testing.assert_array_equal(r.people_present, expected.present)
    k2 = list(r.people_ids).index(2)
    present = r.people_present[:, k2]
    assert not present[r.times < 2.79].any() and present[(r.times > 2.81) & (r.times < 5.99)].all()
    assert not present[r.times > 6.01].any()
    assert np.isnan(r.people_positions[~present, k2]).all()
    # Everyone measured: no NaN leaks into the metrics of present people.
    m = compute_metrics(r)
    assert np.isfinite(m["min_distance_footprint"]) and np.isfinite(m["time_within_1.2"])


def test_straight_line_is_hit_head_on_and_counts_active() -> None:
    # Person 3 walks into the robot's line: the straight-line reference drives into them.
    r = run_crowd_episode(crowd(), TASK, "straight_line", "pr2").record
    ok = evaluate_success(r)
    assert compute_metrics(r)["collisions_active"] >= 1
    assert not ok["no_active_collision"] and not ok["success"]


def test_people_do_not_react_unless_switched() -> None:
    rec = crowd()
    still = run_crowd_episode(rec, TASK, "straight_line", "pr2").record
    moved = run_crowd_episode(rec, TASK, "straight_line", "pr2", switch_distance=3.0).record
    assert still.meta["switched_people"] == []
    assert 3 in moved.meta["switched_people"]
    k3 = list(moved.people_ids).index(3)
    gap = np.nanmax(np.abs(moved.people_positions[:, k3] - still.people_positions[:, k3]))
    assert gap > 0.1  # HL steers the switched person off their recorded line


def test_navground_baselines_see_replayed_people() -> None:
    # ORCA avoids person 3 coming head-on; the straight line does not.
    rec = crowd()
    orca = compute_metrics(run_crowd_episode(rec, TASK, "orca", "pr2").record)
    line = compute_metrics(run_crowd_episode(rec, TASK, "straight_line", "pr2").record)
    assert orca["min_distance_footprint"] > line["min_distance_footprint"]


def test_scene_costmap_is_the_open_space_costmap() -> None:
    rec = crowd()
    robot = ROBOT_MODELS["pr2"]
    scn = crowd_scenario(rec, TASK, ())
    a = scn.static_costmap(robot)
    b = open_space_costmap(rec.area, robot.inscribed_radius)
    assert a.geometry == b.geometry
    np.testing.assert_array_equal(a.costs, b.costs)


@pytest.mark.parametrize("planner", ["paccet"])
def test_our_planner_runs_in_a_replayed_crowd(planner: str) -> None:
    r = run_crowd_episode(crowd(), TASK, planner, "pioneer").record
    assert r.num_steps > 10
    assert np.isfinite(r.robot_poses).all()


def test_partial_presence_survives_storage(tmp_path) -> None:
    from socialnav.experiments.storage import load_episode, save_episode

    r = run_crowd_episode(crowd(), TASK, "straight_line", "pr2").record
    back = load_episode(save_episode(r, tmp_path / "ep"))
    np.testing.assert_array_equal(back.people_present, r.people_present)
    np.testing.assert_allclose(back.people_positions, r.people_positions, equal_nan=True)
    assert back.family == "crowd"
    assert compute_metrics(back) == pytest.approx(compute_metrics(r), nan_ok=True)


class Watcher:
    """A controller that stands still and keeps what it was shown each cycle."""

    def __init__(self) -> None:
        self.seen: list[SocialContext] = []

    def reset(self, scenario, robot) -> None:
        self.seen = []

    def step(self, time, pose, velocity, social) -> PlannerResult:
        self.seen.append(social)
        return PlannerResult(np.zeros(3), PlannerStatus.OK)


@pytest.mark.parametrize("seed", [0, 1])
def test_a_detected_context_shows_the_controller_noisy_tracks_of_the_present(seed: int) -> None:
    # `compare --suite crowds --context detected` was accepted and silently ran the given context
    rec = crowd()
    watched = {}
    for context in ("given", "detected"):
        watcher = Watcher()
        result = run_crowd_episode(rec, TASK, watcher, "pr2", seed, context=context)
        watched[context] = (watcher.seen, result.record)
    given, record = watched["given"]
    detected, again = watched["detected"]
    assert record.meta["context"] == "given" and again.meta["context"] == "detected"
    assert record.meta["acc_lim"] == ROBOT_MODELS["pr2"].kinematic_limits()["acc_lim"]
    assert "estimator_ms_median" not in record.meta and again.meta["estimator_ms_median"] >= 0
    # the metrics are of the true people: the robot stood still, so the records agree
    np.testing.assert_array_equal(record.people_positions, again.people_positions)
    errors = []
    for k, (true, seen) in enumerate(zip(given, detected, strict=True)):
        truth = {p.id: np.asarray(p.position) for p in true.people}
        assert set(truth) == {
            int(i) for i, on in zip(record.people_ids, record.people_present[k], strict=True) if on
        }
        for p in seen.people:
            if p.id in truth:  # false positives have ids of their own
                errors.append(np.hypot(*(np.asarray(p.position) - truth[p.id])))
    # the default tracker: 5 cm of position noise per axis (a few misses, a filter on top)
    assert 0.005 < float(np.median(errors)) < 0.1


def test_an_unknown_crowd_context_is_refused() -> None:
    with pytest.raises(ConfigurationError, match="unknown context 'seen'"):
        run_crowd_episode(crowd(), TASK, "straight_line", "pr2", context="seen")

"""Rate-separated global replanning (``Navigator(replan_mode=...)``): the deferred mode applies
the plan requested at step k at step k + replan_delay exactly, whatever the worker's speed, so
runs are reproducible; the threaded mode applies it when done; inline stays the default."""

from __future__ import annotations

import time

import numpy as np
import pytest
from _planner_helpers import step_pose

from socialnav.core.robot import PR2
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.presets import build_navigator
from socialnav.sim.scenario import load_scenario

COSTMAP = load_scenario("group_join").static_costmap(PR2)
GOAL = np.array([14.0, 12.0, 0.0])


def crowd(k: int) -> SocialContext:
    """Six people walking across the robot's way (deterministic in the step index)."""
    t = 0.1 * k
    return SocialContext(
        tuple(
            Person(i, (4.0 + 1.5 * i + 0.4 * t, 8.0 + 2.0 * np.sin(0.3 * t + i)), (0.4, 0.0))
            for i in range(6)
        )
    )


def run(mode: str, steps: int, slow: float = 0.0, delay: int = 2, search: str = "compiled"):
    nav = build_navigator(
        "paccet",
        PR2,
        COSTMAP,
        GOAL,
        SocialContext(),
        planner_frequency=2.0,
        global_search=search,
        replan_mode=mode,
        replan_delay=delay,
    )
    compute, request = nav._compute_plan, nav._request
    requests: list[int] = []  # step indices at which a plan was computed inline or requested

    def slowed(*args):  # the worker as a loaded machine would run it
        time.sleep(slow)
        return compute(*args)

    def inline(*args):
        requests.append(nav._step_index)
        return compute(*args)

    def requested(*args):
        requests.append(nav._step_index)
        nav._compute_plan = slowed
        try:
            return request(*args)
        finally:
            nav._compute_plan = inline

    apply = nav._apply_plan
    applied: list[int] = []  # step indices at which a plan was put in use

    def applying(*args):
        applied.append(nav._step_index)
        return apply(*args)

    nav._compute_plan = inline
    nav._request = requested
    nav._apply_plan = applying
    pose, vel = np.array([3.0, 3.0, 0.8]), np.zeros(3)
    cmds, paths = [], []
    for k in range(steps):
        res = nav.step(0.1 * k, pose, vel, crowd(k))
        cmds.append(res.cmd.copy())
        paths.append(None if nav.global_path is None else nav.global_path.copy())
        vel = res.cmd
        pose = step_pose(pose, vel)
    nav.close()
    return np.array(cmds), paths, requests, applied


def test_deferred_replanning_is_reproducible_under_load():
    fast, paths_fast, req_fast, _ = run("deferred", 30)
    slow, paths_slow, req_slow, _ = run("deferred", 30, slow=0.15)
    assert len(req_fast) >= 4 and req_fast == req_slow  # same requests at the same steps
    assert np.array_equal(fast, slow)
    for a, b in zip(paths_fast, paths_slow, strict=True):
        assert np.array_equal(a, b)


def test_deferred_plan_applied_exactly_delay_steps_later():
    delay = 3
    _, _, requests, applied = run("deferred", 30, slow=0.05, delay=delay)
    assert requests[0] == applied[0] == 1  # the first plan is inline: nothing to follow yet
    deferred = [k for k in requests[1:] if k + delay <= 30]
    assert len(deferred) >= 3
    assert applied[1 : 1 + len(deferred)] == [k + delay for k in deferred]


def test_threaded_replanning_applies_when_done():
    cmds, paths, requests, _ = run("threaded", 30)
    assert len(requests) >= 4
    assert np.all(np.isfinite(cmds))
    assert all(p is not None for p in paths)


def test_inline_is_the_default_and_bad_modes_are_rejected():
    nav = build_navigator("paccet", PR2, COSTMAP, GOAL, SocialContext())
    assert nav.replan_mode == "inline" and nav.global_search == "scipy"
    with pytest.raises(ValueError, match="replan_mode"):
        build_navigator("paccet", PR2, COSTMAP, GOAL, SocialContext(), replan_mode="later")
    with pytest.raises(ValueError, match="replan_delay"):
        build_navigator("paccet", PR2, COSTMAP, GOAL, SocialContext(), replan_delay=0)

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


def test_a_deferred_periodic_replan_takes_effect_when_an_inline_one_would():
    """The periodic replan is requested ``replan_delay`` steps early, so a plan takes effect at
    the same steps as inline (applied 2 steps late, the plan through an oncoming person made a
    Pioneer brake, back off and then intrude in the hallway_oncoming scenario)."""
    _, _, _, applied_inline = run("inline", 40)
    _, _, requests, applied_deferred = run("deferred", 40, slow=0.05)
    assert len(applied_inline) >= 4
    assert applied_deferred == applied_inline
    early = [k + 2 for k in requests[1:] if k + 2 <= 40]
    assert early == applied_deferred[1:]  # each requested 2 steps early


def test_the_worker_plans_from_where_robot_and_people_will_be_when_it_is_used():
    """A plan from the pose 2 steps old differed by a cell from the inline one, and the Pioneer
    then stalled beside the stationary person of hallway_stationary for 20 s."""
    nav = build_navigator(
        "paccet", PR2, COSTMAP, GOAL, SocialContext(), replan_mode="deferred", replan_delay=3
    )
    seen: list[tuple[np.ndarray, SocialContext]] = []
    compute = nav._compute_plan

    def spy(pose, target, social, fresh, previous=None, partners=None):
        seen.append((pose, social))
        return compute(pose, target, social, fresh, previous, partners)

    nav._compute_plan = spy
    walker = SocialContext((Person(0, (6.0, 6.0), (1.0, -0.5)), Person(1, (8.0, 5.0))))
    pose, twist = np.array([3.0, 3.0, np.pi / 2]), np.array([0.5, 0.0, 0.0])
    nav._request(0.0, pose, GOAL, walker, False, False, twist)
    nav._pending.future.result()
    nav.close()
    lead = 3 * nav.controller_period
    start, people = seen[0]
    np.testing.assert_allclose(start, [3.0, 3.0 + 0.5 * lead, np.pi / 2], atol=1e-12)
    np.testing.assert_allclose(people.positions(), [[6.0 + lead, 6.0 - 0.5 * lead], [8.0, 5.0]])


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

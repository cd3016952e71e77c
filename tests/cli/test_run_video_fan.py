"""``socialnav run --video``: the candidate fan is drawn on the cycles that evaluated candidates."""

from __future__ import annotations

import numpy as np

from socialnav.experiments.planners import run_planner_episode
from socialnav.experiments.run import fan_frames
from socialnav.experiments.suite import EpisodeSpec


def test_fan_frames_exist_where_a_cycle_was_evaluated():
    spec = EpisodeSpec("hallway_passing", "traditional", "pr2")
    result = run_planner_episode(spec, record_diagnostics=True)
    frames = fan_frames(result.diagnostics)
    assert len(frames) == result.record.num_steps
    evaluated = [
        i for i, d in enumerate(result.diagnostics) if d is not None and d.fitness is not None
    ]
    assert len(evaluated) > 10
    for i in evaluated:
        fan = frames[i]
        assert fan is not None
        rec = result.diagnostics[i]
        assert fan.poses.shape == (rec.num_samples, 1, 2)
        np.testing.assert_array_equal(fan.poses[:, 0], rec.end_poses[:, :2])
        assert fan.chosen == rec.chosen
    assert all(frames[i] is None for i in set(range(len(frames))) - set(evaluated))

"""The simulated people tracker: each noise option does what it says, seeded."""

from __future__ import annotations

import numpy as np
import pytest

from socialnav.sim.perception import (
    EXACT_PERCEPTION,
    FALSE_POSITIVE_ID_BASE,
    PerceptionModel,
    PerceptionNoise,
)

IDS = np.arange(1, 41)
POS = np.column_stack([np.arange(40) * 2.0, np.zeros(40)])
VEL = np.zeros((40, 2))
YAW = np.zeros(40)


def observe_many(noise: PerceptionNoise, cycles: int = 50, seed: int = 3, pos=POS):
    model = PerceptionModel(noise, (0, -5, 80, 5), seed=seed)
    return [model.observe(IDS, pos, VEL, YAW) for _ in range(cycles)]


def test_exact_perception_returns_the_true_people():
    (tracks,) = observe_many(EXACT_PERCEPTION, 1)
    assert [p.id for p in tracks] == IDS.tolist()
    np.testing.assert_array_equal([p.position for p in tracks], POS)


def test_position_and_heading_noise_have_the_asked_spread():
    noise = PerceptionNoise(0.1, np.radians(15), 0, 0, 0, 0)
    frames = observe_many(noise)
    err = np.array([[p.position[0] - POS[p.id - 1, 0] for p in f] for f in frames])
    yaw = np.array([[p.yaw for p in f] for f in frames])
    assert err.std() == pytest.approx(0.1, rel=0.1)
    assert yaw.std() == pytest.approx(np.radians(15), rel=0.1)


def test_missed_detections_drop_the_asked_share():
    frames = observe_many(PerceptionNoise(0, 0, 0, 0.2, 0, 0))
    seen = sum(len(f) for f in frames) / (40 * len(frames))
    assert seen == pytest.approx(0.8, abs=0.03)


def test_false_positives_have_fresh_ids_inside_the_bounds():
    frames = observe_many(PerceptionNoise(0, 0, 0, 0, 2.0, 0))
    extra = [p for f in frames for p in f if p.id >= FALSE_POSITIVE_ID_BASE]
    assert len(extra) / len(frames) == pytest.approx(2.0, rel=0.2)
    assert len({p.id for p in extra}) == len(extra)
    assert all(0 <= p.position[0] <= 80 and -5 <= p.position[1] <= 5 for p in extra)


def test_id_switches_swap_two_close_people_for_good():
    close = POS.copy()
    close[1] = (0.5, 0.0)  # ids 1 and 2 stand 0.5 m apart, everyone else far
    frames = observe_many(PerceptionNoise(0, 0, 0, 0, 0, 1.0), cycles=1, pos=close)
    by_id = {p.id: p.position for p in frames[0]}
    assert by_id[1] == (0.5, 0.0) and by_id[2] == (0.0, 0.0)


def test_same_seed_same_tracks_and_bad_options_are_refused():
    a = observe_many(PerceptionNoise(), 5, seed=9)
    b = observe_many(PerceptionNoise(), 5, seed=9)
    assert a == b
    with pytest.raises(ValueError, match="miss_probability"):
        PerceptionNoise(miss_probability=-0.1)

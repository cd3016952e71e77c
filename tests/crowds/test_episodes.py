"""Episode generation on the shared recordings: every rule of the generator holds, seeds are
deterministic, and across-flow episodes appear only where the area allows them."""

from __future__ import annotations

import numpy as np
import pytest

from shared import crowd_data
from socialnav.core.errors import ConfigurationError
from socialnav.crowds import Recording, Track, load_recording
from socialnav.crowds.episodes import (
    BORDER,
    CLEARANCE,
    DISTANCE,
    MIN_PEOPLE,
    NEAR,
    across_allowed,
    generate_episode,
)


@pytest.fixture(scope="module", params=["eth_hotel_obsmat.txt", "ucy_zara01_obsmat.txt"])
def recording(request) -> Recording:
    return load_recording(crowd_data(request.param))


def test_generated_episodes_satisfy_every_rule(recording: Recording) -> None:
    area = recording.area
    for seed in range(12):
        ep = generate_episode(recording, seed)
        start, goal = np.array(ep.start[:2]), np.array(ep.goal[:2])
        assert DISTANCE[0] <= np.hypot(*(goal - start)) <= DISTANCE[1]
        assert area.border_distance(start) >= BORDER and area.border_distance(goal) >= BORDER
        s = recording.state_at(ep.t0)
        d = np.hypot(*(s.positions[0][s.present[0]] - start).T)
        assert d.min() >= CLEARANCE
        assert np.count_nonzero(d <= NEAR) >= MIN_PEOPLE == 5
        assert ep.people_near == np.count_nonzero(d <= NEAR)
        assert ep.start[2] == pytest.approx(np.arctan2(*(goal - start)[::-1]))
        expected = "across" if seed % 2 and across_allowed(recording) else "along"
        assert ep.flow == expected
        assert generate_episode(recording, seed) == ep  # the seed selects the episode


def test_across_allowed_only_where_the_area_is_wide_enough() -> None:
    hotel = load_recording(crowd_data("eth_hotel_obsmat.txt"))
    zara = load_recording(crowd_data("ucy_zara01_obsmat.txt"))
    assert not across_allowed(hotel)  # 7.7 m wide across its flow: no 8 m line 2 m inside
    assert across_allowed(zara)


def test_an_empty_scene_gives_a_clear_error() -> None:
    t = np.arange(10.0)
    rec = Recording((Track(1, t, np.c_[t, t]), Track(2, t, np.c_[20 - t, t + 5])), 0.04)
    with pytest.raises(ConfigurationError, match="no episode with 5 people"):
        generate_episode(rec, 0)

"""The F-formation matching rule and pairwise scores, on hand-worked frames."""

from __future__ import annotations

import pytest

from socialnav.metrics.groups import (
    frame_precision_recall,
    group_detection_scores,
    pairwise_scores,
)


def test_two_thirds_rule_matches_a_group_with_one_member_missing():
    assert frame_precision_recall([[1, 2]], [[1, 2, 3]], 2 / 3) == (1.0, 1.0)
    assert frame_precision_recall([[1, 2]], [[1, 2, 3]], 1.0) == (0.0, 0.0)
    # 2 of 4: below 2/3
    assert frame_precision_recall([[1, 2]], [[1, 2, 3, 4]], 2 / 3) == (0.0, 0.0)


def test_singletons_are_removed_and_empty_frames_count_as_perfect():
    assert frame_precision_recall([[1], [2]], [], 2 / 3) == (1.0, 1.0)
    assert frame_precision_recall([[1, 2]], [], 2 / 3) == (0.0, 1.0)
    assert frame_precision_recall([], [[1, 2]], 2 / 3) == (1.0, 0.0)


def test_scores_average_precision_and_recall_over_frames_then_f1():
    det = [[[1, 2]], [[1, 2], [3, 4]]]
    gt = [[[1, 2]], [[1, 2]]]
    s = group_detection_scores(det, gt)
    assert (s.precision, s.recall, s.frames) == (0.75, 1.0, 2)
    assert s.f1 == pytest.approx(2 * 0.75 / 1.75)
    with pytest.raises(ValueError, match="frames"):
        group_detection_scores(det, gt[:1])


def test_pairwise_counts_only_present_people():
    counts = pairwise_scores([[1, 2, 3]], [[1, 2], [3, 4]], present=[1, 2, 3])
    assert (counts.tp, counts.fp, counts.fn) == (1, 2, 0)
    assert counts.precision == pytest.approx(1 / 3) and counts.recall == 1.0

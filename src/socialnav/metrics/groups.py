"""Scores of detected social structures against ground truth.

- :func:`group_detection_scores`: the F-formation rule of Cristani et al., "Social interaction
  discovery by statistical analysis of F-formations" (BMVC 2011), as used by Setti et al. (PLoS
  One 2015): singletons are removed on both sides; a detected group ``D`` and a true group ``G``
  match when ``|G ∩ D| / max(|G|, |D|) >= T`` (``T`` = 2/3 or 1); precision = matched detected
  groups / detected groups and recall = matched true groups / true groups, per frame, each
  averaged over frames; a ratio with nothing to count (0/0: no detected or no true group)
  is 1, so a frame with no group on either side counts as P = R = 1; F1 from the two means.
- :func:`pairwise_scores`: pairwise precision and recall of "walks together" over person pairs
  (Solera, Calderara, Cucchiara, "Socially constrained structural learning for groups detection
  in crowd", TPAMI 2016, use the same pair counts): a pair is positive when both are in the same
  group; counts are summed over frames.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from itertools import combinations

Groups = Sequence[Iterable[int]]


@dataclass(frozen=True)
class DetectionScores:
    """``precision``, ``recall``, ``f1`` in [0, 1] and the number of ``frames`` scored."""

    precision: float
    recall: float
    f1: float
    frames: int


def _clean(groups: Groups) -> list[frozenset[int]]:
    return [s for s in (frozenset(int(i) for i in g) for g in groups) if len(s) >= 2]


def frame_precision_recall(
    detected: Groups, truth: Groups, threshold: float = 2.0 / 3.0
) -> tuple[float, float]:
    """``(precision, recall)`` of one frame under the match rule (module docstring)."""
    det, gt = _clean(detected), _clean(truth)
    if not det and not gt:
        return 1.0, 1.0

    def match(a: frozenset[int], b: frozenset[int]) -> bool:
        # the small epsilon keeps 2/3 itself a match under floating point
        return len(a & b) / max(len(a), len(b)) >= threshold - 1e-9

    tp_det = sum(1 for d in det if any(match(d, g) for g in gt))
    tp_gt = sum(1 for g in gt if any(match(d, g) for d in det))
    precision = tp_det / len(det) if det else 1.0
    recall = tp_gt / len(gt) if gt else 1.0
    return precision, recall


def group_detection_scores(
    detected: Sequence[Groups], truth: Sequence[Groups], threshold: float = 2.0 / 3.0
) -> DetectionScores:
    """Mean per-frame precision and recall over paired frames, and F1 from the two means.

    ``detected[f]`` / ``truth[f]``: the groups (id collections) of frame ``f``.
    Raises ``ValueError`` when the frame counts differ.
    """
    if len(detected) != len(truth):
        raise ValueError(f"{len(detected)} detected frames but {len(truth)} true frames")
    if not truth:
        return DetectionScores(1.0, 1.0, 1.0, 0)
    pr = [frame_precision_recall(d, t, threshold) for d, t in zip(detected, truth, strict=True)]
    p = sum(x for x, _ in pr) / len(pr)
    r = sum(y for _, y in pr) / len(pr)
    f1 = 2 * p * r / (p + r) if p + r > 0 else 0.0
    return DetectionScores(p, r, f1, len(pr))


def together_pairs(groups: Groups, present: Iterable[int] | None = None) -> set[tuple[int, int]]:
    """Pairs ``(a, b)``, ``a < b``, of people in the same group (restricted to ``present``)."""
    keep = None if present is None else {int(i) for i in present}
    pairs: set[tuple[int, int]] = set()
    for g in groups:
        members = sorted({int(i) for i in g if keep is None or int(i) in keep})
        pairs.update(combinations(members, 2))
    return pairs


@dataclass(frozen=True)
class PairCounts:
    """Summed true positives, false positives and false negatives over person pairs."""

    tp: int = 0
    fp: int = 0
    fn: int = 0

    def __add__(self, other: PairCounts) -> PairCounts:
        return PairCounts(self.tp + other.tp, self.fp + other.fp, self.fn + other.fn)

    @property
    def precision(self) -> float:
        """``tp / (tp + fp)``; 1 when nothing was detected."""
        return self.tp / (self.tp + self.fp) if self.tp + self.fp else 1.0

    @property
    def recall(self) -> float:
        """``tp / (tp + fn)``; 1 when there was nothing to find."""
        return self.tp / (self.tp + self.fn) if self.tp + self.fn else 1.0


def pairwise_scores(detected: Groups, truth: Groups, present: Iterable[int]) -> PairCounts:
    """Pair counts of one frame among the ``present`` people."""
    present = list(present)
    det = together_pairs(detected, present)
    gt = together_pairs(truth, present)
    return PairCounts(len(det & gt), len(det - gt), len(gt - det))

"""Multi-objective core: non-dominated filtering, the Pareto archive, PaCcET, selection.

Three PaCcET objects, three names:

- :class:`PaccetSelection`: the stateless selection strategy the local planner uses (a fresh
  archive from each cycle's candidates); it returns a :class:`Selection`, as every
  :class:`SelectionStrategy` does;
- :class:`PaccetTransform`: the stateful transformation with a persistent
  :class:`ParetoArchive` (``tell`` / ``transform`` / ``order``); :func:`paccet_select` is its
  one-shot form and returns a :class:`PaccetRanking`;
- :class:`~socialnav.moo.optimizer.PaccetEvolution` (ask/tell),
  :func:`~socialnav.moo.optimizer.paccet_evolve` and the pymoo ``PaccetAlgorithm``: the
  evolutionary optimizer, whose runs return a
  :class:`~socialnav.moo.optimizer.PaccetEvolutionResult`.
"""

from socialnav.moo.archive import ParetoArchive
from socialnav.moo.indicators import hypervolume
from socialnav.moo.nondominated import dominates, nondominated_mask, validate_objectives
from socialnav.moo.paccet import (
    PaccetOptions,
    PaccetRanking,
    PaccetTransform,
    normalize,
    paccet_select,
    paccet_transform,
)
from socialnav.moo.scalarize import EqualWeight, L1Target, Scalarization, Weighted
from socialnav.moo.selection import PaccetSelection, Selection, SelectionStrategy, WeightedSum

__all__ = [
    "EqualWeight",
    "L1Target",
    "PaccetOptions",
    "PaccetRanking",
    "PaccetSelection",
    "PaccetTransform",
    "ParetoArchive",
    "Scalarization",
    "Selection",
    "SelectionStrategy",
    "Weighted",
    "WeightedSum",
    "dominates",
    "hypervolume",
    "nondominated_mask",
    "normalize",
    "paccet_select",
    "paccet_transform",
    "validate_objectives",
]

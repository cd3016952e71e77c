"""Multi-objective core: non-dominated filtering, the Pareto archive, PaCcET, selection."""

from socialnav.moo.archive import ParetoArchive
from socialnav.moo.indicators import hypervolume
from socialnav.moo.nondominated import dominates, nondominated_mask, validate_objectives
from socialnav.moo.paccet import (
    PaCcET,
    PaccetOptions,
    PaccetResult,
    normalize,
    paccet_select,
    paccet_transform,
)
from socialnav.moo.scalarize import EqualWeight, L1Target, Scalarization, Weighted
from socialnav.moo.selection import PaccetSelection, Selection, SelectionStrategy, WeightedSum

__all__ = [
    "EqualWeight",
    "L1Target",
    "PaCcET",
    "PaccetOptions",
    "PaccetResult",
    "PaccetSelection",
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

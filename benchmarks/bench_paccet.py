"""PaCcET selection speed: ``paccet_select`` vs a naive all-pairs NumPy version and pymoo.

Rows per (data, n, m) group:
- ``naive (baseline)``: all-pairs broadcast dominance ``(n, n, m)`` + broadcast closed form
  ``(n, P, m)`` + argmin — the straightforward NumPy port, the baseline of every ratio;
- ``select closed``: ``paccet_select`` (default options, closed form);
- ``select parity``: ``paccet_select`` with the reference bisections (vectorized);
- ``pymoo NDS front``: pymoo's ``NonDominatedSorting`` first front only (no transformation),
  for scale: it is a part of the work, not the whole selection.
Data: ``random`` (uniform cube) and ``concave`` (radius 1 + |N(0, 0.02)| on the positive
orthant of the unit sphere: a concave front for minimization, most points non-dominated).
Plus the realistic planner matrix (n = 400, m = 6, few people near: most ID columns 0).

Usage: ``python benchmarks/bench_paccet.py [--quick]``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from harness import Case, run_table
from socialnav.moo import (
    PaccetOptions,
    PaccetSelection,
    Weighted,
    WeightedSum,
    paccet_select,
)
from socialnav.moo.nondominated import nondominated_mask

NAV_WEIGHTS = [0.4, 0.5, 0.5, 0.5, 0.0, 1.0]  # the navigation code's weights (m = 6)


# --------------------------------------------------------------------------- data
def random_points(n: int, m: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).random((n, m))


def concave_points(n: int, m: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    d = np.abs(rng.normal(size=(n, m)))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return d * (1.0 + np.abs(rng.normal(0.0, 0.02, size=(n, 1))))


def realistic_planner_matrix(n: int = 400, seed: int = 0) -> np.ndarray:
    """(ROS cost, ID person 1..3, group, social goal): few people near, many equal costs."""
    rng = np.random.default_rng(seed)
    F = np.zeros((n, 6))
    F[:, 0] = np.round(rng.uniform(0.5, 3.0, n), 3)  # ROS cost
    levels = np.exp(1.0 / np.array([0.7, 0.9, 1.1, 1.3, 1.5]))  # e^(1/d), d <= 1.5 m
    for col, p_near in ((1, 0.2), (2, 0.05)):  # person 3 and the group are far: all 0
        near = rng.random(n) < p_near
        F[near, col] = rng.choice(levels, near.sum())
    F[:, 5] = np.round(rng.uniform(0.0, 2.0, n), 3)  # social-goal distance
    return F


# --------------------------------------------------------------------------- naive baseline
def naive_select(F: np.ndarray, weights: np.ndarray | None = None, delta: float = 0.001) -> int:
    """The direct NumPy port: one-line broadcasts, no chunking, no sorting."""
    n = F.shape[0]
    le = np.all(F[:, None, :] <= F[None, :, :], axis=2)  # le[a, b]: a weakly dominates b
    eq = np.all(F[:, None, :] == F[None, :, :], axis=2)
    earlier = np.arange(n)[:, None] < np.arange(n)[None, :]
    dominated = np.any(le & (~eq | earlier), axis=0)
    A = F[~dominated]
    u = A.min(axis=0) - delta
    rng = A.max(axis=0) - u
    x = (F - u) / rng
    S = (A - u) / rng
    s_star = np.min(np.max(S[None, :, :] / x[:, None, :], axis=2), axis=1)
    T = x / (s_star * x.sum(axis=1))[:, None]
    fit = T.sum(axis=1) if weights is None else T @ weights
    return int(np.argmin(np.where(dominated, np.inf, fit)))


def pymoo_front(F: np.ndarray):
    from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

    return NonDominatedSorting().do(F, only_non_dominated_front=True)


# --------------------------------------------------------------------------- cases
def grid_cases(sizes, dims, datasets) -> list[Case]:
    parity = PaccetOptions(method="parity")
    cases = []
    for name, gen in datasets:
        for m in dims:
            for n in sizes:
                F = gen(n, m)
                P = int(nondominated_mask(F).sum())
                group = f"{name} n={n} m={m}"
                big = n >= 2000
                reps = 3 if big else 7
                extra = {"P": str(P)}
                naive_fits = n * n * m + n * P * m <= 3e8  # memory of the broadcasts
                if naive_fits:
                    cases.append(
                        Case(
                            group,
                            "naive (baseline)",
                            lambda F=F: naive_select(F),
                            reps,
                            extra=extra,
                        )
                    )
                base = "naive (baseline)" if naive_fits else None
                cases += [
                    Case(
                        group,
                        "select closed",
                        lambda F=F: paccet_select(F),
                        reps,
                        baseline=base,
                        extra=extra,
                    ),
                    Case(
                        group,
                        "select parity",
                        lambda F=F: paccet_select(F, options=parity),
                        reps,
                        baseline=base,
                        extra=extra,
                    ),
                    Case(
                        group,
                        "pymoo NDS front",
                        lambda F=F: pymoo_front(F),
                        reps,
                        baseline=base,
                        extra=extra,
                    ),
                ]
    return cases


def realistic_cases() -> list[Case]:
    F = realistic_planner_matrix()
    legal = np.ones(F.shape[0], dtype=bool)
    w = np.asarray(NAV_WEIGHTS)
    scal = Weighted(NAV_WEIGHTS)
    sel = PaccetSelection(scal)
    ref = PaccetSelection(scal, PaccetOptions.reference())
    P = int(nondominated_mask(F).sum())
    extra = {"P": str(P)}
    g = "planner n=400 m=6"
    b = "naive (baseline)"
    return [
        Case(g, b, lambda: naive_select(F, w), 50, extra=extra),
        Case(g, "select closed", lambda: paccet_select(F, scal), 200, baseline=b, extra=extra),
        Case(
            g, "PaccetSelection.select", lambda: sel.select(F, legal), 200, baseline=b, extra=extra
        ),
        Case(
            g, "reference parity select", lambda: ref.select(F, legal), 200, baseline=b, extra=extra
        ),
        Case(
            g,
            "WeightedSum.select (ROS)",
            lambda: WeightedSum(NAV_WEIGHTS).select(F, legal),
            200,
            baseline=b,
            extra=extra,
        ),
        Case(g, "pymoo NDS front", lambda: pymoo_front(F), 200, baseline=b, extra=extra),
    ]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller grid, fewer repeats")
    args = parser.parse_args(argv)
    datasets = [("random", random_points), ("concave", concave_points)]
    if args.quick:
        sizes, dims = (100, 400, 2000), (2, 6)
    else:
        sizes, dims = (100, 400, 2000, 10000), (2, 4, 6)
    run_table(realistic_cases(), "Realistic planner matrix (target < 1 ms)")
    run_table(grid_cases(sizes, dims, datasets), "paccet_select vs naive NumPy and pymoo")


if __name__ == "__main__":
    main()

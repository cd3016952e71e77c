"""PaCcET evolutionary optimizer: the author's mutation-only loop as a general MOO solver.

Citation: L. Yliniemi and K. Tumer, "PaCcET: An Objective Space Transformation to Iteratively
Convexify the Pareto Front", SEAL 2014; reference driver ``KUR.cpp`` / ``Evo_Agent_KUR.h`` in
logan-yliniemi/PaCcET_MWE. The navigation paper (Banisetty et al.) cites this loop for its claim
that PaCcET matches NSGA-II/SPEA2 hypervolume on KUR "with as low as one-tenth of the run-time".

The loop, per generation (population ``pop_size``, ``n_eliminate`` replaced):
1. every population member's objective vector is archive-checked into one *persistent*
   :class:`~socialnav.moo.archive.ParetoArchive` (random thinning, threshold 250, buffer 1);
2. each member is scored by ``scalarization(paccet_transform(F, archive.points))`` (lowest best);
3. the worst ``n_eliminate`` are dropped; each replacement is a mutated clone of the best survivor
   with probability ``p_best`` (reference: 10 %), else of a uniformly random survivor;
4. the clones are evaluated.
The result is the final archive (its decision vectors and objective vectors).

Deviations from the reference driver:
- Mutation is Gaussian, ``sigma = mutation_scale * (xu - xl)`` per variable (default 0.03, i.e.
  0.3 on KUR's [-5, 5]); the reference adds ``r cos(theta)`` with ``r ~ Exp(mean 0.3)``, whose
  standard deviation is also 0.3 but with heavier tails. Bounded variables are clipped (as there).
- Survivors are not re-evaluated: the reference re-evaluates all 100 members every generation,
  which on a deterministic problem returns identical objectives and doubles the evaluation count.
  Here a generation costs ``n_eliminate`` evaluations (plus ``pop_size`` once for the start).
- ``tie_break="dominance"`` (default): fitness ties (to 1e-9 relative) rank members that are
  weakly dominated by an archive member below the rest. This is the documented remedy for the
  weak-dominance blind spot (paccet.md, degeneracy 2): a point equal to a front point in the
  binding objective gets ``s* = 1`` like the front itself, and clipping at a bound makes such
  points common (ZDT: every clone with ``x1`` clipped to 0 has ``f1 = 0`` exactly); without the
  key they flood the population and the run stalls. ``tie_break="none"`` keeps the reference
  behaviour. Remaining ties keep population order (stable sort: earlier survivors first).
- The reference seeds its archive with a dummy (1000, 1000) point; not needed here.
- Optional ``anchors`` (objective vectors, e.g. the two KUR extremes of later author versions) are
  archive-checked at the start and after every generation (the reference re-adds them after
  thinning). They carry no decision vector and are left out of the returned archive.
- All randomness (initial sampling, parent choice, mutation, archive thinning) comes from one
  ``numpy.random.Generator`` built from ``seed``.

pymoo is optional: :class:`PaccetAlgorithm` (a ``pymoo.core.algorithm.Algorithm``) is built on
first access, so importing this module never imports pymoo.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from socialnav.core.errors import ConfigurationError, InvalidInputError

if TYPE_CHECKING:  # pragma: no cover
    from socialnav.moo.paccet import PaccetOptions

# PaccetAlgorithm is importable too (built lazily by __getattr__, so it is not in __all__).
__all__ = [
    "PaccetEvolution",
    "PaccetEvolutionResult",
    "paccet_evolve",
    "paccet_optimize",
]

Scalarization = Callable[[NDArray[np.float64]], NDArray[np.float64]]
FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PaccetEvolutionResult:
    """Outcome of a PaCcET run.

    ``X`` (P, d) and ``F`` (P, m): the final archive (non-dominated, at most the thinning
    threshold), anchors excluded. ``pop_X`` (pop_size, d) / ``pop_F`` (pop_size, m): the last
    population, best fitness first. ``n_eval``: objective evaluations spent; ``n_gen``: generations
    after the initial population.
    """

    X: FloatArray
    F: FloatArray
    pop_X: FloatArray
    pop_F: FloatArray
    n_eval: int
    n_gen: int


def _check_bounds(xl: ArrayLike, xu: ArrayLike) -> tuple[FloatArray, FloatArray]:
    lo = np.atleast_1d(np.asarray(xl, dtype=float))
    hi = np.atleast_1d(np.asarray(xu, dtype=float))
    if lo.ndim != 1 or lo.shape != hi.shape or lo.size == 0:
        raise ConfigurationError(
            f"bounds must be two 1-D arrays of equal length, got {lo.shape}, {hi.shape}"
        )
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        raise ConfigurationError("bounds must be finite (PaCcET samples the box uniformly)")
    if np.any(hi <= lo):
        raise ConfigurationError("every upper bound must exceed its lower bound")
    return lo, hi


def _canonical(F: FloatArray) -> FloatArray:
    # +0.0 turns -0.0 into 0.0 so that equal values also have equal bytes for the row matching.
    return np.ascontiguousarray(F, dtype=float) + 0.0


def _match_rows(A: FloatArray, B: FloatArray) -> NDArray[np.intp]:
    """Index into ``B`` (first occurrence) of every row of ``A``; every row must be present."""
    both = np.vstack([_canonical(B), _canonical(A)])
    _, inverse = np.unique(both, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    ids_b, ids_a = inverse[: len(B)], inverse[len(B) :]
    first = np.full(int(inverse.max()) + 1, -1, dtype=np.intp)
    first[ids_b[::-1]] = np.arange(len(B), dtype=np.intp)[::-1]  # last write wins → first index
    idx = first[ids_a]
    if np.any(idx < 0):  # pragma: no cover - the archive only ever stores rows it was given
        raise RuntimeError("archive holds a point that was never offered to it")
    return idx


class PaccetEvolution:
    """Ask/tell state machine of the PaCcET evolutionary loop (pure NumPy, no pymoo).

    ``ask()`` returns decision vectors to evaluate: (pop_size, d) the first time, then
    (n_eliminate, d) mutated clones. ``tell(X, F)`` takes them back with their objectives (n, m),
    all minimized. Both the plain loop :func:`paccet_evolve` and :class:`PaccetAlgorithm` drive it.

    Parameters (see the module docstring for the loop):
        xl, xu: (d,) finite box bounds.
        pop_size: population size (reference 100), >= 2.
        n_eliminate: members replaced per generation, 1..pop_size-1 (default pop_size // 2).
        mutation_scale: Gaussian sigma as a fraction of each variable's range, > 0.
        p_best: probability a clone's parent is the best survivor rather than a random one.
        scalarization: ``"equal"`` (sum of transformed objectives), ``"target"`` (L1 distance to
            ``target`` on the simplex) or any callable T (n, m) -> (n,), lowest best.
        target: (m,) simplex point for ``"target"``.
        anchors: (k, m) objective vectors kept in the archive (no decision vectors).
        archive_threshold, archive_buffer: archive thinning (reference 250 / 1); threshold None
            disables thinning.
        paccet_options: :class:`~socialnav.moo.paccet.PaccetOptions` for the transform.
        tie_break: ``"dominance"`` (default) or ``"none"`` (reference); see the module docstring.
        seed: int, None or a ``numpy.random.Generator`` (used as is, not copied).
    """

    def __init__(
        self,
        xl: ArrayLike,
        xu: ArrayLike,
        *,
        pop_size: int = 100,
        n_eliminate: int | None = None,
        mutation_scale: float = 0.03,
        p_best: float = 0.1,
        scalarization: str | Scalarization = "equal",
        target: ArrayLike | None = None,
        anchors: ArrayLike | None = None,
        archive_threshold: int | None = 250,
        archive_buffer: int = 1,
        paccet_options: PaccetOptions | None = None,
        tie_break: str = "dominance",
        seed: int | np.random.Generator | None = 0,
    ) -> None:
        from socialnav.moo.archive import ParetoArchive
        from socialnav.moo.paccet import PaccetOptions

        self.xl, self.xu = _check_bounds(xl, xu)
        _check_config(
            pop_size, n_eliminate, mutation_scale, p_best, archive_threshold, archive_buffer
        )
        self.pop_size = int(pop_size)
        self.n_eliminate = self.pop_size // 2 if n_eliminate is None else int(n_eliminate)
        self.n_keep = self.pop_size - self.n_eliminate
        self.sigma = float(mutation_scale) * (self.xu - self.xl)
        self.p_best = float(p_best)
        self._scalarization_spec = scalarization
        self._target = None if target is None else np.asarray(target, dtype=float)
        if isinstance(scalarization, str):
            if scalarization not in ("equal", "target"):
                raise ConfigurationError(
                    f"scalarization must be 'equal', 'target' or a callable, got {scalarization!r}"
                )
            if scalarization == "target" and self._target is None:
                raise ConfigurationError("scalarization='target' needs a target point")
        elif not callable(scalarization):
            raise ConfigurationError("scalarization must be 'equal', 'target' or a callable")
        if self._target is not None and (
            self._target.ndim != 1 or not np.all(np.isfinite(self._target))
        ):
            raise ConfigurationError("target must be a finite 1-D vector")
        self._anchors: FloatArray | None = None
        if anchors is not None:
            a = np.atleast_2d(np.asarray(anchors, dtype=float))
            if a.ndim != 2 or a.size == 0 or not np.all(np.isfinite(a)):
                raise ConfigurationError("anchors must be a finite (k, m) array")
            self._anchors = a
        self.options = PaccetOptions() if paccet_options is None else paccet_options
        if tie_break not in ("dominance", "none"):
            raise ConfigurationError(f"tie_break must be 'dominance' or 'none', got {tie_break!r}")
        self.tie_break = tie_break

        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        # The archive's thinning draws from its own seeded generator, derived from ours.
        self.archive = ParetoArchive(
            threshold=archive_threshold,
            buffer=archive_buffer,
            seed=int(self.rng.integers(2**62)),
        )
        self._scalarize: Scalarization | None = None
        self._archive_X = np.empty((0, self.xl.size))
        self.X: FloatArray | None = None  # (pop_size, d), best fitness first after tell()
        self.F: FloatArray | None = None
        self.fitness: FloatArray | None = None
        self.last_X: FloatArray | None = None
        self.last_F: FloatArray | None = None
        self.n_obj: int | None = None
        self.n_eval = 0
        self.n_gen = 0  # completed generations after the initial population

    # -- ask / tell -------------------------------------------------------------------------
    def ask(self) -> FloatArray:
        """Decision vectors to evaluate next: (pop_size, d) first, then (n_eliminate, d)."""
        d = self.xl.size
        if self.X is None:
            return self.rng.uniform(self.xl, self.xu, size=(self.pop_size, d))
        # Draw every random number on both branches so the stream does not depend on outcomes.
        parent = self.rng.integers(self.n_keep, size=self.n_eliminate)
        parent[self.rng.random(self.n_eliminate) < self.p_best] = 0  # survivors sorted: 0 = best
        noise = self.rng.normal(0.0, 1.0, size=(self.n_eliminate, d)) * self.sigma
        return np.clip(self.X[parent] + noise, self.xl, self.xu)

    def tell(self, X: ArrayLike, F: ArrayLike) -> None:
        """Insert evaluated vectors X (n, d) with objectives F (n, m): archive, score, select."""
        X = np.asarray(X, dtype=float)
        F = np.asarray(F, dtype=float)
        expected = self.pop_size if self.X is None else self.n_eliminate
        if X.shape != (expected, self.xl.size):
            raise InvalidInputError(f"X must have shape {(expected, self.xl.size)}, got {X.shape}")
        if F.ndim != 2 or F.shape[0] != expected:
            raise InvalidInputError(f"F must have shape ({expected}, m), got {F.shape}")
        if not np.all(np.isfinite(F)):
            raise InvalidInputError("objective values must be finite (no NaN/inf)")
        if self.n_obj is None:
            self._bind_objectives(F.shape[1])
        elif F.shape[1] != self.n_obj:
            raise InvalidInputError(f"expected {self.n_obj} objectives, got {F.shape[1]}")

        if self.X is None:
            pop_X, pop_F = X, F
        else:
            assert self.F is not None
            pop_X = np.vstack([self.X[: self.n_keep], X])
            pop_F = np.vstack([self.F[: self.n_keep], F])
            self.n_gen += 1
        self.n_eval += len(X)
        self.last_X, self.last_F = X, F  # the batch just told (for callbacks and benchmarks)
        self._update_archive(pop_X, pop_F)

        from socialnav.moo.paccet import paccet_transform

        assert self._scalarize is not None
        T = paccet_transform(pop_F, self.archive.points, self.options)
        fitness = np.asarray(self._scalarize(T), dtype=float).reshape(-1)
        if self.tie_break == "dominance":
            # lexsort: last key primary. Rounding makes float-noise ties (0.99999... vs 1) equal.
            scale = np.max(np.abs(fitness[np.isfinite(fitness)]), initial=1e-300)
            key = np.round(fitness, 9 - int(np.ceil(np.log10(scale))))
            order = np.lexsort((np.arange(len(fitness)), self._weakly_dominated(pop_F), key))
        else:
            order = np.argsort(fitness, kind="stable")
        self.X, self.F, self.fitness = pop_X[order], pop_F[order], fitness[order]

    # -- results ------------------------------------------------------------------------------
    @property
    def archive_X(self) -> FloatArray:
        """(P, d) decision vectors of the archive members found by search (anchors left out)."""
        return self._archive_X[self._found_mask()]

    @property
    def archive_F(self) -> FloatArray:
        """(P, m) objective vectors matching :attr:`archive_X`."""
        return np.asarray(self.archive.points, dtype=float)[self._found_mask()]

    def result(self) -> PaccetEvolutionResult:
        """The final archive and population as a :class:`PaccetEvolutionResult`."""
        if self.X is None or self.F is None:
            raise RuntimeError("no generation has been told yet")
        return PaccetEvolutionResult(
            X=self.archive_X.copy(),
            F=self.archive_F.copy(),
            pop_X=self.X.copy(),
            pop_F=self.F.copy(),
            n_eval=self.n_eval,
            n_gen=self.n_gen,
        )

    # -- internals ----------------------------------------------------------------------------
    def _found_mask(self) -> NDArray[np.bool_]:
        return ~np.isnan(self._archive_X[:, 0]) if self._archive_X.size else np.zeros(0, bool)

    def _weakly_dominated(self, F: FloatArray) -> NDArray[np.bool_]:
        """(n,) True where an archive member weakly dominates the row and differs from it."""
        A = np.asarray(self.archive.points, dtype=float)
        le = np.ones((len(F), len(A)), dtype=bool)
        lt = np.zeros((len(F), len(A)), dtype=bool)
        for j in range(F.shape[1]):  # one objective at a time keeps memory at n x P
            le &= A[None, :, j] <= F[:, None, j]
            lt |= A[None, :, j] < F[:, None, j]
        return np.any(le & lt, axis=1)

    def _bind_objectives(self, m: int) -> None:
        from socialnav.moo.scalarize import EqualWeight, L1Target

        if m < 2:
            raise InvalidInputError(f"PaCcET needs at least 2 objectives, got {m}")
        if self._target is not None and self._target.shape != (m,):
            raise ConfigurationError(f"target must have {m} entries, got {self._target.shape}")
        if self._anchors is not None and self._anchors.shape[1] != m:
            raise ConfigurationError(f"anchors must have {m} columns, got {self._anchors.shape}")
        spec = self._scalarization_spec
        if spec == "equal":
            self._scalarize = EqualWeight()
        elif spec == "target":
            assert self._target is not None  # checked with the configuration
            self._scalarize = L1Target(self._target)
        else:
            self._scalarize = spec  # type: ignore[assignment]
        self.n_obj = m

    def _update_archive(self, pop_X: FloatArray, pop_F: FloatArray) -> None:
        prev_F = np.asarray(self.archive.points, dtype=float).reshape(-1, pop_F.shape[1])
        cand_F = [prev_F, pop_F]
        cand_X = [self._archive_X, pop_X]
        self.archive.extend(pop_F)
        if self._anchors is not None:
            self.archive.extend(self._anchors)
            cand_F.append(self._anchors)
            cand_X.append(np.full((len(self._anchors), pop_X.shape[1]), np.nan))
        # The archive stores objective vectors only: recover each member's decision vector.
        idx = _match_rows(np.asarray(self.archive.points, dtype=float), np.vstack(cand_F))
        self._archive_X = np.vstack(cand_X)[idx]


def _check_config(
    pop_size: int,
    n_eliminate: int | None,
    mutation_scale: float,
    p_best: float,
    archive_threshold: int | None,
    archive_buffer: int,
) -> None:
    if isinstance(pop_size, bool) or not isinstance(pop_size, int | np.integer) or pop_size < 2:
        raise ConfigurationError(f"pop_size must be an integer >= 2, got {pop_size!r}")
    if n_eliminate is not None and not (
        isinstance(n_eliminate, int | np.integer) and 1 <= n_eliminate < pop_size
    ):
        raise ConfigurationError(f"n_eliminate must be in [1, pop_size), got {n_eliminate!r}")
    if not (np.isfinite(mutation_scale) and mutation_scale > 0):
        raise ConfigurationError(f"mutation_scale must be > 0, got {mutation_scale!r}")
    if not (0.0 <= p_best <= 1.0):
        raise ConfigurationError(f"p_best must be in [0, 1], got {p_best!r}")
    if archive_threshold is not None and archive_threshold < 2:
        raise ConfigurationError(
            f"archive_threshold must be >= 2 or None, got {archive_threshold!r}"
        )
    if archive_buffer < 1:
        raise ConfigurationError(f"archive_buffer must be >= 1, got {archive_buffer!r}")


def paccet_evolve(
    evaluate: Callable[[FloatArray], ArrayLike],
    xl: ArrayLike,
    xu: ArrayLike,
    n_gen: int,
    pop_size: int = 100,
    seed: int | np.random.Generator | None = 0,
    *,
    callback: Callable[[PaccetEvolution], object] | None = None,
    **options: Any,
) -> PaccetEvolutionResult:
    """Run the PaCcET loop as a plain NumPy loop (no optimization framework).

    ``evaluate`` maps X (n, d) to F (n, m), minimized. Spends ``pop_size + n_gen * n_eliminate``
    evaluations. ``callback(state)`` runs after the initial population and after every
    generation. ``options`` go to :class:`PaccetEvolution`.
    """
    if isinstance(n_gen, bool) or not isinstance(n_gen, int | np.integer) or n_gen < 0:
        raise ConfigurationError(f"n_gen must be an integer >= 0, got {n_gen!r}")
    state = PaccetEvolution(xl, xu, pop_size=pop_size, seed=seed, **options)
    for _ in range(int(n_gen) + 1):
        X = state.ask()
        state.tell(X, evaluate(X))
        if callback is not None:
            callback(state)
    return state.result()


def _problem_bounds(problem: Any) -> tuple[FloatArray, FloatArray]:
    n_constr = int(getattr(problem, "n_ieq_constr", 0) or 0) + int(
        getattr(problem, "n_eq_constr", 0) or 0
    )
    if n_constr:
        raise ConfigurationError("PaCcET handles unconstrained problems only")
    if getattr(problem, "xl", None) is None or getattr(problem, "xu", None) is None:
        raise ConfigurationError("the problem must define finite bounds xl and xu")
    xl, xu = _check_bounds(problem.xl, problem.xu)
    if xl.size != int(problem.n_var):
        raise ConfigurationError("bounds do not match problem.n_var")
    return xl, xu


def paccet_optimize(
    problem: Any,
    n_gen: int,
    pop_size: int = 100,
    seed: int | np.random.Generator | None = 0,
    *,
    callback: Callable[[PaccetEvolution], object] | None = None,
    **options: Any,
) -> PaccetEvolutionResult:
    """Optimize a pymoo ``Problem`` (unconstrained, bounded) with the plain PaCcET loop.

    Needs only the problem's ``xl``, ``xu``, ``n_var`` and ``evaluate``; pymoo's optimization
    framework is not involved. Same seed → same result as ``minimize(problem, PaccetAlgorithm(...),
    seed=seed)`` with the same number of generations.
    """
    xl, xu = _problem_bounds(problem)

    def evaluate(X: FloatArray) -> FloatArray:
        return np.asarray(problem.evaluate(X, return_values_of=["F"]), dtype=float)

    return paccet_evolve(evaluate, xl, xu, n_gen, pop_size, seed, callback=callback, **options)


_PYMOO_CLASS: type | None = None


def _build_pymoo_algorithm() -> type:
    """Define the pymoo ``Algorithm`` subclass (imports pymoo; raises ImportError without it)."""
    from pymoo.core.algorithm import Algorithm
    from pymoo.core.population import Population

    class PaccetAlgorithm(Algorithm):  # type: ignore[misc]
        """PaCcET loop as a pymoo ``Algorithm``; ``res.X``/``res.F`` hold the final archive.

        Keyword arguments as :class:`PaccetEvolution` (``pop_size``, ``n_eliminate``,
        ``mutation_scale``, ``p_best``, ``scalarization``, ``target``, ``anchors``,
        ``archive_threshold``, ``archive_buffer``, ``paccet_options``, ``tie_break``); the rest
        go to pymoo's ``Algorithm`` (termination, callback, ...). Randomness comes from pymoo's
        ``random_state`` (``minimize(..., seed=s)``), so results match ``paccet_optimize`` with
        the same seed.
        """

        def __init__(
            self,
            pop_size: int = 100,
            n_eliminate: int | None = None,
            mutation_scale: float = 0.03,
            p_best: float = 0.1,
            scalarization: str | Scalarization = "equal",
            target: ArrayLike | None = None,
            anchors: ArrayLike | None = None,
            archive_threshold: int | None = 250,
            archive_buffer: int = 1,
            paccet_options: PaccetOptions | None = None,
            tie_break: str = "dominance",
            **kwargs: Any,
        ) -> None:
            super().__init__(**kwargs)
            _check_config(
                pop_size, n_eliminate, mutation_scale, p_best, archive_threshold, archive_buffer
            )
            self.pop_size = pop_size
            self._options: dict[str, Any] = {
                "pop_size": pop_size,
                "n_eliminate": n_eliminate,
                "mutation_scale": mutation_scale,
                "p_best": p_best,
                "scalarization": scalarization,
                "target": target,
                "anchors": anchors,
                "archive_threshold": archive_threshold,
                "archive_buffer": archive_buffer,
                "paccet_options": paccet_options,
                "tie_break": tie_break,
            }
            self.state: PaccetEvolution | None = None

        def _setup(self, problem: Any, **kwargs: Any) -> None:
            xl, xu = _problem_bounds(problem)
            self.state = PaccetEvolution(xl, xu, seed=self.random_state, **self._options)

        def _ask(self) -> Any:
            assert self.state is not None
            return Population.new(X=self.state.ask())

        def _tell(self, infills: Any) -> None:
            assert self.state is not None
            self.state.tell(infills.get("X"), infills.get("F"))
            self.pop = Population.new(X=self.state.X, F=self.state.F)

        def _initialize_infill(self) -> Any:
            return self._ask()

        def _initialize_advance(self, infills: Any = None, **kwargs: Any) -> None:
            self._tell(infills)

        def _infill(self) -> Any:
            return self._ask()

        def _advance(self, infills: Any = None, **kwargs: Any) -> None:
            self._tell(infills)

        def _set_optimum(self) -> None:
            assert self.state is not None
            X, F = self.state.archive_X, self.state.archive_F
            self.opt = Population.new(X=X, F=F, CV=np.zeros((len(X), 1)))

    PaccetAlgorithm.__module__ = __name__
    return PaccetAlgorithm


def __getattr__(name: str) -> Any:
    # PEP 562: build the pymoo subclass only when someone asks for it (pymoo is an extra).
    global _PYMOO_CLASS
    if name == "PaccetAlgorithm":
        if _PYMOO_CLASS is None:
            try:
                _PYMOO_CLASS = _build_pymoo_algorithm()
            except ImportError as exc:  # pragma: no cover - exercised only without pymoo
                raise ImportError(
                    "PaccetAlgorithm needs pymoo: install the 'socialnav[moo]' extra"
                ) from exc
            globals()["PaccetAlgorithm"] = _PYMOO_CLASS
        return _PYMOO_CLASS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

"""Behaviour of the PaCcET evolutionary optimizer (plain loop and pymoo Algorithm)."""

from __future__ import annotations

import subprocess
import sys

import moocore
import numpy as np
import pytest

from socialnav.moo.optimizer import PaccetEvolution, paccet_evolve, paccet_optimize

pymoo = pytest.importorskip("pymoo")
from pymoo.core.problem import Problem  # noqa: E402
from pymoo.optimize import minimize  # noqa: E402
from pymoo.problems import get_problem  # noqa: E402


def schaffer(X: np.ndarray) -> np.ndarray:
    """Schaffer N.1: f = (x^2, (x-2)^2); Pareto set is exactly x in [0, 2]."""
    x = X[:, 0]
    return np.column_stack([x**2, (x - 2.0) ** 2])


def test_improves_hypervolume_on_zdt1() -> None:
    ref = (1.1, 10.0)  # wide enough that the random initial population scores > 0
    hv: list[float] = []
    res = paccet_optimize(
        get_problem("zdt1"),
        30,
        seed=0,
        callback=lambda s: hv.append(moocore.hypervolume(s.archive_F, ref=ref)),
    )
    assert len(hv) == 31
    assert hv[-1] > hv[0] + 0.3  # initial about 7.3; 30 generations add about 0.8
    assert moocore.hypervolume(res.F, ref=ref) == pytest.approx(hv[-1])
    assert res.n_eval == 100 + 30 * 50


def test_final_archive_is_nondominated_and_on_schaffer_pareto_set() -> None:
    res = paccet_evolve(schaffer, [-5.0], [5.0], 40, pop_size=40, seed=3)
    assert moocore.is_nondominated(res.F).all()
    assert len(res.F) > 10
    assert np.all((res.X[:, 0] >= -0.02) & (res.X[:, 0] <= 2.02))
    np.testing.assert_allclose(res.F, schaffer(res.X))


def test_same_seed_identical_different_seed_differs() -> None:
    p = get_problem("kursawe")
    a = paccet_optimize(p, 15, seed=7)
    b = paccet_optimize(p, 15, seed=7)
    c = paccet_optimize(p, 15, seed=8)
    np.testing.assert_array_equal(a.X, b.X)
    np.testing.assert_array_equal(a.F, b.F)
    np.testing.assert_array_equal(a.pop_X, b.pop_X)
    assert a.F.shape != c.F.shape or not np.array_equal(a.F, c.F)


def test_runs_through_pymoo_minimize_and_matches_plain_loop() -> None:
    from socialnav.moo.optimizer import PaccetAlgorithm

    p = get_problem("kursawe")
    res = minimize(p, PaccetAlgorithm(pop_size=100), ("n_eval", 100 + 20 * 50), seed=4)
    assert res.algorithm.evaluator.n_eval == 1100
    plain = paccet_optimize(p, 20, seed=4)
    np.testing.assert_array_equal(res.X, plain.X)
    np.testing.assert_array_equal(res.F, plain.F)
    assert moocore.is_nondominated(res.F).all()
    np.testing.assert_allclose(res.F, p.evaluate(res.X, return_values_of=["F"]))
    assert len(res.pop) == 100


def test_bounds_respected_with_large_mutation() -> None:
    xl, xu = np.array([-1.0, 0.0, 2.0]), np.array([1.0, 0.5, 2.1])
    seen: list[np.ndarray] = []

    def f(X: np.ndarray) -> np.ndarray:
        seen.append(X.copy())
        return np.column_stack([np.sum(X**2, axis=1), np.sum((X - 1.0) ** 2, axis=1)])

    res = paccet_evolve(f, xl, xu, 10, pop_size=20, seed=0, mutation_scale=2.0)
    allx = np.vstack(seen)
    assert np.all(allx >= xl) and np.all(allx <= xu)
    assert np.any(allx == xl) and np.any(allx == xu)  # clipping did happen
    assert np.all(xl <= res.X) and np.all(xu >= res.X)


def test_target_scalarization_steers_the_population() -> None:
    def run(target: tuple[float, float]) -> float:
        res = paccet_evolve(
            schaffer,
            [-5.0],
            [5.0],
            40,
            pop_size=40,
            seed=1,
            scalarization="target",
            target=target,
        )
        return float(np.median(res.pop_X[:, 0]))

    # T_1 large ⇔ f1 = x^2 large relative to the archive: the population follows the target.
    assert run((0.9, 0.1)) > run((0.1, 0.9)) + 0.5


def test_anchors_kept_in_archive_but_not_returned() -> None:
    anchors = np.array([[0.0, 4.0], [4.0, 0.0]])  # Schaffer's extremes (x = 0 and x = 2)
    state = PaccetEvolution([-5.0], [5.0], pop_size=20, anchors=anchors, seed=0)
    for _ in range(5):
        X = state.ask()
        state.tell(X, schaffer(X))
    pts = np.asarray(state.archive.points)
    assert len(pts) == len(state.archive_F) + int(np.sum(np.isnan(state._archive_X[:, 0])))
    assert not np.isnan(state.result().X).any()


@pytest.mark.parametrize(
    "kwargs",
    [
        {"pop_size": 1},
        {"n_eliminate": 0},
        {"n_eliminate": 100},
        {"mutation_scale": 0.0},
        {"p_best": 1.5},
        {"scalarization": "median"},
        {"scalarization": "target"},
        {"scalarization": 3},
        {"tie_break": "random"},
        {"archive_threshold": 1},
    ],
)
def test_bad_options_raise(kwargs: dict) -> None:
    with pytest.raises(ValueError):
        paccet_evolve(schaffer, [-5.0], [5.0], 2, seed=0, **kwargs)
    if "pop_size" not in kwargs:
        from socialnav.moo.optimizer import PaccetAlgorithm

        with pytest.raises(ValueError):
            minimize(get_problem("kursawe"), PaccetAlgorithm(**kwargs), ("n_gen", 2), seed=0)


def test_bad_problems_and_data_raise() -> None:
    with pytest.raises(ValueError):
        paccet_evolve(schaffer, [1.0], [0.0], 2)  # empty box
    with pytest.raises(ValueError):
        paccet_evolve(schaffer, [-np.inf], [5.0], 2)
    with pytest.raises(ValueError):
        paccet_evolve(schaffer, [-5.0], [5.0], -1)
    with pytest.raises(ValueError):
        paccet_evolve(lambda X: np.full((len(X), 2), np.nan), [-5.0], [5.0], 2)
    with pytest.raises(ValueError):
        paccet_evolve(lambda X: X[:, :1] ** 2, [-5.0], [5.0], 2)  # single objective
    with pytest.raises(ValueError):
        paccet_evolve(schaffer, [-5.0], [5.0], 2, scalarization="target", target=(0.2, 0.3, 0.5))
    with pytest.raises(ValueError):
        paccet_optimize(get_problem("tnk"), 2)  # constrained
    with pytest.raises(ValueError):
        paccet_optimize(Problem(n_var=2, n_obj=2), 2)  # no bounds
    state = PaccetEvolution([-5.0], [5.0], pop_size=10)
    with pytest.raises(ValueError):
        state.tell(np.zeros((3, 1)), np.zeros((3, 2)))  # wrong batch size


def test_module_imports_without_pymoo() -> None:
    code = (
        "import sys; sys.modules['pymoo'] = None\n"
        "import socialnav.moo.optimizer as o\n"
        "import numpy as np\n"
        "r = o.paccet_evolve(lambda X: np.c_[X[:, 0]**2, (X[:, 0]-2)**2], [-5.], [5.], 3, 10)\n"
        "try:\n    o.PaccetAlgorithm\nexcept ImportError:\n    print('ok', len(r.F) > 0)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok True"

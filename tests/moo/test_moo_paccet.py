import math

import numpy as np
import pytest
from _moo_helpers import EXAMPLE1, EXAMPLE2

from socialnav.moo import (
    EqualWeight,
    L1Target,
    PaccetOptions,
    PaccetTransform,
    Weighted,
    normalize,
    paccet_select,
    paccet_transform,
)

# The paccet.md test vectors: closed form, absolute delta 0.001, no remedies.
VECTORS = PaccetOptions(
    delta_mode="absolute",
    drop_constant_objectives=False,
    rank_weakly_dominated=False,
    sentinel=None,
)


# ---------------------------------------------------------------- reference test vectors
def test_example1_transform():
    T = paccet_select(EXAMPLE1, options=VECTORS).transformed
    expected = [
        [0.999002, 0.000998],
        [0.571327, 0.428673],
        [0.428673, 0.571327],
        [0.000998, 0.999002],
        [0.562422, 0.562422],
    ]
    np.testing.assert_allclose(T, expected, atol=1e-5)


@pytest.mark.parametrize(
    ("scalarization", "fitness", "best"),
    [
        (EqualWeight(), [1, 1, 1, 1, 1.124844], 0),
        (L1Target([0.45, 0.55]), [1.098004, 0.242653, 0.042653, 0.898004, 0.124844], 2),
        (Weighted([0.6, 0.4]), [0.599800, 0.514265, 0.485735, 0.400200, 0.562422], 3),
    ],
)
@pytest.mark.parametrize("remedies", [False, True])
def test_example1_fitness(scalarization, fitness, best, remedies):
    # Example 1 has unit ranges, so the relative delta and the remedies change nothing.
    options = PaccetOptions() if remedies else VECTORS
    res = paccet_select(EXAMPLE1, scalarization, options)
    np.testing.assert_allclose(res.fitness, fitness, atol=1e-5)
    assert res.best_index == best


def test_example1_no_raw_weighted_sum_selects_the_concave_points():
    w1 = np.linspace(0.0, 1.0, 1001)
    W = np.column_stack([w1, 1.0 - w1])
    picks = set(np.argmin(EXAMPLE1 @ W.T, axis=0).tolist())
    assert picks.isdisjoint({1, 2})
    assert paccet_select(EXAMPLE1, L1Target([0.45, 0.55])).best_index == 2


def test_example2_reference_blind_spot():
    eq = paccet_select(EXAMPLE2, options=VECTORS)
    np.testing.assert_allclose(eq.fitness, np.ones(5), atol=1e-12)
    res = paccet_select(EXAMPLE2, Weighted([0.4, 0.5]), VECTORS)
    np.testing.assert_allclose(
        res.fitness, [0.499993, 0.468269, 0.444904, 0.400019, 0.400014], atol=1e-5
    )
    assert res.best_index == 4  # P5 = (30, 0): only weakly dominated, yet it wins
    assert int(np.argmin(EXAMPLE2 @ [0.4, 0.5])) == 0  # raw weighted sum: 0.6 m from the person


def test_example2_remedy_ranks_weakly_dominated_below():
    res = paccet_select(EXAMPLE2, Weighted([0.4, 0.5]), PaccetOptions(delta_mode="absolute"))
    assert not res.nondominated[4]
    assert res.best_index == 3
    assert res.order()[-1] == 4


def test_single_point_and_identical_points():
    # parity: |x| = sqrt(2), v_B quantized to 1e-2 -> relative error up to 0.005 / sqrt(2)
    for options, atol in (
        (VECTORS, 1e-12),
        (PaccetOptions(), 1e-12),
        (PaccetOptions.reference(), 4e-3),
    ):
        one = paccet_select(np.array([[3.0, 4.0]]), options=options)
        np.testing.assert_allclose(one.transformed, [[0.5, 0.5]], atol=atol)
        np.testing.assert_allclose(one.fitness, [1.0], atol=2 * atol)
        three = paccet_select(np.array([[3.0, 4.0]] * 3), options=options)
        np.testing.assert_allclose(three.transformed, [[0.5, 0.5]] * 3, atol=atol)
        np.testing.assert_array_equal(three.nondominated, [True, False, False])
        assert three.best_index == 0


def test_archive_members_land_on_simplex_and_dominated_beyond():
    rng = np.random.default_rng(1)
    F = rng.random((200, 4))
    res = paccet_select(F)
    sums = res.transformed.sum(axis=1)
    np.testing.assert_allclose(sums[res.nondominated], 1.0, rtol=1e-12)
    assert np.all(sums[~res.nondominated] >= 1.0 - 1e-12)


# ---------------------------------------------------------------- degeneracy remedies
def test_constant_objective_is_dropped():
    # Nobody within 1.5 m: the ID cost (column 1) is 0 for every candidate. Row 2 is row 0
    # with a higher navigation cost.
    F = np.array([[10.0, 0.0, 5.0], [14.0, 0.0, 3.0], [30.0, 0.0, 5.0]])
    ref = paccet_select(F, options=VECTORS)
    np.testing.assert_allclose(ref.fitness, 1.0, rtol=1e-12)  # s* = 1 for all: no distinction
    w = Weighted([0.5, 0.5, 1.0])
    ref_w = paccet_select(F, w, VECTORS)
    assert ref_w.fitness[2] < ref_w.fitness[0]  # the higher navigation cost scores better
    drop = PaccetOptions(delta_mode="absolute", rank_weakly_dominated=False)
    res = paccet_select(F, options=drop)
    np.testing.assert_array_equal(res.kept_objectives, [True, False, True])
    np.testing.assert_array_equal(res.transformed[:, 1], 0.0)
    np.testing.assert_allclose(res.fitness[:2], 1.0, rtol=1e-12)
    assert res.fitness[2] > 4.0
    assert paccet_select(F, w, drop).fitness[2] > paccet_select(F, w, drop).fitness[0]


def test_constant_objective_reference_prefers_higher_cost_with_weights():
    # Degeneracy 1 with unequal weights: dropping the objective and ranking fix the choice.
    F = np.array([[10.0, 5.0, 0.0], [14.0, 3.0, 0.0], [20.0, 9.0, 0.0]])
    res = paccet_select(F, Weighted([1.0, 0.0, 1.0]))
    assert res.best_index in (0, 1) and res.nondominated[res.best_index]


def test_sentinel_capping_keeps_order_and_unsquashes():
    F = np.array([[1.0, 0.2], [2.0, 0.1], [1.5, 1e9], [0.5, 2e9]])
    (x, _, nadir) = normalize(F, F[[0, 1, 3]])
    assert nadir[1] < 1e3  # the sentinel no longer sets the nadir
    _, _, nadir_ref = normalize(F, F[[0, 1, 3]], VECTORS)
    assert nadir_ref[1] == 2e9
    # Both sentinel values are capped to the same, worst value of their objective.
    assert x[2, 1] == x[3, 1] > x[:2, 1].max()
    # Reference: the 1e9 values squash the regular ID costs to ~1e-10 in transformed space.
    T_ref = paccet_select(F, options=VECTORS).transformed
    assert np.all(T_ref[:2, 1] < 1e-6)
    T = paccet_select(F).transformed
    assert T[0, 1] > 0.1  # the regular ID cost of row 0 is visible again


def test_sentinel_only_column():
    F = np.array([[1.0, 1e9], [2.0, 1e9], [0.5, 1e9]])
    res = paccet_select(F)
    assert res.best_index == 2  # the archive is the single point (0.5, sentinel)
    assert np.all(np.isfinite(res.transformed))


def test_relative_delta_is_scale_invariant_absolute_is_not():
    F = EXAMPLE2.copy()
    G = F.copy()
    G[:, 1] *= 1e-4  # same objective in tiny units
    w = Weighted([0.4, 0.5])
    rel = PaccetOptions(rank_weakly_dominated=False)
    np.testing.assert_allclose(
        paccet_select(F, w, rel).transformed, paccet_select(G, w, rel).transformed, rtol=1e-9
    )
    a = paccet_select(F, w, VECTORS).transformed
    b = paccet_select(G, w, VECTORS).transformed
    assert np.max(np.abs(a - b)) > 1e-2


def test_point_beyond_utopia_maps_to_origin_in_closed_form():
    A = np.array([[1.0, 0.0], [0.0, 1.0]])
    T = paccet_transform(np.array([[-1.0, -1.0], [0.5, 0.5]]), A, VECTORS)
    np.testing.assert_array_equal(T[0], [0.0, 0.0])
    assert T[1].sum() < 1.0  # not dominated by the archive: inside the simplex
    Tp = paccet_transform(np.array([[-1.0, -1.0]]), A, PaccetOptions.reference())
    assert np.all(np.isfinite(Tp))


# ---------------------------------------------------------------- parity mode
def _closed(F, A, **kw):
    return paccet_transform(F, A, PaccetOptions(**{**VECTORS.__dict__, **kw}))


def _parity(F, A, vb_tol=1e-2, hp_tol=1e-4):
    opts = PaccetOptions(
        **{**VECTORS.__dict__, "method": "parity", "parity_vb_tol": vb_tol, "parity_hp_tol": hp_tol}
    )
    return paccet_transform(F, A, opts)


def test_reference_options():
    ref = PaccetOptions.reference()
    assert ref.method == "parity" and ref.delta_mode == "absolute" and ref.delta == 0.001
    assert not ref.drop_constant_objectives and not ref.rank_weakly_dominated
    assert ref.sentinel is None and ref.parity_vb_tol == 1e-2 and ref.parity_hp_tol == 1e-4
    assert PaccetOptions.reference(parity_vb_tol=1e-4).parity_vb_tol == 1e-4


def test_parity_quantizes_front_points_into_noisy_ties():
    # A concave front: closed form scores every member exactly 1; the v_B bisection
    # (tolerance 1e-2) leaves a per-point quantization error of up to tol/2 on |x|.
    theta = np.linspace(0.05, np.pi / 2 - 0.05, 25)
    A = np.column_stack([1.0 - np.cos(theta), 1.0 - np.sin(theta)])[::-1]
    A = A[np.argsort(A[:, 0])]
    closed = _closed(A, A).sum(axis=1)
    parity = _parity(A, A).sum(axis=1)
    np.testing.assert_allclose(closed, 1.0, rtol=1e-12)
    r = np.linalg.norm(
        (A - A.min(0) + 0.001) / (A.max(0) - A.min(0) + 0.001), axis=1
    )  # ray length of each member
    assert np.all(np.abs(parity - 1.0) <= 0.5e-2 / r * 1.01 + 1e-4)
    assert np.ptp(parity) > 1e-4  # no longer a tie: the bisection noise orders them
    # with the author's tighter tolerance the noise shrinks accordingly
    fine = _parity(A, A, vb_tol=1e-4).sum(axis=1)
    assert np.max(np.abs(fine - 1.0)) < np.max(np.abs(parity - 1.0))


def test_parity_clipping_reverses_far_dominated_points():
    A = np.array([[0.0, 1.0], [1.0, 0.0]])
    F = np.array([[0.001, 50.0], [5.0, 5.0]])  # far out along an axis vs. moderately far
    closed = _closed(F, A).sum(axis=1)
    parity = _parity(F, A).sum(axis=1)
    assert closed[0] < closed[1]  # true geometry: the first is closer to the front
    assert parity[0] > parity[1]  # its ray crossing lies beyond 2*sqrt(2)+0.1: clipped
    upper = 2 * math.sqrt(2) + 0.1
    x0 = (F[0] + 0.001) / 1.001
    np.testing.assert_allclose(parity[0], np.linalg.norm(x0) / upper, rtol=1e-2)


@pytest.mark.parametrize("m", [2, 3, 6])
def test_parity_agrees_with_closed_form_within_tolerance(m):
    rng = np.random.default_rng(m)
    F = rng.random((300, m))
    A = F[np.argsort(F.sum(axis=1))[:1]]
    from socialnav.moo.nondominated import nondominated_mask

    A = F[nondominated_mask(F)]
    for vb_tol in (1e-2, 1e-4):
        closed = _closed(F, A)
        parity = _parity(F, A, vb_tol=vb_tol)
        x = (F - A.min(0) + 0.001) / (A.max(0) - A.min(0) + 0.001)
        r = np.linalg.norm(x, axis=1)
        c_b = r / closed.sum(axis=1)  # ray distance of the crossing = |x| * s*
        upper = 2 * math.sqrt(m) + 0.1
        inside = c_b < upper - vb_tol
        rel = np.abs(parity - closed).max(axis=1) / np.abs(closed).max(axis=1)
        c_hp = r / x.sum(axis=1)
        bound = 0.5 * vb_tol / c_b + 0.5e-4 / c_hp
        assert inside.sum() > 0
        assert np.all(rel[inside] <= 1.05 * bound[inside] + 1e-12)
        # Clamping the crossing to the bracket end reproduces parity for every point.
        clamped = closed * (c_b / np.minimum(c_b, upper))[:, None]
        rel_all = np.abs(parity - clamped).max(axis=1) / np.abs(clamped).max(axis=1)
        assert np.all(rel_all <= 1.05 * (0.5 * vb_tol / np.minimum(c_b, upper) + 0.5e-4 / c_hp))


# ---------------------------------------------------------------- options and scalarizations
@pytest.mark.parametrize(
    "kwargs",
    [
        {"delta": 0.0},
        {"delta": -1.0},
        {"delta": float("nan")},
        {"parity_vb_tol": 0.0},
        {"parity_hp_tol": float("inf")},
        {"delta_mode": "log"},
        {"method": "bisect"},
        {"sentinel": float("inf")},
    ],
)
def test_bad_options_raise(kwargs):
    with pytest.raises(ValueError):
        PaccetOptions(**kwargs)


def test_options_are_frozen():
    with pytest.raises(AttributeError):
        PaccetOptions().delta = 1.0  # type: ignore[misc]


def test_scalarizations_shapes():
    T = np.array([[0.2, 0.8], [0.6, 0.6]])
    np.testing.assert_allclose(EqualWeight()(T), [1.0, 1.2])
    np.testing.assert_allclose(Weighted([1.0, 0.0])(T), [0.2, 0.6])
    np.testing.assert_allclose(L1Target([0.5, 0.5])(T), [0.6, 0.2])
    with pytest.raises(ValueError, match="2 weights for 3"):
        Weighted([1.0, 1.0])(np.ones((2, 3)))
    with pytest.raises(ValueError, match="target has 3"):
        L1Target([1.0, 1.0, 1.0])(T)
    for bad in ([], [np.nan, 1.0], [[1.0]]):
        with pytest.raises(ValueError):
            Weighted(bad)
        with pytest.raises(ValueError):
            L1Target(bad)


def test_select_with_wrong_weight_length_raises():
    with pytest.raises(ValueError):
        paccet_select(EXAMPLE1, Weighted([1.0, 1.0, 1.0]))


@pytest.mark.parametrize(
    "F, A",
    [
        (np.array([[1.0, np.nan]]), EXAMPLE1),
        (EXAMPLE1, np.zeros((0, 2))),
        (EXAMPLE1, np.ones((2, 3))),
        (np.ones(2), EXAMPLE1),
    ],
)
def test_transform_bad_input_raises(F, A):
    with pytest.raises(ValueError):
        paccet_transform(F, A)
    with pytest.raises(ValueError):
        normalize(F, A)


# ---------------------------------------------------------------- stateful object
def test_stateful_paccet_matches_stateless_and_persists():
    p = PaccetTransform(VECTORS)
    with pytest.raises(ValueError, match="tell"):
        p.transform(EXAMPLE1)
    p.tell(EXAMPLE1[:2])
    p.tell(EXAMPLE1[2:])
    assert len(p.archive) == 4
    np.testing.assert_allclose(
        p.transform(EXAMPLE1), paccet_select(EXAMPLE1, options=VECTORS).transformed
    )
    np.testing.assert_allclose(
        p.fitness(EXAMPLE1, L1Target([0.45, 0.55])),
        [1.098004, 0.242653, 0.042653, 0.898004, 0.124844],
        atol=1e-5,
    )
    # A new, better point joins and shifts the bounds on the next tell only.
    before = p.transform(np.array([[0.5, 0.5]]))
    assert before.sum() < 1.0
    p.tell(np.array([[0.5, 0.5]]))
    np.testing.assert_allclose(p.transform(np.array([[0.5, 0.5]])).sum(), 1.0)
    p.reset()
    assert len(p.archive) == 0


def test_stateful_order_ranks_weakly_dominated_last():
    p = PaccetTransform(PaccetOptions(delta_mode="absolute"))
    p.tell(EXAMPLE2)
    order = p.order(EXAMPLE2, Weighted([0.4, 0.5]))
    assert order[-1] == 4 and order[0] == 3
    np.testing.assert_array_equal(p.dominated_by_archive(EXAMPLE2), [0, 0, 0, 0, 1])
    p_ref = PaccetTransform(VECTORS)
    p_ref.tell(EXAMPLE2)
    assert p_ref.order(EXAMPLE2, Weighted([0.4, 0.5]))[0] == 4


def test_stateful_thinning_uses_seed():
    t = np.arange(40.0)
    F = np.column_stack([t, 39.0 - t])
    a, b = PaccetTransform(threshold=10, seed=1), PaccetTransform(threshold=10, seed=1)
    a.tell(F)
    b.tell(F)
    np.testing.assert_array_equal(a.archive.points, b.archive.points)
    assert len(a.archive) < 11


def test_two_objective_staircase_path_is_bit_identical_to_dense():
    from socialnav.moo.paccet import _s_star, _s_star_2d, _s_star_dense

    rng = np.random.default_rng(7)
    theta = rng.uniform(0, np.pi / 2, 300)
    F = np.column_stack([np.cos(theta), np.sin(theta)])
    F *= 1 + np.abs(rng.normal(0, 0.05, (300, 1)))
    F = np.vstack([F, [[-0.5, 2.0], [2.0, -0.5], [0.0, 0.0]]])  # beyond the utopia, x <= 0
    from socialnav.moo.nondominated import nondominated_mask

    nd = nondominated_mask(F[:300])
    A = F[:300][nd]
    x = (F - A.min(0) + 1e-3) / (A.max(0) - A.min(0) + 1e-3)
    S = (A - A.min(0) + 1e-3) / (A.max(0) - A.min(0) + 1e-3)
    inv = np.full_like(x, np.inf)
    np.divide(1.0, x, out=inv, where=x > 0)
    dense = _s_star_dense(inv, S)
    np.testing.assert_array_equal(_s_star_2d(inv, S), dense)
    # a caller-supplied archive with dominated rows and duplicates gives the same minimum
    S_dirty = np.vstack([S, S[:5], S[:5] + 0.1])
    np.testing.assert_array_equal(_s_star_2d(inv, S_dirty), dense)
    # members are skipped with s* = 1 exactly; the dense path (S * (1/x)) is within an ulp
    members = np.zeros(x.shape[0], dtype=bool)
    members[:300] = nd
    np.testing.assert_array_equal(_s_star(x, S, members)[members], 1.0)
    np.testing.assert_allclose(dense[members], 1.0, rtol=3e-16)
    assert np.all(np.isinf(dense[-3:-1]))

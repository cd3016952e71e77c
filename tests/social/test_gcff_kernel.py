"""The compiled GCFF solve gives the labels of the NumPy reference."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.core.compiled import AVAILABLE
from socialnav.social.perception import gcff_kernel
from socialnav.social.perception.fformations import (
    FFormationParams,
    _centre,
    _labels_reference,
    assignment_costs,
    gcff,
    kernel_params,
    merge_wide,
)

pytestmark = pytest.mark.skipif(not AVAILABLE, reason="numba not installed")


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(2, 12),
    st.sampled_from([0.0, np.radians(15.0), np.radians(40.0)]),
    st.floats(1.5, 6.0),
)
def test_compiled_solve_labels_equal_the_reference(seed, k, tolerance, extent):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(0.0, extent, (k, 2))
    yaw = rng.uniform(-np.pi, np.pi, k)
    p = FFormationParams(heading_tolerance=tolerance)
    expected = _labels_reference(pos, yaw, p)
    got = gcff_kernel.solve_component(pos, yaw, kernel_params(p), p.iterations)
    np.testing.assert_array_equal(got, expected)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 7))
def test_compiled_group_centre_and_costs_equal_the_reference(seed, k):
    rng = np.random.default_rng(seed)
    a = 2 * np.pi * np.arange(k) / k + rng.normal(0, 0.2, k)
    pos = 0.8 * np.column_stack([np.cos(a), np.sin(a)]) + rng.normal(0, 0.1, (k, 2))
    yaw = a + np.pi + rng.normal(0, 0.3, k)
    p = FFormationParams()
    center, costs = gcff_kernel.centre_and_costs(pos, yaw, kernel_params(p))
    expected = _centre(pos, yaw, p)
    np.testing.assert_allclose(center, expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(
        costs, assignment_costs(pos, yaw, expected[None], p)[:, 0], rtol=1e-9, atol=1e-9
    )


def test_a_circle_and_a_pair_facing_each_other_compiled():
    a = 2 * np.pi * np.arange(4) / 4
    circle = 0.8 * np.column_stack([np.cos(a), np.sin(a)])
    pos = np.vstack([circle, [(3.0, 0.0), (4.0, 0.0)]])
    yaw = np.concatenate([a + np.pi, [0.0, np.pi]])
    labels = gcff_kernel.solve_component(pos, yaw, kernel_params(FFormationParams()), 10)
    assert labels.tolist() == [0, 0, 0, 0, 1, 1]


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(3, 8), st.floats(0.6, 1.8))
def test_compiled_and_reference_paths_give_the_same_wide_circle_groups(seed, k, radius):
    # the merge step (merge_wide) runs after either solve
    rng = np.random.default_rng(seed)
    a = 2 * np.pi * np.arange(k) / k + rng.normal(0, 0.15, k)
    pos = radius * np.column_stack([np.cos(a), np.sin(a)]) + rng.normal(0, 0.05, (k, 2))
    yaw = a + np.pi + rng.normal(0, np.radians(10.0), k)
    previous = gcff_kernel.set_enabled(True)
    try:
        compiled = [g.tolist() for g in gcff(pos, yaw, FFormationParams())]
        gcff_kernel.set_enabled(False)
        reference = [g.tolist() for g in gcff(pos, yaw, FFormationParams())]
    finally:
        gcff_kernel.set_enabled(previous)
    assert compiled == reference


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(3, 12), st.floats(1.5, 6.0))
def test_compiled_merge_equals_the_reference_on_random_scenes(seed, k, extent):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(0.0, extent, (k, 2))
    yaw = rng.uniform(-np.pi, np.pi, k)
    p = FFormationParams(merge_facing=np.radians(60.0))  # loose: more merges to compare
    start = _labels_reference(pos, yaw, p)
    expected, strides = merge_wide(pos, yaw, start, p)
    got, fitted = gcff_kernel.merge_wide(pos, yaw, start, kernel_params(p))
    np.testing.assert_array_equal(got, expected)
    assert {u: float(d) for u, d in enumerate(fitted) if np.isfinite(d)} == pytest.approx(strides)


def test_set_enabled_switches_the_path_and_returns_the_previous_setting():
    previous = gcff_kernel.set_enabled(False)
    try:
        assert not gcff_kernel.enabled()
        assert gcff_kernel.set_enabled(True) is False
        assert gcff_kernel.enabled()
    finally:
        gcff_kernel.set_enabled(previous)

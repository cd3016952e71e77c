"""Bad estimator input gets a clear error (newcomer trial: a NaN or infinite time was accepted
and silently wiped every structure track, ``smoothing=0`` left a person who stopped walking at
1 m/s for ever, and an unknown detector parameter raised a bare ``TypeError``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from socialnav.core.errors import ConfigurationError, InvalidInputError
from socialnav.core.scene import Person
from socialnav.social.perception import ContextEstimator, EstimatorParams
from socialnav.social.perception.tracking import HysteresisParams, StructureTracker

PAIR = [Person(1, (0.0, 0.0), yaw=0.0), Person(2, (1.2, 0.0), yaw=math.pi)]


@pytest.mark.parametrize("time", [math.nan, math.inf, -math.inf, "1.0", None, True])
def test_a_time_that_is_not_a_finite_number_is_refused_and_changes_nothing(time):
    estimator = ContextEstimator()
    for k in range(6):
        before = estimator.update(0.1 * k, PAIR)
    assert [g.member_ids for g in before.context.groups] == [(1, 2)]
    with pytest.raises(InvalidInputError, match="time"):
        estimator.update(time, PAIR)  # type: ignore[arg-type]
    after = estimator.update(0.6, PAIR)  # the confirmed pair is still there: nothing was wiped
    assert [g.member_ids for g in after.context.groups] == [(1, 2)]
    assert estimator.update(np.float64(0.7), PAIR).time == pytest.approx(0.7)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("smoothing", 0.0),
        ("smoothing", -1.0),
        ("smoothing", 1.5),
        ("standing_smoothing", 0.0),
        ("gate", math.nan),
        ("gate", 0.0),
        ("standing_gate", -0.1),
        ("coast_time", -1.0),
        ("still_speed", math.nan),
        ("motion_z", -2.0),
    ],
)
def test_parameters_outside_their_range_are_refused_by_name(field, value):
    with pytest.raises(ConfigurationError, match=field):
        ContextEstimator(params=EstimatorParams(**{field: value}))


def test_the_documented_ranges_are_accepted():
    ContextEstimator(params=EstimatorParams(smoothing=1.0, coast_time=0.0, still_speed=0.0))


def test_an_unknown_detector_parameter_names_the_detector_and_the_known_ones():
    params = EstimatorParams(detector_params={"fformation": {"strid": 0.5}})
    with pytest.raises(ConfigurationError, match=r"FFormationDetector: unknown.*strid.*stride"):
        ContextEstimator(params=params)


@pytest.mark.parametrize(
    "hysteresis",
    [
        HysteresisParams(time_constant=math.nan),
        HysteresisParams(time_constant=-1.0),
        HysteresisParams(nominal_period=0.0),
        HysteresisParams(on=0.2, off=0.9),
        HysteresisParams(match_jaccard=0.0),
        None,
    ],
)
def test_hysteresis_out_of_range_is_refused(hysteresis):
    # second trial: a NaN time constant confirmed nothing, ever
    with pytest.raises(ConfigurationError, match="hysteresis"):
        ContextEstimator(params=EstimatorParams(hysteresis=hysteresis))  # type: ignore[arg-type]
    if hysteresis is not None:
        with pytest.raises(ConfigurationError, match="hysteresis"):
            StructureTracker(hysteresis)


@pytest.mark.parametrize(
    ("params", "match"),
    [
        ({"fformation": {"heading_tolerance": math.nan}}, "heading_tolerance must be a finite"),
        ({"fformation": {"mdl": 0.0}}, "mdl must be a finite number > 0"),
        ({"fformation": {"iterations": 0}}, "iterations"),
        ({"queue": {"spacing": -1.0}}, "spacing"),
        ({"walking_group": {"max_distance": math.inf}}, "max_distance"),
        ({"viewers": {"max_depth": -2.0}}, "max_depth"),
        ({"dominant_sets": {}}, "detector_params for dominant_sets, which the pipeline"),
        ({"nonexistent": {}}, "detector_params for nonexistent"),
    ],
)
def test_detector_parameters_are_checked_by_name(params, match):
    with pytest.raises(ConfigurationError, match=match):
        ContextEstimator(params=EstimatorParams(detector_params=params))


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("pipeline", "fformation", "sequence of detector names"),
        ("velocity_window", math.inf, "velocity_window"),
        ("velocity_min_samples", 2.5, "velocity_min_samples"),
        ("velocity_min_samples", 1, "velocity_min_samples"),
    ],
)
def test_estimator_shape_parameters_are_checked(field, value, match):
    with pytest.raises(ConfigurationError, match=match):
        ContextEstimator(params=EstimatorParams(**{field: value}))

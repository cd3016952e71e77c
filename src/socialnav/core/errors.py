"""Exception types: exceptions belong to configuration time; the hot path returns statuses."""

import dataclasses
import math
from collections.abc import Mapping
from numbers import Real
from typing import Any, TypeVar

import numpy as np

T = TypeVar("T")


class SocialNavError(Exception):
    """Base class of every error socialnav raises on purpose."""


class ConfigurationError(SocialNavError, ValueError):
    """A component, scenario or parameter set is malformed (raised at configuration time)."""


class InvalidInputError(SocialNavError, ValueError):
    """Numeric input is unusable: NaN, infinite, wrong shape or impossible geometry."""


def is_non_negative_number(value: object) -> bool:
    """Whether ``value`` is a finite real number >= 0 (any ``numbers.Real``, NumPy's included,
    not a ``bool`` or a string): the check of the planner's fractions, margins and loop
    parameters at configuration time."""
    if isinstance(value, bool) or not isinstance(value, Real):
        return False
    return math.isfinite(value) and float(value) >= 0


def checked_bool(value: object, name: str) -> bool:
    """``value`` as a Python ``bool`` when it is a bool (NumPy's included: stored as Python's, it
    serializes to JSON and declares as a ROS 2 bool parameter). Raises ``ConfigurationError``
    naming ``name`` for anything else (a truthy string such as ``"no"`` must not switch a
    feature on)."""
    if not isinstance(value, bool | np.bool_):
        raise ConfigurationError(f"{name} must be a bool, got {value!r}")
    return bool(value)


def with_overrides(base: T, overrides: T | Mapping[str, Any] | None, what: str) -> T:
    """``base`` (a dataclass instance) with the fields in mapping ``overrides`` replaced (the
    dataclass checks the values); an ``overrides`` of ``base``'s own type is returned as is,
    ``None`` gives ``base``. Raises ``ConfigurationError`` naming ``what`` for an unknown field
    or an ``overrides`` that is neither."""
    if overrides is None:
        return base
    if isinstance(overrides, type(base)):
        return overrides
    if not isinstance(overrides, Mapping):
        raise ConfigurationError(
            f"{what} parameters must be a {type(base).__name__} or a mapping of its fields,"
            f" got {type(overrides).__name__}"
        )
    known = {f.name for f in dataclasses.fields(base)}  # type: ignore[arg-type]
    unknown = sorted(set(overrides) - known)
    if unknown:
        raise ConfigurationError(
            f"unknown {what} parameter(s) {unknown}; known: {', '.join(sorted(known))}"
        )
    return dataclasses.replace(base, **overrides)  # type: ignore[type-var]

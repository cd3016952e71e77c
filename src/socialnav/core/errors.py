"""Exception types: exceptions belong to configuration time; the hot path returns statuses."""

import math


class SocialNavError(Exception):
    """Base class of every error socialnav raises on purpose."""


class ConfigurationError(SocialNavError, ValueError):
    """A component, scenario or parameter set is malformed (raised at configuration time)."""


class InvalidInputError(SocialNavError, ValueError):
    """Numeric input is unusable: NaN, infinite, wrong shape or impossible geometry."""


def is_non_negative_number(value: object) -> bool:
    """Whether ``value`` is a finite real number >= 0 (an ``int`` or ``float``, not a ``bool``
    or a string): the check of the planner's fractions and margins at configuration time."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    return math.isfinite(value) and value >= 0

"""Exception types: exceptions belong to configuration time; the hot path returns statuses."""


class SocialNavError(Exception):
    """Base class of every error socialnav raises on purpose."""


class ConfigurationError(SocialNavError, ValueError):
    """A component, scenario or parameter set is malformed (raised at configuration time)."""


class InvalidInputError(SocialNavError, ValueError):
    """Numeric input is unusable: NaN, infinite, wrong shape or impossible geometry."""

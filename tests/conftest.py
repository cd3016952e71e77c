"""Property tests draw their examples deterministically, so a run is reproducible and CI
cannot fail on a draw that the developer never saw (hypothesis' derandomize profile)."""

from hypothesis import settings

settings.register_profile("deterministic", derandomize=True, deadline=None)
settings.load_profile("deterministic")

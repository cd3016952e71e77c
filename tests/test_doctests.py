"""The docstring examples of the pure-geometry functions are tests."""

from __future__ import annotations

import doctest

import pytest

import socialnav.core.geometry
import socialnav.social.proxemics
import socialnav.social.spaces

MODULES = [socialnav.core.geometry, socialnav.social.spaces, socialnav.social.proxemics]


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__)
def test_docstring_examples(module) -> None:
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0
    if module is socialnav.core.geometry:
        assert result.attempted >= 8

"""One registry mechanism for every pluggable kind (critics, planners, metrics, scenarios).

Unknown names raise a :class:`ConfigurationError` listing the known names and a "did you mean".
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterator
from typing import Generic, TypeVar

from socialnav.core.errors import ConfigurationError

T = TypeVar("T")


class Registry(Generic[T]):
    """A name → object map for one kind of component."""

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self._items: dict[str, T] = {}

    def register(self, name: str) -> Callable[[T], T]:
        """Decorator: ``@REGISTRY.register("name")`` on a class or factory."""

        def decorate(obj: T) -> T:
            self.add(name, obj)
            return obj

        return decorate

    def add(self, name: str, obj: T) -> None:
        """Register ``obj`` as ``name``; ``ConfigurationError`` if another object has it."""
        if name in self._items and self._items[name] is not obj:
            raise ConfigurationError(f"{self.kind} {name!r} is already registered")
        self._items[name] = obj

    def get(self, name: str) -> T:
        """The object registered as ``name``; ``ConfigurationError`` listing the known names."""
        try:
            return self._items[name]
        except KeyError:
            raise ConfigurationError(self.unknown_message(name)) from None

    def unknown_message(self, name: str) -> str:
        """The error text for an unknown ``name``: a "did you mean" and the known names."""
        known = ", ".join(sorted(self._items)) or "none"
        close = difflib.get_close_matches(name, self._items, n=1)
        hint = f" Did you mean {close[0]!r}?" if close else ""
        return f"unknown {self.kind} {name!r}.{hint} Known: {known}."

    def names(self) -> list[str]:
        """Every registered name, sorted."""
        return sorted(self._items)

    def __contains__(self, name: object) -> bool:
        return name in self._items

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __len__(self) -> int:
        return len(self._items)

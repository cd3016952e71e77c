"""Groups, queues and artworks from a file, attached to the people the tracker sees.

Trackers give anonymous people; the social structure (who talks with whom, who waits in line,
who looks at which artwork) comes from a context file named by the node's
``social_context_file`` parameter until an estimator provides it. Each structure names its
members by where they stand; every cycle each member position is matched to a distinct tracked
person within ``match_radius`` m (the cheapest one-to-one assignment, as the tracker's
association). A group or queue is in the cycle's :class:`SocialContext` only when all its
members are matched (a group needs two); an artwork is always there, with the viewers found.

The file (YAML, metres and radians in the node's global frame)::

    groups:
      - members: [[3.0, 1.0], [3.8, 1.2], [3.4, 1.8]]
        mode: join                 # or lead
    queues:
      - members: [[5.0, 0.0], [5.0, -0.8]]   # from the person being served to the last
        service_point: [5.0, 0.8]
        spacing: 0.8
    artworks:
      - center: [13.0, 25.0]
        width: 1.2
        facing: -1.5708           # yaw of its normal into the room
        viewers: [[13.0, 23.5]]

No ROS imports (tested in the main environment). Errors name the file and the field.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import linear_sum_assignment

from socialnav.core.errors import ConfigurationError, SocialNavError
from socialnav.core.geometry import FloatArray
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.integrations.ros2.params import read_yaml_file

__all__ = ["ContextFile", "load_context_file"]

MAX_CONTEXT_FILE_BYTES = 1_000_000


@dataclass(frozen=True)
class _Structure:
    kind: str  # "group", "queue" or "artwork"
    members: FloatArray  # (M, 2) expected member positions
    fields: dict[str, Any]


def _points(value: Any, where: str, minimum: int) -> FloatArray:
    try:
        arr = np.asarray(value, dtype=float).reshape(-1, 2)
    except (TypeError, ValueError):
        raise ConfigurationError(f"{where}: expected a list of [x, y] points") from None
    if arr.shape[0] < minimum or not np.all(np.isfinite(arr)):
        raise ConfigurationError(f"{where}: needs at least {minimum} finite [x, y] points")
    return arr


def _xy(value: Any, where: str) -> tuple[float, float]:
    return tuple(_points(value, where, 1)[0].tolist())


@dataclass(frozen=True)
class ContextFile:
    """The structures of one context file; :meth:`resolve` attaches them to people."""

    structures: tuple[_Structure, ...]
    match_radius: float = 0.75

    def resolve(self, people: tuple[Person, ...]) -> SocialContext:
        """The :class:`SocialContext` of ``people`` with every structure whose members are
        all matched (see the module docstring); never raises on well-typed people."""
        xy = np.array([p.position for p in people], dtype=float).reshape(-1, 2)
        ids = [p.id for p in people]
        groups, queues, artworks = [], [], []
        for s in self.structures:
            matched = self._match(s.members, xy, ids)
            try:
                if s.kind == "group" and len(matched) == len(s.members) >= 2:
                    groups.append(Group(tuple(matched), mode=s.fields.get("mode", "join")))
                elif s.kind == "queue" and len(matched) == len(s.members):
                    queues.append(Queue(tuple(matched), **s.fields))
                elif s.kind == "artwork":
                    artworks.append(Artwork(viewer_ids=tuple(matched), **s.fields))
            except SocialNavError:
                continue  # validated at load; a structure that no longer fits is left out
        return SocialContext(people, tuple(groups), tuple(queues), tuple(artworks))

    def _match(self, members: FloatArray, xy: FloatArray, ids: list[int]) -> list[int]:
        if members.shape[0] == 0 or xy.shape[0] == 0:
            return []
        cost = np.hypot(*(members[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))
        rows, cols = linear_sum_assignment(np.where(cost <= self.match_radius, cost, 1e6))
        pairs = sorted(
            (int(r), ids[int(c)])
            for r, c in zip(rows, cols, strict=True)
            if cost[r, c] <= self.match_radius
        )
        return [pid for _, pid in pairs]


def load_context_file(path: str | Path, match_radius: float = 0.75) -> ContextFile:
    """Read and validate a context file; :class:`ConfigurationError` names file and field."""
    path = Path(path)
    where = str(path)
    doc = read_yaml_file(path, "context file", MAX_CONTEXT_FILE_BYTES) or {}
    if not isinstance(doc, dict):
        raise ConfigurationError(f"{where}: expected a mapping with groups, queues, artworks")
    unknown = set(doc) - {"groups", "queues", "artworks"}
    if unknown:
        raise ConfigurationError(f"{where}: unknown keys {sorted(unknown)}")
    out: list[_Structure] = []
    for kind, key in (("group", "groups"), ("queue", "queues"), ("artwork", "artworks")):
        items = doc.get(key) or []
        if not isinstance(items, list):
            raise ConfigurationError(f"{where}: {key}: expected a list")
        for i, item in enumerate(items):
            at = f"{where}: {key}[{i}]"
            if not isinstance(item, dict):
                raise ConfigurationError(f"{at}: expected a mapping")
            try:
                out.append(_structure(kind, item, at))
            except (SocialNavError, TypeError, ValueError) as exc:
                text = str(exc)
                raise ConfigurationError(text if text.startswith(at) else f"{at}: {text}") from None
    return ContextFile(tuple(out), float(match_radius))


def _structure(kind: str, item: dict[str, Any], at: str) -> _Structure:
    if kind == "group":
        mode = item.get("mode", "join")
        Group((0, 1), mode=mode)  # validates the mode
        return _Structure(kind, _points(item.get("members"), f"{at}.members", 2), {"mode": mode})
    if kind == "queue":
        fields: dict[str, Any] = {
            "service_point": _xy(item.get("service_point"), f"{at}.service_point")
        }
        if "spacing" in item:
            fields["spacing"] = float(item["spacing"])
        Queue((0,), **fields)  # validates the numbers
        return _Structure(kind, _points(item.get("members"), f"{at}.members", 1), fields)
    art: dict[str, Any] = {
        "center": _xy(item.get("center"), f"{at}.center"),
        "width": float(item.get("width", 0.0)),
        "facing": float(item.get("facing", 0.0)),
    }
    Artwork(**art)  # validates width and finiteness
    viewers = item.get("viewers") or []
    members = _points(viewers, f"{at}.viewers", 0) if viewers else np.zeros((0, 2))
    return _Structure(kind, members, art)

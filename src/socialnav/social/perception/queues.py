"""Queues: standing people in a line, each facing the one ahead, ordered head → tail.

Method: a queue is a chain in the "stands behind" graph. Person ``i`` stands behind ``j`` when
``j`` is ``min_spacing``–``max_spacing`` m away within ``max_bearing`` of ``i``'s heading, ``j``
faces away from ``i`` (the direction ``i → j`` within ``max_bearing`` of ``j``'s heading) and
both face roughly the same way (``max_relative_yaw``). The spacing range brackets Hall's
personal distance (0.45–1.2 m, "The Hidden Dimension", 1966) and the 0.6–1.1 m spacings of the
project's queue scenarios; the angular limits admit the 15° heading noise and 0.1 m position
noise of the benchmark (about 3 σ of the combined bearing error). A chain whose headings are
not coherent (mean resultant length below ``min_heading_coherence``) curls around a centre and
is left to the F-formation detector. These are this module's own choices, tuned on generated
queues of development seeds and reported on other seeds (``benchmarks/bench_context.py``), not
taken from a paper. Each person gets at most one
successor and one predecessor: edges are taken cheapest first (cost = bearing / max_bearing +
|gap − spacing| / spacing), refusing cycles (a greedy matching with union–find).

The head: with service points from the map (a desk or counter), a chain whose front person is
within ``service_reach`` of one and faces it is a queue served there, and a single person there
is a queue of one. Without a map, the head is the front of the chain (people face it) and the
service point is placed ``spacing`` ahead of the head along its heading; chains of two are
accepted but scored lower, since two people one behind the other may just be standing there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from socialnav.core.geometry import FloatArray, wrap_angle
from socialnav.social.perception.base import (
    DETECTORS,
    STANDING_SPEED,
    Candidate,
    MapKnowledge,
    ParamDetector,
    TrackFrame,
    unclaimed,
)


@dataclass(frozen=True)
class QueueParams:
    """Queue cues (module docstring); metres and radians."""

    min_spacing: float = 0.35
    max_spacing: float = 1.6
    spacing: float = 0.8
    max_bearing: float = np.radians(60.0)
    max_relative_yaw: float = np.radians(75.0)
    min_heading_coherence: float = 0.85
    service_reach: float = 1.6
    service_bearing: float = np.radians(60.0)
    min_members_without_map: int = 2
    standing_speed: float = STANDING_SPEED
    only_at_desk: bool = False


def behind_edges(pos: FloatArray, yaw: FloatArray, p: QueueParams) -> list[tuple[float, int, int]]:
    """``(cost, i, j)`` for every ``i`` that could stand right behind ``j``, cheapest first."""
    d = pos[None, :, :] - pos[:, None, :]  # i -> j
    dist = np.hypot(d[..., 0], d[..., 1])
    direction = np.arctan2(d[..., 1], d[..., 0])
    bearing = np.abs(wrap_angle(direction - yaw[:, None]))
    # j looks the same way, away from i (people around a circle look across it instead)
    away = np.abs(wrap_angle(direction - yaw[None, :]))
    rel_yaw = np.abs(wrap_angle(yaw[:, None] - yaw[None, :]))
    ok = (
        (dist >= p.min_spacing)
        & (dist <= p.max_spacing)
        & (bearing <= p.max_bearing)
        & (away <= p.max_bearing)
        & (rel_yaw <= p.max_relative_yaw)
    )
    np.fill_diagonal(ok, False)
    cost = bearing / p.max_bearing + np.abs(dist - p.spacing) / p.spacing
    ii, jj = np.nonzero(ok)
    return sorted(zip(cost[ii, jj].tolist(), ii.tolist(), jj.tolist(), strict=True))


def heading_coherence(yaw: FloatArray) -> float:
    """Mean resultant length of headings ``(K,)`` in [0, 1] (1: all alike; Mardia & Jupp,
    "Directional Statistics", 2000, §2.3)."""
    return float(np.hypot(np.cos(yaw).mean(), np.sin(yaw).mean()))


def chains(n: int, edges: list[tuple[float, int, int]]) -> list[list[int]]:
    """Chains (front first) of a greedy one-successor/one-predecessor matching of ``edges``."""
    succ = np.full(n, -1)
    pred = np.full(n, -1)
    root = list(range(n))

    def find(a: int) -> int:
        while root[a] != a:
            root[a] = root[root[a]]
            a = root[a]
        return a

    for _, i, j in edges:
        if succ[i] >= 0 or pred[j] >= 0 or find(i) == find(j):
            continue
        succ[i], pred[j] = j, i
        root[find(i)] = find(j)
    out = []
    for front in np.flatnonzero(succ < 0):  # nobody ahead: the front of a chain
        chain = [int(front)]
        while pred[chain[-1]] >= 0:
            chain.append(int(pred[chain[-1]]))
        out.append(chain)
    return out


class QueueDetector(ParamDetector[QueueParams]):
    """Registered as ``queue``."""

    params_type = QueueParams
    positive = frozenset({"max_spacing", "spacing"})

    def __call__(
        self, frame: TrackFrame, knowledge: MapKnowledge, claimed: frozenset[int]
    ) -> list[Candidate]:
        """Candidates of one frame (see :data:`~socialnav.social.perception.base.Detector`)."""
        p = self.params
        idx = unclaimed(frame, claimed, frame.standing(p.standing_speed))
        pos, yaw = frame.positions[idx], frame.yaws[idx]
        service = knowledge.service_points
        out: list[Candidate] = []
        # who stands within reach of a desk: only they can be a queue of one
        if service.shape[0]:
            gap = pos[:, None, :] - service[None, :, :]
            near = (np.hypot(gap[..., 0], gap[..., 1]) <= p.service_reach).any(axis=1)
        else:
            near = np.zeros(idx.size, dtype=bool)
        for chain in chains(idx.size, behind_edges(pos, yaw, p)):
            if len(chain) < max(2, p.min_members_without_map) and not near[chain[0]]:
                continue  # too short for a queue without a desk, and no desk in reach
            if len(chain) > 1 and heading_coherence(yaw[chain]) < p.min_heading_coherence:
                continue  # headings that turn around a centre: a conversation, not a line
            head = pos[chain[0]]
            served = None
            if service.shape[0]:
                to_desk = service - head
                dist = np.hypot(to_desk[:, 0], to_desk[:, 1])
                s = int(np.argmin(dist))
                facing = abs(
                    float(wrap_angle(np.arctan2(to_desk[s, 1], to_desk[s, 0]) - yaw[chain[0]]))
                )
                if dist[s] <= p.service_reach and facing <= p.service_bearing:
                    served = service[s]
            if served is None and (
                p.only_at_desk or len(chain) < max(2, p.min_members_without_map)
            ):
                continue
            if served is None:
                heading = np.array([np.cos(yaw[chain[0]]), np.sin(yaw[chain[0]])])
                service_point = head + p.spacing * heading
                score = 1.0 - 0.5 / (len(chain) - 0.5)  # 2 members: 0.67, 8: 0.93
            else:
                service_point = np.asarray(served, dtype=float)
                score = 1.0
            gaps = np.linalg.norm(np.diff(pos[chain], axis=0), axis=1)
            out.append(
                Candidate(
                    "queue",
                    tuple(int(frame.ids[idx[c]]) for c in chain),
                    float(score),
                    anchor=(float(service_point[0]), float(service_point[1])),
                    geometry={
                        "spacing": float(gaps.mean()) if gaps.size else p.spacing,
                        "from_map": served is not None,
                    },
                )
            )
        return out


class DeskQueueDetector(QueueDetector):
    """Registered as ``desk_queue``: only queues whose head is served by a desk of the map.
    It runs before the artwork viewers so that a desk's queue is a queue, while a line of
    people without a desk facing an artwork is its viewers (the later ``queue`` entry)."""

    def __init__(self, params: QueueParams | None = None, **overrides: Any) -> None:
        super().__init__(params, **{"only_at_desk": True, **overrides})


DETECTORS.add("queue", QueueDetector)
DETECTORS.add("desk_queue", DeskQueueDetector)

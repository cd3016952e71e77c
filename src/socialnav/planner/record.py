"""The per-cycle evaluation record (Nav2 DWB's ``LocalPlanEvaluation``, as typed data).

Recorded only when asked (``LocalPlanner.plan(ctx, record=True)``): it holds every candidate.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from socialnav.core.geometry import FloatArray


@dataclass(frozen=True)
class EvaluationRecord:
    """One control cycle.

    - ``time`` (s), ``pose (3,)``, ``velocity (3,)``, ``goal (3,)``, ``status`` (planner status
      name), ``message``.
    - ``twists (N, 3)`` sampled body twists; ``end_poses (N, 3)`` rollout end poses.
    - ``F (N, m)`` objective matrix (``+inf`` rows illegal), ``objective_names (m,)``,
      ``legal (N,)``, ``raw`` critic key → ``(N,)`` raw cost.
    - ``rejected`` ``(critic, reason)`` → count (a trajectory may be counted by several critics).
    - ``fitness (N,)`` the selection's fitness (``+inf`` illegal), ``chosen`` row or ``None``,
      ``selection`` the strategy's details.
    - ``timing`` seconds per stage (``sample``, ``rollout``, ``prepare:<critic>``,
      ``score:<critic>``, ``select``, ``total``).
    """

    time: float
    pose: FloatArray
    velocity: FloatArray
    goal: FloatArray
    status: str
    message: str = ""
    twists: FloatArray = field(default_factory=lambda: np.zeros((0, 3)))
    end_poses: FloatArray = field(default_factory=lambda: np.zeros((0, 3)))
    F: FloatArray = field(default_factory=lambda: np.zeros((0, 0)))
    objective_names: tuple[str, ...] = ()
    legal: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    raw: dict[str, FloatArray] = field(default_factory=dict)
    rejected: dict[tuple[str, str], int] = field(default_factory=dict)
    fitness: FloatArray | None = None
    chosen: int | None = None
    selection: dict[str, Any] = field(default_factory=dict)
    timing: dict[str, float] = field(default_factory=dict)

    @property
    def num_samples(self) -> int:
        """Number of candidates ``N``."""
        return int(self.twists.shape[0])

    @property
    def num_legal(self) -> int:
        """Number of legal candidates."""
        return int(np.count_nonzero(self.legal))

    def rejection_summary(self) -> str:
        """One line, DWB style: ``"12/330 legal; occupancy/collision: 300, ..."``."""
        parts = [f"{c}/{r}: {k}" for (c, r), k in sorted(self.rejected.items()) if k]
        head = f"{self.num_legal}/{self.num_samples} legal"
        return head + ("; " + ", ".join(parts) if parts else "")

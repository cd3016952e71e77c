"""Objectives: weighted critic terms → the objective matrix ``F (N, m)``.

Banisetty et al.: the traditional cost ``α Δ_path + β Δ_goal + γ Δ_heading + δ Δ_occ`` is one
objective; each social feature (ID, GD, SGD) is another; PaCcET (or a weighted sum) selects.

Decisions: weights live here (``Objective.terms``), never inside critics. Each distinct critic
(frozen dataclasses compare by value) is prepared and scored once per cycle even when several
objectives use it. A trajectory is legal only if no critic marks it illegal; ``F`` rows of illegal
trajectories are ``+inf`` (their raw costs may be ``inf`` too).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TypeVar, cast

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.trajectories import Trajectories
from socialnav.moo.selection import PaccetSelection
from socialnav.planner.cache import CycleCache
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.base import Critic

S = TypeVar("S")


@dataclass(frozen=True)
class Objective:
    """One objective: ``F[:, j] = Σ scale · critic.cost`` over ``terms``.

    ``indifference`` (the objective's raw units, finite, >= 0; 0 = off): the floor of this
    objective's normalizing range in a PaCcET selection (``PaccetOptions.indifference``).
    :class:`~socialnav.planner.local_planner.LocalPlanner` and the presets hand the objectives'
    thresholds to a :class:`~socialnav.moo.selection.PaccetSelection` that has none
    (:func:`with_indifference`); weighted sums ignore them.
    """

    name: str
    terms: tuple[tuple[Critic, float], ...]
    indifference: float = 0.0

    def __post_init__(self) -> None:
        if not self.name:
            raise ConfigurationError("objective name must be non-empty")
        if not self.terms:
            raise ConfigurationError(f"objective {self.name!r} has no terms")
        q = self.indifference
        if not (isinstance(q, (int, float)) and np.isfinite(q) and q >= 0):
            raise ConfigurationError(
                f"objective {self.name!r}: indifference must be a finite number >= 0, got {q!r}"
            )
        for critic, scale in self.terms:
            if not isinstance(critic, Critic):
                raise ConfigurationError(f"objective {self.name!r}: {critic!r} is not a Critic")
            if not (np.isfinite(scale) and scale >= 0):
                raise ConfigurationError(
                    f"objective {self.name!r}: scale for {critic.name} must be finite and >= 0"
                )


@dataclass(frozen=True)
class Evaluation:
    """``F (N, m)``, ``legal (N,)``, ``raw`` critic key → ``(N,)`` raw cost, ``rejected``
    ``(critic key, reason)`` → count, ``names`` the objective names, ``timing`` seconds per
    ``prepare:<key>`` / ``score:<key>``."""

    F: FloatArray
    legal: np.ndarray
    raw: dict[str, FloatArray]
    rejected: dict[tuple[str, str], int]
    names: tuple[str, ...]
    timing: dict[str, float] = field(default_factory=dict)


def with_indifference(selection: S, objectives: Sequence[Objective]) -> S:
    """``selection`` with the objectives' ``indifference`` thresholds when it is a
    :class:`~socialnav.moo.selection.PaccetSelection` without thresholds of its own and some
    objective has one; otherwise ``selection`` itself. Raises ``ConfigurationError`` when the
    selection's own thresholds are not one per objective (checked here, when a planner is
    built, so that ``plan`` never raises on them)."""
    if not isinstance(selection, PaccetSelection):
        return selection
    own = selection.options.indifference
    if own is not None:
        if len(own) != len(objectives):
            raise ConfigurationError(
                f"the PaCcET selection has {len(own)} indifference thresholds for "
                f"{len(objectives)} objectives ({', '.join(o.name for o in objectives)})"
            )
        return selection
    q = [o.indifference for o in objectives]
    return cast(S, selection.with_indifference(q)) if any(q) else selection


def critic_keys(objectives: Sequence[Objective]) -> dict[Critic, str]:
    """Distinct critics in order of first use → their key (the registry name, suffixed ``#2``…
    when differently-parameterized critics of one kind are used)."""
    keys: dict[Critic, str] = {}
    used: dict[str, int] = {}
    for obj in objectives:
        for critic, _ in obj.terms:
            if critic in keys:
                continue
            count = used.get(critic.name, 0) + 1
            used[critic.name] = count
            keys[critic] = critic.name if count == 1 else f"{critic.name}#{count}"
    return keys


class PreparedReuse:
    """The last ``size`` cycles' prepared map grids (BFS grids, occupancy masks, densified plan),
    handed to a later cycle whose inputs are identical byte for byte — the critics, the
    costmap's costs and geometry, the robot's footprint, pose, goal, plan, the planner's reach
    and which kernel path is active — so the values are exactly those a fresh preparation would
    give (a robot waiting in a static window pays for its grids once)."""

    def __init__(self, size: int = 4) -> None:
        self.size = size
        self._entries: list[tuple[tuple[object, ...], CycleCache]] = []  # newest last

    @staticmethod
    def key(ctx: PlanningContext, critics: tuple[Critic, ...]) -> tuple[object, ...]:
        """Everything the reusable entries depend on, as an exactly comparable tuple."""
        from socialnav.planner import kernels

        geom = ctx.costmap.geometry
        return (
            critics,  # frozen dataclasses: equal when their parameters are
            ctx.costmap.costs.tobytes(),
            tuple(geom.shape),
            float(geom.resolution),
            tuple(map(float, geom.origin)),
            np.asarray(ctx.robot.polygon, dtype=float).tobytes(),
            float(ctx.robot.inscribed_radius),
            np.asarray(ctx.pose, dtype=float).tobytes(),
            np.asarray(ctx.goal, dtype=float).tobytes(),
            np.asarray(ctx.global_path, dtype=float).tobytes(),
            ctx.cache.reach,
            kernels.enabled(),
        )

    def restore(self, ctx: PlanningContext, critics: tuple[Critic, ...]) -> tuple[object, ...]:
        """Fill ``ctx.cache`` from an entry with this cycle's key (if any); returns the key."""
        key = self.key(ctx, critics)
        for k, (entry_key, data) in enumerate(self._entries):
            if entry_key == key:
                ctx.cache.fill(data)
                self._entries.append(self._entries.pop(k))
                break
        return key

    def keep(self, key: tuple[object, ...], ctx: PlanningContext) -> None:
        """Remember this cycle's reusable ``ctx.cache`` fields
        (:data:`~socialnav.planner.cache.REUSABLE`) under ``key``."""
        if self.size <= 0:  # reuse switched off
            return
        data = ctx.cache.reusable()
        self._entries = [e for e in self._entries if e[0] != key][-(self.size - 1) :]
        self._entries.append((key, data))


_REUSE = PreparedReuse()


def prepare(
    objectives: Sequence[Objective], ctx: PlanningContext, timing: dict[str, float] | None = None
) -> None:
    """Run every distinct critic's ``prepare`` once (after restoring the previous cycle's
    prepared grids when their inputs are identical, :class:`PreparedReuse`); propagates
    ``CriticUnavailable``."""
    keys = critic_keys(objectives)
    key = _REUSE.restore(ctx, tuple(keys))
    for critic, name in keys.items():
        start = time.perf_counter()
        critic.prepare(ctx)
        if timing is not None:
            timing[f"prepare:{name}"] = time.perf_counter() - start
    _REUSE.keep(key, ctx)


#: Illegal reasons that yield when nothing else is left: if no trajectory is legal under them,
#: the cycle keeps the trajectories legal under the other reasons (``("objectives",
#: "soft_relaxed")`` counts them). Overlap with a person who walks into the robot whatever it
#: does is unavoidable; moving toward them (``person_approach``) is not, and stays hard.
SOFT_REASONS = frozenset({"person_collision"})
#: Illegal reasons relaxed first: if no trajectory left after the hard and soft reasons is
#: legal under them, the cycle keeps those trajectories (``("objectives",
#: "preferred_relaxed")`` counts them). Keeping someone's personal space is a preference the
#: robot gives up before it gives up avoiding contact. As for soft reasons, a critic's count
#: under ``rejected`` is how many it marked, kept or not.
PREFERRED_REASONS = frozenset({"personal_space"})


def evaluate(
    objectives: Sequence[Objective],
    trajs: Trajectories,
    ctx: PlanningContext,
) -> Evaluation:
    """Score ``trajs`` with every objective. Calls :func:`prepare` first (critics make it
    idempotent within a cycle). A trajectory is legal when no critic marks it for a hard
    reason; then, tier by tier, for a :data:`SOFT_REASONS` and a :data:`PREFERRED_REASONS`
    reason, each tier given up when it would leave no legal trajectory. May raise
    ``CriticUnavailable``."""
    timing: dict[str, float] = {}
    prepare(objectives, ctx, timing)
    n = len(trajs)
    keys = critic_keys(objectives)
    raw: dict[str, FloatArray] = {}
    rejected: dict[tuple[str, str], int] = {}
    legal = np.ones(n, dtype=bool)
    soft = np.ones(n, dtype=bool)
    preferred = np.ones(n, dtype=bool)
    for critic, key in keys.items():
        start = time.perf_counter()
        result = critic.score(trajs, ctx)
        timing[f"score:{key}"] = time.perf_counter() - start
        raw[key] = np.asarray(result.cost, dtype=float)
        for reason, mask in result.illegal.items():
            rejected[(key, reason)] = int(np.count_nonzero(mask))
            if reason in PREFERRED_REASONS:
                preferred &= ~np.asarray(mask, dtype=bool)
            elif reason in SOFT_REASONS:
                soft &= ~np.asarray(mask, dtype=bool)
            else:
                legal &= ~np.asarray(mask, dtype=bool)
    if (legal & soft).any():
        legal &= soft
    elif legal.any():
        rejected[("objectives", "soft_relaxed")] = int(np.count_nonzero(legal))
    if (legal & preferred).any():
        legal &= preferred
    elif legal.any():
        rejected[("objectives", "preferred_relaxed")] = int(np.count_nonzero(legal))
    # Critics promise finite costs on legal rows; a non-finite one is treated as illegal.
    F = np.zeros((n, len(objectives)))
    for j, obj in enumerate(objectives):
        for critic, scale in obj.terms:
            if scale != 0.0:
                F[:, j] += scale * np.where(legal, raw[keys[critic]], 0.0)
    bad = legal & ~np.isfinite(F).all(axis=1)
    if bad.any():
        rejected[("objectives", "non_finite")] = int(np.count_nonzero(bad))
        legal &= ~bad
    F[~legal] = np.inf
    return Evaluation(F, legal, raw, rejected, tuple(o.name for o in objectives), timing)

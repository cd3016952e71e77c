"""Group-distance critic: the paper's GD objective.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach",
eq. (Group Distance): ``GD_f = exp(1 / GD)`` "whenever [the robot] is close to a group".

Deviations and choices (the paper does not define GD or "close"):
- ``GD`` = distance from the trajectory point to the boundary of the group's o-space disc
  (fitted circle radius ``R − 0.3`` m, :func:`socialnav.social.spaces.o_space`) from the members'
  current positions (groups stand still); inside the disc the cost is the cap
  ``exp(1/min_distance)``.
- "Close" = ``GD <= influence_range`` (default 0.25 m): the join spot on the group circle lies
  0.3 m outside the o-space, so joining a group is not penalised while cutting through it is.
- Groups whose o-space has radius 0 (one member, a very tight pair) are ignored: the
  interpersonal critic already covers individuals.
- ``evaluation="last"`` (paper: end point) or ``"max_over_time"`` (every rollout point);
  several groups → maximum. ``illegal_inside=True`` declares trajectories whose centre enters any
  o-space at any time illegal (reason ``ospace_intrusion``) — except in an o-space the robot is
  already inside (a group formed around it, or it was pushed in), where only a trajectory that
  gets nearer its centre than now is: without that every trajectory was illegal and the robot
  waited inside until the group left (as the interpersonal critic's escape from overlap).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, ClassVar, Literal

import numpy as np

from socialnav.core.errors import ConfigurationError
from socialnav.core.geometry import FloatArray
from socialnav.core.scene import SocialContext
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
from socialnav.planner.critics.base import CRITICS, ESCAPE_TOLERANCE, Critic, CriticScore
from socialnav.planner.critics.interpersonal import capped_inverse_exp
from socialnav.social.spaces import OSPACE_MARGIN, o_space

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


def group_ospaces(
    social: SocialContext, margin: float = OSPACE_MARGIN
) -> tuple[FloatArray, FloatArray]:
    """Centres ``(G, 2)`` and radii ``(G,)`` of the non-empty o-spaces of ``social.groups``."""
    centers, radii = [], []
    for group in social.groups:
        if not group.member_ids:
            continue
        positions = np.ascontiguousarray(social.positions(group.member_ids), dtype=float)
        c, r = _o_space(positions.tobytes(), positions.shape[0], float(margin))
        if r > 0:
            centers.append(c)
            radii.append(r)
    return np.array(centers, dtype=float).reshape(-1, 2), np.array(radii, dtype=float)


@lru_cache(maxsize=64)
def _o_space(positions: bytes, count: int, margin: float) -> tuple[FloatArray, float]:
    """:func:`~socialnav.social.spaces.o_space` of ``count`` member positions (float64 bytes),
    remembered: a standing group is fitted once, not every control cycle (the fit is a few
    small linear-algebra calls, ~0.1 ms). The centre is read-only (shared)."""
    center, radius = o_space(np.frombuffer(positions, dtype=float).reshape(count, 2), margin)
    center = np.array(center, dtype=float)
    center.flags.writeable = False
    return center, radius


@CRITICS.register("group")
@dataclass(frozen=True)
class GroupCritic(Critic):
    """``GD_f = exp(1/GD)`` within ``influence_range`` of a group's o-space (module docstring).

    Parameters: ``influence_range`` (m, 0.25), ``evaluation`` (``last`` | ``max_over_time``),
    ``min_distance`` (m, cap ``exp(1/min_distance)``), ``margin`` (m, o-space = R − margin),
    ``illegal_inside`` (bool).
    """

    name: ClassVar[str] = "group"
    unit: ClassVar[str] = "exp(1/m)"

    influence_range: float = 0.25
    evaluation: Literal["last", "max_over_time"] = "last"
    min_distance: float = 0.1
    margin: float = OSPACE_MARGIN
    illegal_inside: bool = False

    def __post_init__(self) -> None:
        if not self.influence_range >= 0 or not self.min_distance > 0:
            raise ConfigurationError("group: influence_range >= 0 and min_distance > 0 required")
        if self.evaluation not in ("last", "max_over_time"):
            raise ConfigurationError(
                f"group: evaluation must be last|max_over_time, got {self.evaluation!r}"
            )

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Raw cost ``(N,)`` and illegal masks of the batch (see the class docstring)."""
        n = len(trajs)
        centers, radii = group_ospaces(ctx.social, self.margin)
        if radii.size == 0:
            return CriticScore(np.zeros(n))
        # Squared distance (G,) below which a trajectory intrudes: r² outside an o-space, the
        # current distance less ESCAPE_TOLERANCE inside one (escape: never deeper).
        now = np.hypot(*(np.asarray(ctx.pose[:2], dtype=float) - centers).T)
        limit = np.where(now < radii, np.maximum(now - ESCAPE_TOLERANCE, 0.0) ** 2, radii**2)
        if kernels.enabled():
            return self._score_compiled(trajs, centers, radii, limit)
        xy = trajs.xy if self.evaluation == "max_over_time" else trajs.xy[:, -1:]
        dx = xy[:, :, None, 0] - centers[:, 0]
        dy = xy[:, :, None, 1] - centers[:, 1]
        d2 = dx * dx + dy * dy  # (N, T', G)
        # GD_f is non-increasing in GD: the max over time is taken at the closest approach
        gd = np.sqrt(d2.min(axis=1)) - radii  # (N, G)
        cost = capped_inverse_exp(gd, self.influence_range, self.min_distance).max(axis=1)
        illegal: dict[str, np.ndarray] = {}
        if self.illegal_inside:
            if xy.shape[1] != trajs.xy.shape[1]:
                dx = trajs.xy[:, :, None, 0] - centers[:, 0]
                dy = trajs.xy[:, :, None, 1] - centers[:, 1]
                d2 = dx * dx + dy * dy
            illegal["ospace_intrusion"] = np.asarray((d2 < limit).any(axis=(1, 2)))
        return CriticScore(cost, illegal)

    def _score_compiled(
        self, trajs: Trajectories, centers: FloatArray, radii: FloatArray, limit: FloatArray
    ) -> CriticScore:
        """:meth:`score` with the minimum over time from the compiled kernel (bit-identical:
        the same squared distances and exact minima; ``any(d² < r²) == (min d²) < r²``)."""
        g = radii.size
        people = np.arange(g, dtype=np.intp)

        def d2min(poses: FloatArray) -> FloatArray:
            fixed = np.broadcast_to(centers, (poses.shape[1], g, 2))
            out = np.empty((poses.shape[0], g))
            kernels.min_squared_distances(poses, fixed, people, out)
            return out

        d2_all: FloatArray | None = None
        if self.evaluation == "max_over_time" or self.illegal_inside:
            d2_all = d2min(trajs.poses)
        if self.evaluation == "max_over_time" and d2_all is not None:
            d2 = d2_all
        else:
            d2 = d2min(trajs.poses[:, -1:])
        gd = np.sqrt(d2) - radii  # (N, G)
        cost = capped_inverse_exp(gd, self.influence_range, self.min_distance).max(axis=1)
        illegal: dict[str, np.ndarray] = {}
        if self.illegal_inside:
            assert d2_all is not None
            illegal["ospace_intrusion"] = np.asarray((d2_all < limit).any(axis=1))
        return CriticScore(cost, illegal)

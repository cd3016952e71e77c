"""The reward of the socialnav Gymnasium environments, term by term.

Per step of ``dt`` seconds (robot centre ``p``, footprint polygon ``F`` in the world frame):

===================  ==========================================================  ===========
term                 value                                                       default
===================  ==========================================================  ===========
progress             ``progress_scale · (d_prev − d)``, ``d`` = distance to the   0.1 / m
                     target (the social goal where one applies, else the goal)
success              ``success_reward`` when the episode terminates at the        +1
                     target (within tolerance, stopped)
collision            ``collision_penalty`` when ``F`` touches a person, a wall    −0.25
                     or an obstacle
timeout              ``timeout_penalty`` when the time limit truncates            0
discomfort           ``discomfort_factor · (g − discomfort_distance) · dt`` when  0.5, 0.2 m
                     the smallest gap ``g`` (robot disc edge to person edge) is
                     below ``discomfort_distance``
personal space       ``personal_space_factor · (c − personal_distance) · dt``     0.25, 1.2 m
                     when the nearest person's centre distance ``c`` is below
                     ``personal_distance`` (Hall's personal zone, as
                     ``socialnav compare``'s intrusion metrics)
group                ``−group_factor · depth · dt``, depth of ``p`` in a group's  1.0 / m·s
                     o-space (R − 0.3 m, the success condition's disc)
queue                ``−queue_factor · depth · dt``, depth of ``F`` in a queue    1.0 / m·s
                     band (between consecutive members; a cut-in)
activity space       ``−activity_factor · depth · dt``, depth of ``F`` in an      1.0 / m·s
                     artwork viewer's activity space
===================  ==========================================================  ===========

Sources. Success, collision, timeout and discomfort are CrowdNav's (Chen et al., "Crowd-Robot
Interaction", ICRA 2019, ``crowd_sim.py``: +1 on reaching the goal, −0.25 on a collision, 0 on a
timeout, ``(d_min − 0.2) · 0.5 · dt`` below 0.2 m). Progress is SocNavGym's distance reward
(Kapoor et al., "SocNavGym: A Reinforcement Learning Gym for Social Navigation", 2023: the change
of the distance to the goal, scaled); its discomfort factor (0.5) is reused for the personal-space
term. Group, queue and activity-space violations are this library's, measured with the geometry
``socialnav compare``'s success conditions use (``socialnav.social.spaces``), built from where
the people stood at the episode's start.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from socialnav.core.geometry import FloatArray
from socialnav.metrics.series import convex_overlap_depth
from socialnav.social.proxemics import PERSONAL

__all__ = ["RewardConfig", "SocialGeometry", "reward_terms"]


@dataclass(frozen=True)
class RewardConfig:
    """Weights of the reward terms (see the module docstring); SI units."""

    progress_scale: float = 0.1
    success_reward: float = 1.0
    collision_penalty: float = -0.25
    timeout_penalty: float = 0.0
    discomfort_distance: float = 0.2
    discomfort_factor: float = 0.5
    personal_distance: float = PERSONAL
    personal_space_factor: float = 0.25
    group_factor: float = 1.0
    queue_factor: float = 1.0
    activity_factor: float = 1.0

    @classmethod
    def from_any(cls, value: RewardConfig | dict[str, Any] | None) -> RewardConfig:
        """A config from itself, a mapping of field overrides, or ``None`` (the defaults).

        Raises ``ValueError`` naming an unknown field or a non-finite value."""
        if value is None:
            return cls()
        if isinstance(value, RewardConfig):
            return value
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(value) - known)
        if unknown:
            raise ValueError(f"reward: unknown term(s) {unknown}; known: {sorted(known)}")
        out = cls(**{k: float(v) for k, v in value.items()})
        for f in fields(cls):
            if not np.isfinite(getattr(out, f.name)):
                raise ValueError(f"reward.{f.name} must be finite")
        return out


@dataclass(frozen=True)
class SocialGeometry:
    """The spaces the group, queue and activity terms measure against (world frame, m):
    o-space discs ``(G, 3)`` as ``[x, y, r]``, queue bands and activity spaces ``[(4, 2)]``."""

    ospaces: FloatArray
    queue_bands: tuple[FloatArray, ...]
    activity_spaces: tuple[FloatArray, ...]


def _polygon_depth(footprint: FloatArray, polygons: tuple[FloatArray, ...]) -> float:
    """Deepest penetration (m) of ``footprint (V, 2)`` into any of ``polygons`` [(4, 2)]."""
    if not polygons:
        return 0.0
    stacked = np.stack(polygons)  # (P, 4, 2): every band and activity space is a quadrilateral
    # Bounding circles first: most steps the robot is nowhere near a band.
    centres, fc = stacked.mean(axis=1), footprint.mean(axis=0)
    reach = np.linalg.norm(stacked - centres[:, None], axis=2).max(axis=1)
    near = np.hypot(*(centres - fc).T) <= reach + np.linalg.norm(footprint - fc, axis=1).max()
    if not near.any():
        return 0.0
    return float(convex_overlap_depth(footprint[None], stacked[near]).max())


def reward_terms(
    config: RewardConfig,
    *,
    dt: float,
    progress: float,
    gap: float,
    centre_distance: float,
    collided: bool,
    succeeded: bool,
    timed_out: bool,
    centre: FloatArray,
    footprint: FloatArray,
    geometry: SocialGeometry,
) -> dict[str, float]:
    """Each term's value for one step (their sum is the reward).

    ``progress`` (m, positive toward the target), ``gap`` (m, robot disc edge to the nearest
    person's edge; ``inf`` without people), ``centre_distance`` (m, to the nearest person's
    centre), ``centre (2,)`` and ``footprint (V, 2)`` in the world frame.
    """
    c = config
    terms = {
        "progress": c.progress_scale * progress,
        "success": c.success_reward if succeeded else 0.0,
        "collision": c.collision_penalty if collided else 0.0,
        "timeout": c.timeout_penalty if timed_out else 0.0,
        "discomfort": (
            c.discomfort_factor * (gap - c.discomfort_distance) * dt
            if gap < c.discomfort_distance
            else 0.0
        ),
        "personal_space": (
            c.personal_space_factor * (centre_distance - c.personal_distance) * dt
            if centre_distance < c.personal_distance
            else 0.0
        ),
        "group": 0.0,
        "queue": -c.queue_factor * _polygon_depth(footprint, geometry.queue_bands) * dt,
        "activity_space": (
            -c.activity_factor * _polygon_depth(footprint, geometry.activity_spaces) * dt
        ),
    }
    if len(geometry.ospaces):
        depth = geometry.ospaces[:, 2] - np.hypot(*(geometry.ospaces[:, :2] - centre).T)
        terms["group"] = -c.group_factor * float(np.maximum(depth, 0.0).max()) * dt
    return terms

"""Sanity limits for groups: is this a conversation the robot could join?

A group's members come from a scenario file, an annotation or a detector, and any of them can
be wrong (the ETH/UCY walking-group lists give groups whose members are metres apart). The
join spot is built from the group's fitted circle, so a group is a join target only when:

- the circle's radius is within ``RADIUS_RANGE`` = [0.25, 2.5] m. 0.25 m is two people
  touching shoulder to shoulder (two 0.25 m body radii apart, the pair as diameter); 2.5 m is
  about the largest F-formation of a standing conversation: Kendon's o-space is held within
  Hall's social distance (far phase to 3.6 m between neighbours, "The Hidden Dimension", 1966),
  and a circle of 2.5 m radius already puts six members 2.5 m apart. The range admits the
  0.5–2 m of every group scenario and generator of this project;
- every member's nearest other member is at most ``MAX_NEIGHBOUR_DISTANCE`` = 5 m away, the
  diameter of the largest admitted circle: a member farther from everyone cannot share a
  plausible circle with them (the fit may still return one, pulled huge by that member);
- no two members stand closer than ``MIN_MEMBER_DISTANCE`` = 0.25 m, one body radius: two
  bodies cannot share that spot, so such a group is a duplicated track or a bad annotation;
- it is not a walking group (``Group.mode == "walking"``): people moving together are kept
  whole, never joined.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from socialnav.core.geometry import as_points
from socialnav.core.scene import SocialContext
from socialnav.social.spaces import fit_circle_detailed

RADIUS_RANGE = (0.25, 2.5)
MAX_NEIGHBOUR_DISTANCE = 2.0 * RADIUS_RANGE[1]
MIN_MEMBER_DISTANCE = 0.25


@dataclass(frozen=True)
class Plausibility:
    """``ok``; ``reason`` (a sentence, ``None`` when ok); the fitted ``radius`` (m) and the
    largest ``neighbour_distance`` (m, a member to their nearest other member)."""

    ok: bool
    reason: str | None
    radius: float
    neighbour_distance: float


def group_plausibility(
    positions: ArrayLike,
    *,
    radius_range: tuple[float, float] = RADIUS_RANGE,
    max_neighbour_distance: float = MAX_NEIGHBOUR_DISTANCE,
) -> Plausibility:
    """Check members ``(K, 2)`` (m) against the limits of the module docstring.

    Raises :class:`~socialnav.core.errors.InvalidInputError` on NaN or a wrong shape.
    """
    p = as_points(positions, "positions").reshape(-1, 2)
    if p.shape[0] < 2:
        return Plausibility(False, "fewer than two members", 0.0, 0.0)
    fit = fit_circle_detailed(p)
    d = np.linalg.norm(p[:, None] - p[None], axis=-1)
    np.fill_diagonal(d, np.inf)
    neighbour = float(d.min(axis=1).max())
    closest = float(d.min())
    lo, hi = radius_range
    if fit.method == "collinear":
        return Plausibility(False, "members stand in a line, not a circle", fit.radius, neighbour)
    if not lo <= fit.radius <= hi:
        return Plausibility(
            False,
            f"fitted circle radius {fit.radius:.2f} m is outside [{lo:.2f}, {hi:.2f}] m",
            fit.radius,
            neighbour,
        )
    if closest < MIN_MEMBER_DISTANCE:
        return Plausibility(
            False,
            f"two members stand {closest:.2f} m apart (< {MIN_MEMBER_DISTANCE:.2f} m: one spot)",
            fit.radius,
            neighbour,
        )
    if neighbour > max_neighbour_distance:
        return Plausibility(
            False,
            f"a member is {neighbour:.2f} m from every other member "
            f"(> {max_neighbour_distance:.2f} m)",
            fit.radius,
            neighbour,
        )
    return Plausibility(True, None, fit.radius, neighbour)


def implausible_groups(social: SocialContext) -> tuple[tuple[int, str], ...]:
    """``(index, reason)`` of every standing group of ``social.groups`` that fails the limits
    of the module docstring (walking groups are not conversations and are not checked)."""
    out = []
    for k, group in enumerate(social.groups):
        if group.is_walking or not group.member_ids:
            continue
        check = group_plausibility(social.positions(group.member_ids))
        if not check.ok:
            out.append((k, str(check.reason)))
    return tuple(out)


def plausible_context(social: SocialContext) -> SocialContext:
    """``social`` without its implausible standing groups (:func:`implausible_groups`): their
    members are planned around as people, not as a conversation whose o-space (built from the
    same implausible circle) the robot would keep out of; ``social`` itself when every group
    passes."""
    bad = {k for k, _ in implausible_groups(social)}
    if not bad:
        return social
    groups = tuple(g for k, g in enumerate(social.groups) if k not in bad)
    return replace(social, groups=groups)

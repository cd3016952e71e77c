"""Interpersonal-distance critic: the paper's ID objective.

Banisetty et al., "Socially-Aware Navigation: A Non-linear Multi-Objective Optimization Approach",
eq. (Interpersonal Distance): ``ID_f = exp(1 / ID)`` when ``ID <= 1.5 m``, else 0, one objective
per person (``ID_f1 … ID_fn``).

Deviations and choices:
- ``ID`` is the centre-to-centre distance (``distance="center"``, the paper's wording) or the
  gap between the robot's footprint disc and the person's disc (``distance="edge"``); the
  threshold applies to whichever distance is chosen.
- ``exp(1/d)`` explodes near 0; ``d`` is clamped at ``min_distance`` (default 0.1 m), so the cost
  is capped at ``exp(1/min_distance)`` ≈ 2.2e4 — finite, unlike the reference code's 1e9
  sentinel, and such rows are normally illegal anyway (below).
- ``evaluation="last"`` is the paper's rule: the trajectory's end point against people where
  they are now. ``"max_over_time"`` scores every rollout point against people forecast to that
  point's time (``ctx.people_at(trajs.t)``, Kollmitz-style time-indexed) and keeps the maximum.
- ``person_slot=None`` aggregates over people by the maximum; ``person_slot=k`` scores only the
  k-th nearest person to the robot at cycle start (0 = nearest; ties by person order; cost 0
  when there are fewer people), so ``ID_f1 … ID_fn`` can be separate objectives.
- Interaction partners (``partner_distance=True``, off by default: the paper has no such rule):
  when the robot steers to a stopping social goal, the people of a structure (group member,
  queue member, artwork viewer) nearer the spot than ``threshold`` are the people it joins,
  queues behind or presents to; their threshold becomes the distance the spot itself keeps
  from them less ``partner_margin`` (the formation's member spacing, the queue spacing, the
  presenter's distance), and their distance is scaled by ``threshold / own threshold`` so the
  cost has the paper's shape relative to the interaction's distance. Without it the objective
  forbids what the social goal asks for (the robot stalls ~1.5 m from its partners). With no
  social goal, the same rule holds for anyone nearer the given goal than ``threshold``: the
  goal's own distance from them, less the margin (a goal beside a standing stranger is
  reachable without a crawl against ID).
- Narrow passages (``passage_distance=True``, off by default: the paper has no such rule): a
  person standing (slower than ``STANDING_SPEED``) within ``threshold`` of the global plan's
  next ``PASSAGE_LOOKAHEAD`` m, beside a passage that allows less than ``threshold``
  (:func:`passage_clearances`), gets the passage's own distance less ``partner_margin`` as
  their threshold — at least ``PERSONAL_DISTANCE + partner_margin`` where the passage allows
  the 1.2 m personal space (which keeps the personal space where the estimate, at the
  costmap's resolution, is a little short; between 1.2 and 1.25 m the robot then still pays
  a small cost at the passage's far edge) — and their distance is scaled as for partners.
  Without it, passing someone who stands 0.8 m from a wall costs more ID the farther the
  robot has driven, up to the closest point, so every cycle a slower command scores better:
  the robot crawled, and the progress checker gave up beside the person (generated hallway).
  A robot already beside the person, within ``PASSAGE_COMMIT`` m of them along the plan,
  keeps its own side's room, unless only the other side keeps ``PERSONAL_DISTANCE``; one
  squeezed abreast of them, already nearer than ``PERSONAL_DISTANCE`` on a side whose places
  keep less than it from everyone standing, gets a room of at most its own lateral offset
  from them plus ``ABREAST_MARGIN`` (:func:`passage_clearances`).
- Passing distance (``hold_horizon`` s, 0 = off; ``max_over_time`` only): after the rollout the
  robot is assumed to stand at the trajectory's end point while people walk on at constant
  velocity for ``hold_horizon`` s, and the distance is the minimum over the rollout and that
  continuation. A walker who will pass the end point at 1.4 m then costs the same whether the
  robot got there now or stands still: without it, standing still scores better against an
  oncoming walker only because the closest approach falls outside the rollout horizon, and the
  robot stops until the walker has passed (the "yielding" time). Standing in a walker's way
  costs what the encounter will cost (the end point is where a robot can always stop).
- Personal space as a preference (``personal_space`` m, 0 = off, the paper has no such rule;
  ``max_over_time`` only, at most ``threshold``): a trajectory that comes nearer than its bound to
  someone now at least that far away is illegal, reason ``personal_space``, a *preferred* reason
  (``objectives.PREFERRED_REASONS``: given up first, when no trajectory keeps it). The distance is
  the one this critic measures (centre to centre with ``distance="center"``), over the rollout and
  the passing continuation; each person's bound is ``personal_space``, or their own threshold where
  that is less (an interaction partner at the interaction's distance, someone beside a narrow
  passage at the most the passage allows less ``partner_margin``, a stranger near the given goal at
  the goal's own distance less the margin; these are centre to centre, as ID's thresholds, also with
  ``distance="edge"``). Someone already nearer than their bound is not judged. ID alone only trades
  the distance against progress, so the robot drove on beside a walker at 1.14–1.2 m, or squeezed
  past someone standing while the other side had room, where slowing down for a moment kept the
  personal space (generated hallway). Only where few people are near (at most
  ``personal_space_people`` centres within ``personal_space_range`` m of the robot's: in a crowd
  nearly every move enters someone's space and constant-velocity forecasts do not hold), only while
  one of them walks (at least ``personal_space_walker_speed`` m/s; 0 = always: waiting for a walker
  to go by ends, but someone standing stays, and the robot stood 1.21 m from a viewer it had to pass
  until the time limit, generated gallery_pass), and with ``personal_space_kinematics="holonomic"``
  only for a robot that can step sideways.
- Collisions: a trajectory whose footprint disc (``footprint_disc`` radius: the inscribed circle
  by default — the occupancy critic handles corners against walls; choose ``circumscribed`` to be
  conservative) overlaps a person's disc at any rollout time (people forecast by
  ``ctx.people_at``) is illegal, reason ``person_collision`` — except against a person already
  overlapping it now, where only a trajectory that ever gets closer to them is (escape from
  overlap: the robot can always drive away from someone touching it).
- Closing on a person (``approach_check``, on by default): a trajectory that moves toward a
  person's forecast position while its footprint disc (``footprint_disc``) touches theirs —
  the robot's own step between two rollout samples has a component above ``approach_speed``
  (m/s) toward them at a sample in contact — is illegal, reason ``person_approach``. This is
  the rollout form of an *active* collision (Francis et al. 2023; ``socialnav.metrics.crowd``).
  ``approach_footprint="polygon"`` judges it on the footprint polygon instead of the disc, as
  the crowd metric does: at a sample where the polygon touches a person, the robot's step into
  or out of it (translation and turning) brings the polygon closer to the person's centre,
  held where it is, faster than ``approach_speed``. The disc sees neither a corner swept into
  someone by a turn on the spot nor a corner beyond the inscribed circle.
  ``person_collision`` (any overlap) is a *soft* reason (``objectives.SOFT_REASONS``): when a
  person walks into the robot whatever it does, it is dropped for the cycle, so the planner
  still chooses among the trajectories that stand still or move away (passive contact)
  instead of having none.
- Speed, not behaviour: the per-time distances enter only through their minimum over time
  (``f`` is non-increasing; a collision at some time is ``min d² < r²``), so the ``(N, K)``
  minimum is computed once per cycle and shared by every interpersonal critic (the paper's
  ``ID_f1 … ID_fn`` slots) via ``ctx.cache``; people who provably stay beyond every distance
  that matters are culled first (:func:`min_squared_distances`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from numbers import Integral
from typing import TYPE_CHECKING, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from socialnav.core.errors import ConfigurationError, is_non_negative_number
from socialnav.core.geometry import (
    FloatArray,
    signed_distance_to_polygon,
    world_to_body_frames,
)
from socialnav.core.trajectories import Trajectories
from socialnav.planner import kernels
from socialnav.planner.cache import PeopleDistances
from socialnav.planner.critics.base import CRITICS, Critic, CriticScore
from socialnav.social.goals import interaction_distances
from socialnav.world.grid import INSCRIBED, LETHAL, Costmap

if TYPE_CHECKING:
    from socialnav.planner.context import PlanningContext


def capped_inverse_exp(d: FloatArray, threshold: float, min_distance: float) -> FloatArray:
    """``exp(1 / max(d, min_distance))`` where ``d <= threshold``, else 0 (same shape as ``d``)."""
    return np.where(d <= threshold, np.exp(1.0 / np.maximum(d, min_distance)), 0.0)


def footprint_radius(ctx: PlanningContext, which: str) -> float:
    """The robot's inscribed or circumscribed radius (m)."""
    return ctx.robot.inscribed_radius if which == "inscribed" else ctx.robot.circumscribed_radius


def _box(xy: FloatArray) -> tuple[FloatArray, FloatArray]:
    return xy.min(axis=0), xy.max(axis=0)


def min_squared_distances(
    trajs: Trajectories, ctx: PlanningContext, reach: FloatArray
) -> FloatArray:
    """``(N, K)`` min over rollout time of the squared distance between each trajectory point
    and each person forecast to that time (``ctx.people_at(trajs.t)``).

    Exact wherever the distance can be ``<= reach[k]`` (m, per person); a person who provably
    stays farther than ``reach[k]`` from every rollout point at every time gets ``inf`` (culled:
    the bound is the distance from the person to the box of all trajectory points at that
    time). The compiled path also culls single (trajectory, person) pairs whose boxes over the
    whole rollout stay farther apart than ``reach[k]`` (``inf`` there too; the reference keeps
    those exact). Shared through ``ctx.cache.people_distances`` within a cycle: computed once
    per (trajectory batch, forecast) — the cache keeps the batch itself and compares by
    identity — and extended when a later caller's ``reach`` needs more people or a larger
    reach.
    """
    entry = ctx.cache.people_distances
    if entry is None or entry.trajs is not trajs:
        xy = trajs.xy
        forecast = ctx.people_at(trajs.t)  # (T, K, 2)
        # Per-time box of the rollout points → a lower bound on each person's distance.
        lo, hi = kernels.time_box(trajs.poses) if kernels.enabled() else _box(xy)  # (T, 2)
        gap = np.maximum(lo[:, None] - forecast, 0.0) + np.maximum(forecast - hi[:, None], 0.0)
        bound = np.sqrt((gap * gap).sum(axis=-1)).min(axis=0)  # (K,)
        d2min = np.full((len(trajs), forecast.shape[1]), np.inf)
        entry = PeopleDistances(trajs, forecast, bound, np.full(forecast.shape[1], -np.inf), d2min)
        ctx.cache.people_distances = entry
    forecast, bound, covered, d2min = entry.forecast, entry.bound, entry.covered, entry.d2min
    # A relative margin keeps the cull conservative against rounding in the bound.
    todo = (reach > covered) & (bound <= reach * (1.0 + 1e-9) + 1e-9)
    if todo.any() and kernels.enabled():
        cols = np.flatnonzero(todo)
        kernels.min_squared_distances_culled(trajs.poses, forecast, cols, reach[cols], d2min)
        covered[todo] = reach[todo]
    elif todo.any():
        xs = np.ascontiguousarray(trajs.xy[..., 0])  # (N, T)
        ys = np.ascontiguousarray(trajs.xy[..., 1])
        # One person at a time: (N, T) temporaries stay in cache, unlike one (N, T, K) array.
        for j in np.flatnonzero(todo):
            dx = xs - forecast[None, :, j, 0]
            dy = ys - forecast[None, :, j, 1]
            np.multiply(dx, dx, out=dx)
            np.multiply(dy, dy, out=dy)
            np.add(dx, dy, out=dx)
            d2min[:, j] = dx.min(axis=1)
        covered[todo] = np.inf
    return d2min


def passing_walks(
    trajs: Trajectories, ctx: PlanningContext, horizon: float, reach: FloatArray | None = None
) -> tuple[FloatArray, FloatArray, NDArray[np.intp]]:
    """Each person's walk after the rollout for :func:`passing_distances`: ``start (K, 2)``
    (m, world: the forecast position at the rollout's end), ``step (K, 2)`` (m: velocity ×
    ``horizon`` s), and the people ``(K',)`` whose walk can come within ``reach (K,)`` m of an
    end point (all without ``reach``)."""
    end = trajs.xy[:, -1]  # (N, 2)
    t_end = np.asarray(trajs.t[-1:], dtype=float)
    start = ctx.people_at(t_end)[0]  # (K, 2)
    step = ctx.social.velocities() * horizon  # (K, 2): the walk after the rollout
    cols = np.arange(start.shape[0])
    if reach is not None:
        lo, hi = end.min(axis=0), end.max(axis=0)
        seg_lo, seg_hi = np.minimum(start, start + step), np.maximum(start, start + step)
        gap = np.maximum(lo - seg_hi, 0.0) + np.maximum(seg_lo - hi, 0.0)  # (K, 2)
        bound = np.sqrt((gap * gap).sum(axis=1))
        cols = np.flatnonzero(bound <= reach * (1.0 + 1e-9) + 1e-9)
    return start, step, cols


def passing_distances(
    trajs: Trajectories, ctx: PlanningContext, horizon: float, reach: FloatArray | None = None
) -> FloatArray:
    """``(N, K)`` closest distance (m, centres) between each trajectory's end point, where the
    robot is assumed to stop, and each person walking on at constant velocity from their
    forecast position at the rollout's end for ``horizon`` s (module docstring).

    With ``reach (K,)`` (m), a person whose walk provably stays farther than ``reach[k]`` from
    every end point gets ``inf`` (the bound: the gap between the walk's box and the end points'
    box), as :func:`min_squared_distances` culls."""
    end = trajs.xy[:, -1]  # (N, 2)
    start, step, cols = passing_walks(trajs, ctx, horizon, reach)
    out = np.full((end.shape[0], start.shape[0]), np.inf)
    start, step = start[cols], step[cols]
    w = end[:, None, :] - start[None]  # (N, K', 2)
    uu = (step * step).sum(axis=1)  # (K',)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(uu > 0, (w * step[None]).sum(axis=-1) / uu, 0.0)
    s = np.clip(s, 0.0, 1.0)
    gap = w - s[..., None] * step[None]
    out[:, cols] = np.sqrt((gap * gap).sum(axis=-1))
    return out


#: people slower than this (m/s) stand (``passage_distance``); stricter than the 0.3 m/s under
#: which the global plan treats people as standing (``presets.MEETING_LAYER``): only people
#: who really stand lower the threshold (0.3 was not measured)
STANDING_SPEED = 0.1
#: how much of the global plan ahead (m) ``passage_distance`` looks at
PASSAGE_LOOKAHEAD = 3.0
#: the personal space (m) a passage that allows it keeps (``passage_distance``)
PERSONAL_DISTANCE = 1.2
#: how far (m) to either side of a standing person the passage is looked at
PASSAGE_REACH = 3.0
#: within this distance (m) of a person's cross-section, along the plan, a robot already
#: beside them keeps to its own side's room (``passage_clearances``)
PASSAGE_COMMIT = 1.5
#: a robot squeezed abreast of a standing person gets their passage room capped at its own
#: lateral offset plus this (m): with the default ``partner_margin`` (0.05) the ID threshold is
#: the offset less 1 cm, so level with them an inward step of more than 1 cm costs ID
#: (``passage_clearances``; before or past them, where the distance is not the lateral offset,
#: smaller steps can be free)
ABREAST_MARGIN = 0.04


def passage_clearances(ctx: PlanningContext, threshold: float) -> FloatArray:
    """``(K,)`` for each person standing within ``threshold`` (m) of the global plan's next
    ``PASSAGE_LOOKAHEAD`` m: the largest centre distance (m) from them at which the robot's
    centre can pass, on the cross-section through them perpendicular to the plan, among the
    places that keep the most distance from every standing person; ``inf`` for everyone else.

    The cross-section runs ``PASSAGE_REACH`` m to either side (so no value exceeds it; values of
    ``threshold`` or more mean no narrow passage), through other people (a pair standing side by
    side is passed on the side with room for both) but not through static obstacles (a blocked
    place next to a LETHAL cell that is not a person's; so also a wall inside a person's own
    inflation); a place is free where ``ctx.costmap`` is below INSCRIBED, or inside a walker's
    own cells (they walk on) away from static obstacles. An estimate, sampled at the costmap's
    resolution (within about half a cell in a straight corridor; the local section of the
    passage elsewhere). Places within one cell of the most distance count as keeping it, so
    where both sides of a cross-section nearly tie, each person gets the side farther from them.
    A robot within ``PASSAGE_COMMIT`` m of the cross-section (along the plan, before or past it)
    and beside the person (its centre at least their radius plus its inscribed radius to one
    side) is committed to its side: only that side's places count, when it has any, unless the
    other side has a place that keeps ``PERSONAL_DISTANCE`` from everyone standing and its own
    side has none (the robot is better off going round; the crawl makes it stop and replan:
    generated hallway dev seed 107, Pioneer, passed 1.06 m from a person when committed there,
    1.33 m without). Without this, a robot that went into the narrower of two gaps (after giving
    way to a walker, say) was held to the wider gap's distance and crawled against ID until it
    stalled (generated hallway dev seed 183, Pioneer). A robot *squeezed* beside a person —
    beside them, abreast of them (the distance from its centre to theirs, along the plan's
    tangent at the person, at most their radius plus the footprint's half-length), already
    nearer than ``PERSONAL_DISTANCE``, on a side whose places keep less than
    ``PERSONAL_DISTANCE`` from everyone standing — gets at most its own lateral offset from them
    (on the cross-section's normal) plus ``ABREAST_MARGIN`` as the room, whatever the other side
    allows: the places the estimate finds may lie beyond its footprint's reach (a cell or so at
    a wall: dev seed 73, Pioneer, 0.87 m against an estimated 0.95 m) or on the other side,
    which it can no longer reach without turning back (dev seed 196, Pioneer, 0.77 m from a
    person with 1.5 m below them); held to either, it crawled back and forth beside the person
    until the time limit. A side that keeps the personal space is never capped, so there ID
    still pushes the robot out. Without a plan of positive length, or nobody standing near it,
    all ``inf`` (the option has no effect). Never raises for a well-typed context."""
    from socialnav.planner.critics.map_grid import plan_ahead

    social = ctx.social
    k = len(social.people)
    out = np.full(k, np.inf)
    path = np.asarray(ctx.global_path, dtype=float).reshape(-1, 2)
    if k == 0 or path.shape[0] < 2:
        return out
    pos, radii = social.positions(), social.radii()
    speed = np.hypot(*social.velocities().reshape(-1, 2).T)
    standing = speed < STANDING_SPEED
    if not standing.any():
        return out
    ahead, arc = plan_ahead(path, np.asarray(ctx.pose, dtype=float)[:2])
    ahead = ahead[arc <= PASSAGE_LOOKAHEAD]
    if ahead.shape[0] < 2:
        return out
    d = np.hypot(*(ahead[None] - pos[:, None]).transpose(2, 0, 1))  # (K, P)
    todo = np.flatnonzero(standing & (d.min(axis=1) < threshold))
    if todo.size == 0:
        return out
    cm = ctx.costmap
    res = cm.resolution
    inscribed = ctx.robot.inscribed_radius
    t = np.arange(-PASSAGE_REACH, PASSAGE_REACH + 0.5 * res, res)  # (S,) offsets (m)
    middle = int(np.argmin(np.abs(t)))
    still = pos[standing]
    walkers = np.flatnonzero(~standing)
    # the cross-sections (P, S): through each person, perpendicular to the plan's tangent
    j = np.argmin(d[todo], axis=1)
    last = ahead.shape[0] - 1
    tangent = ahead[np.minimum(j + 3, last)] - ahead[np.maximum(j - 3, 0)]  # (P, 2)
    norm = np.hypot(*tangent.T)
    ok = norm > 1e-9
    todo, tangent, norm = todo[ok], tangent[ok], norm[ok]
    if todo.size == 0:
        return out
    normal = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1) / norm[:, None]
    pts = pos[todo, None, :] + t[None, :, None] * normal[:, None, :]  # (P, S, 2)
    free = cm.cost_at(pts) < INSCRIBED
    to_still = np.hypot(*(pts[:, :, None] - still).transpose(3, 0, 1, 2)).min(axis=-1)
    if walkers.size:
        free = ~people_unblocked(cm, pts, ~free, pos[walkers], radii[walkers], inscribed)
    # Static obstacles end a cross-section on either side of the person; people do not. A
    # blocked place near someone standing is a wall only next to a LETHAL cell that is not a
    # person's own: a wall inside their inflation ends the cross-section too.
    near = ~free & (to_still <= radii.max() + inscribed + 2 * res)
    wall = ~free & ~near
    if near.any():
        wall[near] = foreign_lethal(cm, pts[near], _NEIGHBOURS, pos, radii)
    up, down = wall[:, middle:], wall[:, middle::-1]
    stop = np.where(up.any(axis=1), middle + up.argmax(axis=1), t.size)  # (P,) exclusive
    first = np.where(down.any(axis=1), middle - down.argmax(axis=1) + 1, 0)
    idx = np.arange(t.size)
    free &= (idx >= first[:, None]) & (idx < stop[:, None])
    has = free.any(axis=1)
    room, kept = _room(free, to_still, t, res)
    # a robot already beside the person, near the cross-section, keeps to its side's room,
    # unless only the other side keeps the personal space
    rel = np.asarray(ctx.pose, dtype=float)[:2] - pos[todo]  # (P, 2)
    lateral = (rel * normal).sum(axis=1)
    along = (rel * tangent).sum(axis=1) / norm
    beside = (np.abs(along) <= PASSAGE_COMMIT) & (np.abs(lateral) >= radii[todo] + inscribed)
    if beside.any():
        own_side = free & (np.sign(lateral)[:, None] * t[None, :] > 0)
        own_room, own_kept = _room(own_side, to_still, t, res)
        commit = (own_kept >= PERSONAL_DISTANCE) | (kept < PERSONAL_DISTANCE)
        room = np.where(beside & own_side.any(axis=1) & commit, own_room, room)
        # squeezed (docstring): the estimate's room may be out of the footprint's reach
        half_length = float(np.abs(ctx.robot.polygon[:, 0]).max())
        abreast = np.abs(along) <= radii[todo] + half_length
        inside = np.hypot(*rel.T) < PERSONAL_DISTANCE
        squeezed = beside & abreast & inside & (own_kept < PERSONAL_DISTANCE)
        offset = np.abs(lateral) + ABREAST_MARGIN
        room = np.where(squeezed, np.minimum(room, offset), room)
    out[todo[has]] = room[has]
    return out


def _room(
    free: NDArray[np.bool_], to_still: FloatArray, t: FloatArray, res: float
) -> tuple[FloatArray, FloatArray]:
    """Per cross-section ``(P,)``: the most distance ``to_still (P, S)`` from everyone standing
    that its ``free`` places ``(P, S)`` keep, and the largest ``|t|`` among the places within
    ``res`` of it (the person's room); ``(room, kept)``, ``-inf`` without a free place."""
    kept = np.where(free, to_still, -np.inf).max(axis=1, initial=-np.inf)
    best = free & (to_still >= kept[:, None] - res)
    room: FloatArray = np.where(best, np.abs(t), -np.inf).max(axis=1, initial=-np.inf)
    return room, kept


#: a cell and its 8 neighbours, as (rows, cols) offsets
_NEIGHBOURS = (np.repeat(np.arange(-1, 2), 3), np.tile(np.arange(-1, 2), 3))


def foreign_lethal(
    cm: Costmap,
    places: FloatArray,
    offsets: tuple[NDArray[np.intp], NDArray[np.intp]],
    people: FloatArray,
    radii: FloatArray,
) -> NDArray[np.bool_]:
    """``(Q,)`` whether a LETHAL cell of ``cm`` lies at ``offsets`` (rows, cols) around the cell
    of each of ``places (Q, 2)`` (m, world) that is not one of ``people (K, 2)``'s own (its
    centre within their radius ``radii (K,)`` plus a cell)."""
    res = cm.resolution
    rc = cm.geometry.world_to_cell(places)  # (Q, 2)
    dr, dc = offsets
    cells = np.stack([rc[:, None, 0] + dr, rc[:, None, 1] + dc], axis=-1)  # (Q, M, 2)
    world = np.asarray(cm.geometry.origin) + (cells[..., ::-1] + 0.5) * res
    lethal = cm.cost_at(world) >= LETHAL  # (Q, M)
    own = np.hypot(*(world[:, :, None] - people).transpose(3, 0, 1, 2)) <= radii + res
    found: NDArray[np.bool_] = (lethal & ~own.any(axis=-1)).any(axis=1)
    return found


def people_unblocked(
    cm: Costmap,
    places: FloatArray,
    blocked: NDArray[np.bool_],
    people: FloatArray,
    radii: FloatArray,
    inscribed: float,
) -> NDArray[np.bool_]:
    """``blocked`` (a copy, shape of ``places (..., 2)`` without the last axis) with the places
    near ``people (K, 2)`` (within their radius ``radii (K,)`` + ``inscribed`` + 2 cells)
    blocked only where a LETHAL cell that is no person's own lies within ``inscribed`` m: the
    costmap marks people inflated like walls, and this sees through them but not through a
    wall beside them."""
    out = blocked.copy()
    res = cm.resolution
    rel = places[..., None, :] - people
    near = out & (np.hypot(rel[..., 0], rel[..., 1]) <= radii + inscribed + 2 * res).any(axis=-1)
    if near.any():
        out[near] = foreign_lethal(cm, places[near], disc_offsets(inscribed, res), people, radii)
    return out


@lru_cache(maxsize=8)
def disc_offsets(radius: float, res: float) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Cell offsets ``(M,)`` rows and columns within ``radius`` (m) of a cell's centre."""
    n = int(np.ceil(radius / res))
    dr, dc = np.mgrid[-n : n + 1, -n : n + 1]
    keep = np.hypot(dr, dc) * res <= radius
    return dr[keep], dc[keep]


def partner_thresholds(
    ctx: PlanningContext,
    threshold: float,
    margin: float,
    passage: bool = False,
    partners: bool = True,
) -> FloatArray:
    """Per person ``(K,)``: ``threshold`` (m); with ``partners``, for an interaction partner of
    the stopping social goal the spot's own distance to them less ``margin``; with
    ``passage``, for a person standing beside a narrow passage the passage's own distance less
    ``margin`` (module docstring)."""
    if partners:
        out = _partner_thresholds(ctx, threshold, margin)
    else:
        out = np.full(len(ctx.social.people), float(threshold))
    if passage and out.size:
        room = passage_clearances(ctx, threshold)
        own = np.where(
            room >= PERSONAL_DISTANCE,
            np.maximum(room - margin, PERSONAL_DISTANCE + margin),
            room - margin,
        )
        out = np.where(room < threshold, np.minimum(out, np.maximum(own, 1e-3)), out)
    return out


def _partner_thresholds(ctx: PlanningContext, threshold: float, margin: float) -> FloatArray:
    social = ctx.social
    out = np.full(len(social.people), float(threshold))
    sg = ctx.social_goal
    if not social.people:
        return out
    if sg is None:
        # A given goal inside someone's personal space: they keep the goal's own distance
        # from them (less the margin), so the last metres are not a crawl against ID.
        gaps = np.linalg.norm(social.positions() - np.asarray(ctx.goal, dtype=float)[:2], axis=1)
        near = gaps < threshold
        out[near] = np.maximum(gaps[near] - margin, 1e-3)
        return out
    if getattr(sg, "is_waypoint", False):
        return out
    if not np.allclose(np.asarray(sg.pose, dtype=float), ctx.goal):
        return out  # steering elsewhere (e.g. a waypoint first): nobody is a partner yet
    return interaction_distances(social, sg.pose, threshold, margin)


@CRITICS.register("interpersonal")
@dataclass(frozen=True)
class InterpersonalCritic(Critic):
    """``ID_f = exp(1/ID)`` for ``ID <= threshold`` (module docstring for the options).

    Parameters: ``threshold`` (m, 1.5), ``distance`` (``center`` | ``edge``), ``evaluation``
    (``last`` | ``max_over_time``), ``person_slot`` (int >= 0 or None), ``min_distance`` (m, the
    cap), ``footprint_disc`` (``inscribed`` | ``circumscribed``), ``collision_check`` (bool),
    ``partner_distance`` (bool) and ``partner_margin`` (m, 0.05), ``approach_check`` (bool),
    ``approach_speed`` (m/s, 0.02) and ``approach_footprint`` (``disc`` | ``polygon``),
    ``hold_horizon`` (s, 0 = off), ``passage_distance`` (bool), ``personal_space`` (m, 0 = off,
    at most ``threshold``, ``max_over_time`` only) with ``personal_space_people`` (int >= 1,
    3), ``personal_space_range`` (m, 10.0), ``personal_space_walker_speed`` (m/s, 0.3) and
    ``personal_space_kinematics`` (``any`` | ``holonomic``, ``any``); each is described in the
    module docstring. Raises ``ConfigurationError`` for a ``personal_space*`` value out of
    range or of the wrong type. Use:
    ``InterpersonalCritic(...).score(trajs, ctx)`` with a
    :class:`~socialnav.planner.context.PlanningContext` (no ``prepare`` needed).
    """

    name: ClassVar[str] = "interpersonal"
    unit: ClassVar[str] = "exp(1/m)"

    threshold: float = 1.5
    distance: Literal["center", "edge"] = "center"
    evaluation: Literal["last", "max_over_time"] = "last"
    person_slot: int | None = None
    min_distance: float = 0.1
    footprint_disc: Literal["inscribed", "circumscribed"] = "inscribed"
    collision_check: bool = True
    partner_distance: bool = False
    partner_margin: float = 0.05
    approach_check: bool = True
    approach_speed: float = 0.02
    approach_footprint: Literal["disc", "polygon"] = "disc"
    hold_horizon: float = 0.0
    passage_distance: bool = False
    personal_space: float = 0.0
    personal_space_people: int = 3
    personal_space_range: float = 10.0
    personal_space_walker_speed: float = 0.3
    personal_space_kinematics: Literal["any", "holonomic"] = "any"

    def __post_init__(self) -> None:
        for name in ("personal_space", "personal_space_range", "personal_space_walker_speed"):
            value = getattr(self, name)
            if not is_non_negative_number(value) or (name.endswith("range") and value == 0):
                sign = "> 0" if name.endswith("range") else ">= 0"
                raise ConfigurationError(
                    f"interpersonal: {name} must be a finite number {sign}, got {value!r}"
                )
        if self.personal_space > 0 and (
            self.evaluation != "max_over_time" or self.personal_space > self.threshold
        ):
            raise ConfigurationError(
                "interpersonal: personal_space needs evaluation='max_over_time' and at most "
                f"threshold ({self.threshold!r} m), got {self.personal_space!r} with "
                f"{self.evaluation!r}"
            )
        if (
            not isinstance(self.personal_space_people, Integral)
            or isinstance(self.personal_space_people, bool)
            or self.personal_space_people < 1
        ):
            raise ConfigurationError(
                "interpersonal: personal_space_people must be an int >= 1, got "
                f"{self.personal_space_people!r}"
            )
        if self.personal_space_kinematics not in ("any", "holonomic"):
            raise ConfigurationError(
                "interpersonal: personal_space_kinematics must be any|holonomic, "
                f"got {self.personal_space_kinematics!r}"
            )
        if not self.threshold > 0 or not self.min_distance > 0:
            raise ConfigurationError("interpersonal: threshold and min_distance must be > 0")
        if not (np.isfinite(self.hold_horizon) and self.hold_horizon >= 0):
            raise ConfigurationError("interpersonal: hold_horizon must be finite and >= 0")
        if self.distance not in ("center", "edge"):
            raise ConfigurationError(
                f"interpersonal: distance must be center|edge, got {self.distance!r}"
            )
        if self.evaluation not in ("last", "max_over_time"):
            raise ConfigurationError(
                f"interpersonal: evaluation must be last|max_over_time, got {self.evaluation!r}"
            )
        if self.person_slot is not None and (
            not isinstance(self.person_slot, int) or self.person_slot < 0
        ):
            raise ConfigurationError("interpersonal: person_slot must be None or an int >= 0")
        if self.approach_footprint not in ("disc", "polygon"):
            raise ConfigurationError(
                "interpersonal: approach_footprint must be disc|polygon, "
                f"got {self.approach_footprint!r}"
            )
        if self.footprint_disc not in ("inscribed", "circumscribed"):
            raise ConfigurationError(
                "interpersonal: footprint_disc must be inscribed|circumscribed"
            )

    def _distance_scale(self, ctx: PlanningContext) -> FloatArray | None:
        """``(K,)`` factor on each person's distance, ``threshold / own threshold`` (partners,
        narrow passages: module docstring), or None when neither option is on."""
        if not (self.partner_distance or self.passage_distance):
            return None
        own = partner_thresholds(
            ctx, self.threshold, self.partner_margin, self.passage_distance, self.partner_distance
        )
        return np.asarray(self.threshold / own)

    def _personal_space(
        self,
        ctx: PlanningContext,
        d: FloatArray,
        cols: NDArray[np.intp] | None,
        scale: FloatArray | None,
    ) -> np.ndarray | None:
        """``(N,)`` the rows of ``d`` (``(N, J)`` distances as measured and scaled by ``scale``
        (``(K,)``, :meth:`_distance_scale`'s, None: unscaled), of the people ``cols``, all when
        None) that come inside someone's bound who is now outside it, or None when the rule
        does not apply (module docstring)."""
        if self.personal_space <= 0:
            return None
        if self.personal_space_kinematics == "holonomic" and not ctx.robot.holonomic:
            return None
        centre = np.hypot(*(ctx.social.positions() - ctx.pose[:2]).T)  # (K,)
        near = centre <= self.personal_space_range
        if int(near.sum()) > self.personal_space_people:
            return None
        if self.personal_space_walker_speed > 0:
            v = ctx.social.velocities()
            if not (near & (np.hypot(v[:, 0], v[:, 1]) >= self.personal_space_walker_speed)).any():
                return None
        now = centre
        if self.distance == "edge":
            robot_r = footprint_radius(ctx, self.footprint_disc)
            now = np.maximum(centre - ctx.social.radii() - robot_r, 0.0)
        if scale is None:
            scale = np.ones_like(now)
        # d is scaled by threshold / own: the bound min(personal_space, own) on the measured
        # distance is min(personal_space * scale, threshold) on the scaled one
        bound = np.minimum(self.personal_space * scale, self.threshold)
        outside = now * scale >= bound
        if cols is not None:
            outside, bound = outside[cols], bound[cols]
        return np.asarray((d[:, outside] < bound[outside][None, :]).any(axis=1))

    def score(self, trajs: Trajectories, ctx: PlanningContext) -> CriticScore:
        """Raw cost ``(N,)`` and illegal masks of the batch (see the class docstring)."""
        n = len(trajs)
        people_now = ctx.social.positions()  # (K, 2)
        k = people_now.shape[0]
        if k == 0:
            return CriticScore(np.zeros(n))
        radii = ctx.social.radii()
        robot_r = footprint_radius(ctx, self.footprint_disc)
        xy = trajs.xy  # (N, T, 2)
        d2min = None
        if self.evaluation == "max_over_time" or self.collision_check:
            # Per person, the largest distance at which this critic's result depends on it.
            reach = np.full(k, -np.inf)
            if self.evaluation == "max_over_time":
                reach = np.full(k, self.threshold)
                if self.distance == "edge":
                    reach = reach + radii + robot_r
            if self.collision_check:
                reach = np.maximum(reach, radii + robot_r)
                if self.approach_check and self.approach_footprint == "polygon":
                    reach = np.maximum(reach, radii + ctx.robot.circumscribed_radius)
            d2min = min_squared_distances(trajs, ctx, reach)  # (N, K)
        if (
            d2min is not None
            and kernels.enabled()
            and self.evaluation == "max_over_time"
            and self.person_slot is None
            and trajs.poses.dtype == np.float64
        ):
            return self._score_compiled(trajs, ctx, d2min, reach, robot_r)

        if self.evaluation == "last":
            d = np.linalg.norm(xy[:, -1, None, :] - people_now[None], axis=-1)  # (N, K)
        else:
            # f is non-increasing in d, so max over time of f(d) = f(min over time of d)
            assert d2min is not None
            d = np.sqrt(d2min)
            if self.hold_horizon > 0 and ctx.predict_people:
                # beyond the threshold reach the cost is 0 whichever distance is taken
                d = np.minimum(d, passing_distances(trajs, ctx, self.hold_horizon, reach))
        if self.distance == "edge":
            d = np.maximum(d - radii - robot_r, 0.0)
        scale = self._distance_scale(ctx)
        if scale is not None:
            d = d * scale[None, :]
        f = capped_inverse_exp(d, self.threshold, self.min_distance)  # (N, K)

        if self.person_slot is None:
            cost = f.max(axis=1)
        elif self.person_slot < k:
            near = np.linalg.norm(people_now - ctx.pose[:2], axis=1)
            cost = f[:, np.argsort(near, kind="stable")[self.person_slot]]
        else:
            cost = np.zeros(n)

        illegal: dict[str, np.ndarray] = {}
        inside = self._personal_space(ctx, d, None, scale)
        if inside is not None:
            illegal["personal_space"] = inside
        if self.collision_check:
            # any over time of d² < r² is (min over time of d²) < r²
            assert d2min is not None
            r2 = (radii + robot_r) ** 2
            hit = d2min < r2  # (N, K)
            touching = ((people_now - ctx.pose[:2]) ** 2).sum(axis=1) < r2  # (K,)
            if touching.any():
                # Escape from overlap: against a person already touching the robot, only
                # trajectories that get closer to them are collisions.
                forecast = ctx.people_at(trajs.t)
                hit = hit.copy()
                for j in np.flatnonzero(touching):
                    dj = ((xy - forecast[None, :, j]) ** 2).sum(axis=-1)  # (N, T)
                    hit[:, j] = ~np.all(np.diff(dj, axis=1) >= -1e-12, axis=1)
            illegal["person_collision"] = np.asarray(hit.any(axis=1))
            if self.approach_check:
                illegal["person_approach"] = self._approaches(trajs, ctx, d2min, robot_r)
        return CriticScore(np.ascontiguousarray(cost, dtype=float), illegal)

    def _score_compiled(
        self,
        trajs: Trajectories,
        ctx: PlanningContext,
        d2min: FloatArray,
        reach: FloatArray,
        robot_r: float,
    ) -> CriticScore:
        """:meth:`score` for ``max_over_time`` over every person, on the compiled kernels and
        only over the people that can matter: those whose distances were computed
        (:func:`min_squared_distances`) or whose walk after the rollout can come within
        ``reach``; everyone else is beyond ``reach`` (cost 0, no collision, no approach), as in
        the reference. Bit-identical: the kernels repeat the reference's operations, and the
        people left out contribute 0 to a maximum of non-negative costs."""
        entry = ctx.cache.people_distances
        assert entry is not None and entry.d2min is d2min
        radii = ctx.social.radii()
        k = radii.shape[0]
        computed = entry.covered > -np.inf  # other columns are all inf
        passing = np.zeros(k, dtype=bool)
        start = step = np.zeros((k, 2))
        if self.hold_horizon > 0 and ctx.predict_people:
            start, step, walks = passing_walks(trajs, ctx, self.hold_horizon, reach)
            passing[walks] = True
        cols = np.flatnonzero(computed | passing)
        contact = radii + robot_r
        r2 = contact**2
        touching = np.zeros(k, dtype=bool)
        if self.collision_check:
            touching = ((ctx.social.positions() - ctx.pose[:2]) ** 2).sum(axis=1) < r2
        collide = np.full(cols.size, self.collision_check) & ~touching[cols]
        end = trajs.poses[:, -1, :2]
        d, hit = kernels.person_distances(d2min, cols, end, start, step, passing[cols], r2, collide)
        if self.distance == "edge":
            d = np.maximum(d - radii[cols] - robot_r, 0.0)
        scale = self._distance_scale(ctx)
        if scale is not None:
            d = d * scale[cols][None, :]
        f = capped_inverse_exp(d, self.threshold, self.min_distance)  # (N, J)
        cost = f.max(axis=1, initial=0.0)
        illegal: dict[str, np.ndarray] = {}
        inside = self._personal_space(ctx, d, cols, scale)
        if inside is not None:
            illegal["personal_space"] = inside
        if self.collision_check:
            xy = trajs.xy
            for j in np.flatnonzero(touching):  # escape from overlap, as in the reference
                dj = ((xy - entry.forecast[None, :, j]) ** 2).sum(axis=-1)  # (N, T)
                hit |= ~np.all(np.diff(dj, axis=1) >= -1e-12, axis=1)
            illegal["person_collision"] = hit
            if self.approach_check and self.approach_footprint == "polygon":
                illegal["person_approach"] = self._approaches(trajs, ctx, d2min, robot_r)
            elif self.approach_check:
                illegal["person_approach"] = kernels.approaches(
                    trajs.poses,
                    trajs.t,
                    entry.forecast,
                    d2min,
                    np.flatnonzero(computed),
                    contact,
                    self.approach_speed,
                )
        return CriticScore(np.ascontiguousarray(cost, dtype=float), illegal)

    def _approaches(
        self, trajs: Trajectories, ctx: PlanningContext, d2min: FloatArray, robot_r: float
    ) -> np.ndarray:
        radii = ctx.social.radii()
        if self.approach_footprint == "polygon":
            return footprint_approaches(trajs, ctx, d2min, radii, self.approach_speed)
        return approaches(trajs, ctx, d2min, radii + robot_r, self.approach_speed)


def footprint_approaches(
    trajs: Trajectories,
    ctx: PlanningContext,
    d2min: FloatArray,
    radii: FloatArray,
    speed: float,
) -> np.ndarray:
    """``(N,)`` trajectories whose footprint polygon moves toward a person while touching them.

    ``d2min (N, K)``: :func:`min_squared_distances`, exact within ``radii`` plus the robot's
    circumscribed radius; ``radii (K,)`` the people's (m). At rollout sample ``i`` where the
    footprint (``ctx.robot.polygon``, body frame) overlaps person ``k``'s disc (forecast by
    ``ctx.people_at``), the robot's step into ``i`` or out of ``i`` — translation and turning,
    the person held at their sample-``i`` position — reducing the footprint's signed distance
    to their centre faster than ``speed`` (m/s) makes the trajectory illegal: the rule by which
    ``socialnav.metrics.crowd`` calls a recorded contact *active* (Francis et al. 2023). People
    who never come within the circumscribed reach of any trajectory are skipped.
    """
    n = len(trajs)
    out = np.zeros(n, dtype=bool)
    polygon = ctx.robot.polygon
    reach2 = ((radii + ctx.robot.circumscribed_radius) * (1.0 + 1e-9)) ** 2  # (K,)
    pairs = d2min < reach2[None]  # (N, K)
    near = np.flatnonzero(pairs.any(axis=0))
    if near.size == 0 or trajs.t.shape[0] < 2:
        return out
    forecast = ctx.people_at(trajs.t)  # (T, K, 2)
    dt = np.maximum(np.diff(trajs.t), 1e-9)  # (T-1,)
    last = trajs.t.shape[0] - 1
    for k in near:
        rows = np.flatnonzero(pairs[:, k])
        poses = trajs.poses[rows]  # (R, T, 3)
        # Only samples within the circumscribed reach can touch: judge those alone.
        rel = poses[..., :2] - forecast[None, :, k]
        r_i, t_i = np.nonzero((rel * rel).sum(axis=-1) < reach2[k])  # (M,) each
        if r_i.size == 0:
            continue
        at = forecast[t_i, k]  # (M, 2) the person at sample i, held there
        before, after = np.maximum(t_i - 1, 0), np.minimum(t_i + 1, last)
        # the person seen from the pose at sample i, the pose before it and the pose after it
        q = np.concatenate([poses[r_i, t_i], poses[r_i, before], poses[r_i, after]])
        signed = (
            kernels.signed_distance_to_polygon if kernels.enabled() else signed_distance_to_polygon
        )
        sd = signed(world_to_body_frames(np.tile(at, (3, 1)), q), polygon)
        here, from_before, to_after = sd.reshape(3, -1)
        touch = here < radii[k]
        into = np.where(t_i > 0, (from_before - here) / dt[before], -np.inf)
        leave = np.where(t_i < last, (here - to_after) / dt[np.minimum(t_i, last - 1)], 0.0)
        hit = touch & (np.maximum(into, leave) > speed)
        out[rows[np.unique(r_i[hit])]] = True
    return out


def approaches(
    trajs: Trajectories,
    ctx: PlanningContext,
    d2min: FloatArray,
    contact: FloatArray,
    speed: float,
) -> np.ndarray:
    """``(N,)`` trajectories that move toward a person while in contact with them.

    ``d2min (N, K)``: :func:`min_squared_distances` (exact within ``contact``); ``contact (K,)``
    centre distance (m) below which robot and person touch. At rollout sample ``i`` in contact
    with person ``k`` (forecast by ``ctx.people_at``), the robot's step into ``i`` or out of
    ``i`` closing on ``k`` faster than ``speed`` (m/s) makes the trajectory illegal. People who
    never come within ``contact`` of any trajectory are skipped.
    """
    n = len(trajs)
    out = np.zeros(n, dtype=bool)
    # Only (trajectory, person) pairs that come within contact can be judged illegal; the
    # relative margin keeps this cull conservative against rounding in sqrt.
    reach2 = (contact * (1.0 + 1e-9)) ** 2  # (K,)
    pairs = d2min < reach2[None]  # (N, K)
    near = np.flatnonzero(pairs.any(axis=0))
    if near.size == 0 or trajs.t.shape[0] < 2:
        return out
    forecast = ctx.people_at(trajs.t)  # (T, K, 2)
    dt = np.maximum(np.diff(trajs.t), 1e-9)[None, :, None]  # (1, T-1, 1)
    for k in near:
        rows = np.flatnonzero(pairs[:, k])
        xy = trajs.xy[rows]  # (R, T, 2)
        step = np.diff(xy, axis=1) / dt  # (R, T-1, 2)
        rel = forecast[None, :, k] - xy  # (R, T, 2), robot → person
        dist = np.sqrt((rel * rel).sum(axis=-1))  # (R, T)
        unit = rel / np.maximum(dist, 1e-9)[..., None]
        closing = np.zeros_like(dist)  # the faster of the steps arriving at and leaving i
        closing[:, 1:] = (step * unit[:, 1:]).sum(axis=-1)
        closing[:, :-1] = np.maximum(closing[:, :-1], (step * unit[:, :-1]).sum(axis=-1))
        closing[:, -1] = np.maximum(closing[:, -1], 0.0)  # no step leaves the last sample
        out[rows] |= ((dist < contact[k]) & (closing > speed)).any(axis=1)
    return out

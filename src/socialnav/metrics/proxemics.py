"""Safety and proxemics toward individuals (metrics.md).

Conventions: distances are centre-to-centre unless the name says otherwise; Hall's zones are
intimate < 0.45 m, personal < 1.2 m, social < 3.6 m (scenarios.md). Every metric here is NaN
for a record without people. Shares are fractions of samples (= of time, fixed ``dt``) over the
whole record, using the closest person at each sample.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.episode import EpisodeRecord
from socialnav.core.geometry import wrap_angle
from socialnav.metrics.base import Direction, MetricFn, metric
from socialnav.metrics.series import (
    closest_distance,
    closest_person,
    footprint_gaps,
    person_distances,
    person_headings,
    robot_velocity,
)
from socialnav.social.proxemics import INTIMATE, PERSONAL, SOCIAL

NAN = float("nan")
PASS_THRESHOLD = 0.25  # |winding number| at which a person counts as passed (a 90° sweep)
KIRBY = "Kirby 2010 (asymmetric Gaussian); metrics.md"


def _has_people(record: EpisodeRecord) -> bool:
    return record.people_ids.shape[0] > 0


@metric("min_distance_center", unit="m", direction="max")
def min_distance_center(record: EpisodeRecord) -> float:
    """min_{t,k} |p_t - h_{k,t}|: smallest centre-to-centre robot–person distance."""
    return float(person_distances(record).min()) if _has_people(record) else NAN


@metric("min_distance_edge", unit="m", direction="max")
def min_distance_edge(record: EpisodeRecord) -> float:
    """min_{t,k} (|p_t - h_{k,t}| - r_robot - r_k), r_robot = ``record.robot_radius`` (the
    circumscribed radius, so this is a conservative lower bound on the body gap; negative when
    the circles overlap). See ``min_distance_footprint`` for the exact footprint gap."""
    if not _has_people(record):
        return NAN
    gap = person_distances(record) - record.robot_radius - record.people_radii[None, :]
    return float(gap.min())


@metric("min_distance_footprint", unit="m", direction="max")
def min_distance_footprint(record: EpisodeRecord) -> float:
    """min_{t,k} (sd(h_{k,t}, footprint_t) - r_k), sd = signed distance from the person's centre
    to the robot's (convex) footprint polygon at pose t (negative inside): the body-to-body gap,
    negative on contact."""
    if not _has_people(record):
        return NAN
    return float(footprint_gaps(record).min())


def _zone_share(lo: float, hi: float, zone: str) -> MetricFn:
    def share(record: EpisodeRecord) -> float:
        if not _has_people(record):
            return NAN
        d = closest_distance(record)
        return float(np.mean((d >= lo) & (d < hi)))

    share.__doc__ = (
        f"Share of samples whose closest centre-to-centre distance d satisfies "
        f"{lo} <= d < {hi} m (Hall's {zone} zone; the zones are exclusive bands, so the "
        f"four shares sum to 1)."
    )
    return share


_ZONES: tuple[tuple[str, float, float, Direction], ...] = (
    ("intimate", 0.0, INTIMATE, "min"),
    ("personal", INTIMATE, PERSONAL, "min"),
    ("social", PERSONAL, SOCIAL, "max"),
    ("public", SOCIAL, np.inf, "max"),
)
for _zone, _lo, _hi, _dir in _ZONES:
    metric(f"time_share_{_zone}", unit="1", direction=_dir, reference="Hall 1966")(
        _zone_share(_lo, _hi, _zone)
    )


def _compliance(threshold: float) -> MetricFn:
    def psc(record: EpisodeRecord) -> float:
        if not _has_people(record):
            return NAN
        return float(np.mean(closest_distance(record) >= threshold))

    psc.__doc__ = (
        f"Personal-space compliance: share of samples at which every person is at least "
        f"{threshold} m away (centre-to-centre), i.e. mean_t[min_k d_k(t) >= {threshold}]."
    )
    return psc


for _threshold in (INTIMATE, PERSONAL):
    metric(f"psc_{_threshold}", unit="1", direction="max")(_compliance(_threshold))


@metric("min_time_to_collision", unit="s", direction="max")
def min_time_to_collision(record: EpisodeRecord) -> float:
    """min_{t,k} τ_{k,t}, the time until the robot and person k would touch if both kept their
    velocity of sample t: smallest τ >= 0 with |Δp + Δv τ| = r_robot + r_k, Δp = h - p,
    Δv = v_h - v_p. Robot velocity from forward differences of position, people velocities as
    recorded, r_robot = ``record.robot_radius`` (circumscribed). 0 when already overlapping,
    +inf when no collision is ever predicted, NaN without people."""
    if not _has_people(record):
        return NAN
    dp = record.people_positions - record.robot_xy[:, None, :]
    dv = record.people_velocities - robot_velocity(record)[:, None, :]
    reach = record.robot_radius + record.people_radii[None, :]
    a = np.einsum("tki,tki->tk", dv, dv)
    b = 2.0 * np.einsum("tki,tki->tk", dp, dv)
    c = np.einsum("tki,tki->tk", dp, dp) - reach**2
    disc = b * b - 4.0 * a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = (-b - np.sqrt(np.maximum(disc, 0.0))) / (2.0 * a)
    approaching = (a > 1e-12) & (disc >= 0.0) & (tau >= 0.0)
    tau = np.where(c <= 0.0, 0.0, np.where(approaching, tau, np.inf))
    return float(tau.min())


def winding_numbers(record: EpisodeRecord) -> np.ndarray:
    """w_k = (1/2π) Σ_t wrap(φ_{k,t+1} - φ_{k,t}), φ_{k,t} = atan2 of (h_{k,t} - p_t): ``(K,)``.

    Positive when the bearing to person k turned counter-clockwise, i.e. the person went by on
    the robot's left."""
    rel = record.people_positions - record.robot_xy[:, None, :]
    phi = np.arctan2(rel[..., 1], rel[..., 0])
    return wrap_angle(np.diff(phi, axis=0)).sum(axis=0) / (2.0 * np.pi)


@metric("winding_number", unit="1", direction="max", reference="metrics.md")
def winding_number(record: EpisodeRecord) -> float:
    """w of the closest person (see ``winding_numbers``); +0.5 for a full pass with the person on
    the robot's left, -0.5 on its right. NaN without people."""
    j = closest_person(record)
    return NAN if j is None else float(winding_numbers(record)[j])


@metric("passing_side", unit="1", direction="max", reference="metrics.md")
def passing_side(record: EpisodeRecord) -> float:
    """Passing side of the closest person from its winding number w: +1 ("left": the person went
    by on the robot's left, i.e. the robot kept to the right — the hallway norm) when
    w >= 0.25, -1 ("right") when w <= -0.25, 0 (no pass: the bearing swept less than 90°).
    "max" is better only in the sense of the keep-right norm. NaN without people."""
    w = winding_number(record)
    if np.isnan(w):
        return NAN
    return float(np.sign(w) if abs(w) >= PASS_THRESHOLD else 0.0)


def kirby_intrusion(record: EpisodeRecord) -> np.ndarray:
    """Kirby's asymmetric Gaussian of each person evaluated at the robot centre ``(T, K)`` in
    [0, 1]: exp(-x²/(2σ_x²) - y²/(2σ_s²)) with (x, y) the robot in the person's frame (x along
    the person's heading), σ_h = max(2|v|, 0.5), σ_s = 2σ_h/3, σ_r = σ_h/2 and σ_x = σ_h in
    front (x > 0), σ_r behind. Heading: velocity direction, or the person's yaw when still."""
    rel = record.robot_xy[:, None, :] - record.people_positions
    heading = person_headings(record)
    c, s = np.cos(heading), np.sin(heading)
    x = c * rel[..., 0] + s * rel[..., 1]
    y = -s * rel[..., 0] + c * rel[..., 1]
    sigma_h = np.maximum(2.0 * np.linalg.norm(record.people_velocities, axis=-1), 0.5)
    sigma_x = np.where(x > 0.0, sigma_h, sigma_h / 2.0)
    sigma_s = 2.0 * sigma_h / 3.0
    return np.exp(-(x**2) / (2.0 * sigma_x**2) - y**2 / (2.0 * sigma_s**2))


@metric("kirby_intrusion_max", unit="1", direction="min", reference=KIRBY)
def kirby_intrusion_max(record: EpisodeRecord) -> float:
    """max_{t,k} of Kirby's asymmetric Gaussian at the robot centre (see ``kirby_intrusion``);
    1 = on top of a person. NaN without people."""
    return float(kirby_intrusion(record).max()) if _has_people(record) else NAN


@metric("kirby_intrusion_mean", unit="1", direction="min", reference=KIRBY)
def kirby_intrusion_mean(record: EpisodeRecord) -> float:
    """mean_t max_k of Kirby's asymmetric Gaussian at the robot centre over the whole record.
    NaN without people."""
    return float(kirby_intrusion(record).max(axis=1).mean()) if _has_people(record) else NAN

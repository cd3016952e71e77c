"""Named planner configurations: which objectives, which selection, which social goal.

- ``traditional``: the ROS planner — one navigation objective, weighted sum, the given goal.
- ``proxemic_layer``: the traditional planner on a costmap with the social_navigation_layers
  proxemic Gaussian of every person (what a ROS user does today); still drives to the given goal.
- ``weighted_social``: the social objectives of ``paccet`` combined by a weighted sum — the
  alternative the paper argues against.
- ``paccet_paper``: the paper-faithful configuration — one ``ID`` objective per person (up to
  three nearest), ``GD`` when there is a group, ``SGD`` when a social goal applies, all measured at
  the trajectory's end point against people where they are now; a fresh archive every cycle, the
  reference weights (0.4, 0.5, 0.5, 0.5, 0, 1) over (navigation, ID1..3, GD, SGD) on the
  transformed values, and the reference PaCcET behaviour (parity bisections, absolute delta,
  no degeneracy remedies).
- ``paccet``: our recommended configuration, each choice measured on the scenario suite (the
  README and the issue notes give the numbers): people forecast along the rollout; PaCcET with
  its degeneracy remedies and an L1 target on the flattened front (the reference weights always
  pick an extreme of the front, and the robot stalls outside 1.5 m of a person in a 3 m
  corridor); a global path over a personal-space cost and the groups' o-spaces; the social-goal
  objective only near the social goal; activity-space intrusion as an objective; interaction
  partners at the interaction's own distance in ID (``partner_objectives``); arrival inside
  ``RECOMMENDED_SPOT_TOLERANCE`` at social spots; rollouts that stop at the goal
  (``LocalPlannerParams.stop_at_goal``) inside a 0.07 m tolerance; walkers' passing distance
  in ID (``PASSING_HORIZON``); the approach rule on the footprint polygon, turning included
  (``InterpersonalCritic.approach_footprint``, ``partner_objectives``); the goal term along the
  plan (``LocalPlannerParams.goal_distance_measure``, ``RECOMMENDED_PARAMS``); a floor on the
  social objectives' normalizing ranges (``SOCIAL_INDIFFERENCE``,
  ``PaccetOptions.indifference``). ``params``
  passed to :func:`build_navigator` replace the preset's whole ``LocalPlannerParams``: start
  from ``dataclasses.replace(RECOMMENDED_PARAMS, ...)`` to change one field of ``paccet``.
  These were measured on the generated suite's development seeds
  (``benchmarks/tune_generated.py``) and Table 1. Measured and left off: walkers' personal
  space where the robot can meet them and replan hysteresis (``MEETING_LAYER``,
  ``RECOMMENDED_HYSTERESIS``; ``benchmarks/time_breakdown.py``).

Deviation shared by all social presets: navigation steers to the social goal (the Navigator
plans to it); the paper kept the given goal and let ``SGD`` pull toward the social goal, so its
robot would never report reaching the tail of a queue.

The objective set follows the scene, as in the paper: 2 objectives in the hallway, 3 in the
gallery, 5 in the queue.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from socialnav.core.errors import (
    ConfigurationError,
    InvalidInputError,
    checked_bool,
    is_non_negative_number,
    with_overrides,
)
from socialnav.core.geometry import FloatArray
from socialnav.core.registry import Registry
from socialnav.core.robot import RobotModel
from socialnav.core.scene import HUMAN_RADIUS, Person, SocialContext
from socialnav.moo.paccet import PaccetOptions
from socialnav.moo.scalarize import L1Target, Weighted
from socialnav.moo.selection import PaccetSelection, SelectionStrategy, WeightedSum
from socialnav.planner import kernels
from socialnav.planner.contact_guard import ContactGuardParams
from socialnav.planner.context import PlanningContext
from socialnav.planner.critics.activity_space import ActivitySpaceCritic
from socialnav.planner.critics.group import GroupCritic
from socialnav.planner.critics.interpersonal import InterpersonalCritic
from socialnav.planner.critics.social_goal import SocialGoalCritic
from socialnav.planner.global_planner import GlobalSearch
from socialnav.planner.local_planner import (
    LocalPlanner,
    LocalPlannerParams,
    traditional_objectives,
)
from socialnav.planner.navigator import CostmapLayer, MeetingLayer, Navigator, ReplanMode
from socialnav.planner.objectives import Objective, with_indifference
from socialnav.planner.recovery import RecoveringPlanner, RecoveryParams
from socialnav.social.goals import SocialGoal
from socialnav.social.proxemics import PERSONAL
from socialnav.world.grid import Costmap, GridGeometry

# The reference navigation code's scalarization weights, by objective kind.
PAPER_WEIGHTS = {"navigation": 0.4, "ID": 0.5, "GD": 0.0, "SGD": 1.0, "AS": 0.5}
PAPER_MAX_PEOPLE = 3
# SGD acts within this distance (m) of the social goal: close enough to overcome the ID cost of
# the people the robot joins, far enough that it never pulls the robot through their group.
SGD_ACTIVE_WITHIN = 2.5
# The rolling local costmap (m, square): ROS configurations use 4–6 m. The goal-distance critic
# seeds its grid at the last plan point inside it, so a smaller window keeps the local goal on
# the global path instead of pulling straight across (e.g. through a group) to a goal in view.
LOCAL_WINDOW = 5.0


@dataclass(frozen=True)
class PlannerPreset:
    """How to build one named planner; ``objectives`` maps a scene to objectives + weights;
    ``order`` places it in listings and reports (ascending, baselines first)."""

    description: str
    objectives: Callable[[SocialContext, bool, LocalPlannerParams], list[tuple[Objective, float]]]
    selection: Callable[[list[float]], SelectionStrategy]
    social_goal: bool = False
    proxemic_layer: bool = False
    social_global_path: bool = False
    predict_people: bool = True
    params: LocalPlannerParams = field(default_factory=LocalPlannerParams)
    #: (m, rad) replacing the social goal's own arrival tolerances; None keeps them
    spot_tolerance: tuple[float, float] | None = None
    order: int = 1000
    recovery: RecoveryParams = field(default_factory=RecoveryParams)
    #: with ``social_global_path``: walkers' personal space drawn where the robot can meet
    #: them (:func:`meeting_space_layer`), not where they are now
    meeting_layer: bool = False
    #: ``Navigator.replan_hysteresis``: keep the plan unless a new one is this much cheaper
    replan_hysteresis: float = 0.0
    #: ``Navigator.detour_limit`` with ``social_global_path``: a social plan more than this
    #: fraction longer than the plan around standing people only (:func:`standing_space_layer`:
    #: people slower than ``MEETING_LAYER["min_speed"]``, 0.3 m/s, and the o-spaces) gives way
    #: to that plan (``DETOUR_LIMIT``); 0: off (and without ``social_global_path``)
    detour_limit: float = 0.0
    #: ``Navigator.contact_guard``: no command closes the footprint on a person it touches
    #: (:mod:`~socialnav.planner.contact_guard`); None: off
    contact_guard: ContactGuardParams | None = None
    #: ``Navigator.partner_spacing``: the social goal's interaction partners at the
    #: interaction's own distance in the global plan (``PARTNER_SPACING``); acts only on the
    #: ``social_global_path`` layers (not with ``proxemic_layer``, whose layer has no partners)
    partner_spacing: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.recovery, RecoveryParams):
            raise ConfigurationError(
                f"planner preset {self.description!r}: recovery must be a RecoveryParams, got"
                f" {type(self.recovery).__name__}"
            )
        for name in ("replan_hysteresis", "detour_limit"):
            value = getattr(self, name)
            if not is_non_negative_number(value):
                raise ConfigurationError(
                    f"planner preset {self.description!r}: {name} must be a finite number >= 0,"
                    f" got {value!r}"
                )
        spacing = checked_bool(
            self.partner_spacing, f"planner preset {self.description!r}: partner_spacing"
        )
        object.__setattr__(self, "partner_spacing", spacing)


PRESETS: Registry[PlannerPreset] = Registry("planner preset")


def has_social_goal(social: SocialContext) -> bool:
    """Scenes whose structure may yield a social goal (queue, standing group, artwork with a
    viewer, a structure of a registered kind); walking groups never do."""
    return bool(
        social.queues
        or any(not g.is_walking for g in social.groups)
        or social.structures
        or any(a.viewer_ids for a in social.artworks)
    )


def navigation_only(
    social: SocialContext, social_goal: bool, params: LocalPlannerParams
) -> list[tuple[Objective, float]]:
    """The single navigation objective (the traditional planner)."""
    return [(traditional_objectives(params)[0], 1.0)]


def paper_objectives(
    social: SocialContext, social_goal: bool, params: LocalPlannerParams
) -> list[tuple[Objective, float]]:
    """Navigation, ID per person (≤ 3), GD if a group, SGD if a social goal; end-point rule."""
    out = [(traditional_objectives(params)[0], PAPER_WEIGHTS["navigation"])]
    for k in range(min(PAPER_MAX_PEOPLE, len(social.people))):
        critic = InterpersonalCritic(person_slot=k, evaluation="last")
        out.append((Objective(f"ID{k + 1}", ((critic, 1.0),)), PAPER_WEIGHTS["ID"]))
    if social.groups:
        out.append((Objective("GD", ((GroupCritic(evaluation="last"), 1.0),)), PAPER_WEIGHTS["GD"]))
    if social_goal:
        out.append((Objective("SGD", ((SocialGoalCritic(), 1.0),)), PAPER_WEIGHTS["SGD"]))
    return out


def recommended_objectives(
    social: SocialContext,
    social_goal: bool,
    params: LocalPlannerParams,
    partner_distance: bool = False,
    hold_horizon: float = 0.0,
    approach_footprint: Literal["disc", "polygon"] = "disc",
    social_indifference: float = 0.0,
    passage_distance: bool = False,
    personal_space: float = 0.0,
) -> list[tuple[Objective, float]]:
    """Navigation (to the social goal), one ID over all people forecast along the rollout, GD,
    SGD near the social goal, activity space; ``partner_distance``: the people the social goal
    is about get the interaction's own distance in ID; ``hold_horizon`` (s): ID counts the
    passing distance of walkers past the end point (both: ``InterpersonalCritic``);
    ``social_indifference``: every social objective's ``Objective.indifference``;
    ``passage_distance``: people standing beside a narrow passage keep the passage's own
    distance in ID; ``personal_space`` (m, 0 = off): ID also prefers, for a holonomic robot
    among few people, the trajectories that keep out of everyone's personal space
    (``InterpersonalCritic.personal_space``, ``PREFERRED_PERSONAL_SPACE``)."""
    q = social_indifference
    out = [(traditional_objectives(params)[0], PAPER_WEIGHTS["navigation"])]
    if social.people:
        interpersonal = InterpersonalCritic(
            evaluation="max_over_time",
            partner_distance=partner_distance,
            hold_horizon=hold_horizon,
            approach_footprint=approach_footprint,
            passage_distance=passage_distance,
            personal_space=personal_space,
            personal_space_kinematics="holonomic",
        )
        out.append((Objective("ID", ((interpersonal, 1.0),), q), PAPER_WEIGHTS["ID"]))
    if social.groups:
        group = GroupCritic(evaluation="max_over_time", illegal_inside=True)
        out.append((Objective("GD", ((group, 1.0),), q), PAPER_WEIGHTS["ID"]))
    if social_goal:
        # SGD only within 2 m of the social goal: farther away, navigation (which steers to the
        # social goal around people) leads and exp(SGD) cannot pull the robot through a group.
        sgd = SocialGoalCritic(relative=True, active_within=SGD_ACTIVE_WITHIN)
        out.append((Objective("SGD", ((sgd, 1.0),), q), PAPER_WEIGHTS["SGD"]))
    if any(a.viewer_ids for a in social.artworks):
        activity = ActivitySpaceCritic(measure="max_depth")
        out.append((Objective("AS", ((activity, 1.0),), q), PAPER_WEIGHTS["AS"]))
    return out


def partner_objectives(
    social: SocialContext,
    social_goal: bool,
    params: LocalPlannerParams,
    personal_space: float | None = None,
) -> list[tuple[Objective, float]]:
    """:func:`recommended_objectives` with interaction partners at their own distance, the
    walkers' passing distance (``PASSING_HORIZON``) and the approach rule on the footprint
    polygon (``InterpersonalCritic.approach_footprint``: turning counts). Recorded crowds, dev
    seeds 0–89, both recordings and robots (360 episodes): successes 315 → 347, episodes with
    an active contact 41 → 9, with a passive one 101 → 108 (giving way's approach test on the
    polygon too); generated dev seeds 0–19, every family: 348 of 360 passes either way.

    People standing beside a narrow passage keep the passage's own distance
    (``InterpersonalCritic.passage_distance``). Dev seeds, against without: hallway 0–199
    Pioneer 183 → 184 of 200, PR2 187 → 187, collision runs 2 and 6 either way, time on the
    scenes both pass −0.8 % and −5.0 %; crowdnav, crowdnav_visible and mixed 0–59 356 → 356
    of 360 (time −0.7 to +0 %); recorded crowds 0–89 354 → 354 of 360 successes, active- and
    passive-contact episodes 3 and 112 either way. Measured and not kept on hallway 0–199: the
    plan's own distance from them less 0.05 m (Pioneer 182, PR2 183: a plan through the
    Gaussian's cheap side passes closer than the corridor requires, 7 personal-space
    failures); the free distance past the plan's nearest point, away from them (186 and 187,
    but 2 new personal-space failures where the corridor allowed 1.25 m and 1 new timeout:
    the side the plan takes decides the room, not the corridor); the widest path
    over the local costmap (184 and 186: a robot already in a gap only ever sees the gap).

    ``personal_space`` (m; ``None``: ``PREFERRED_PERSONAL_SPACE``; 0 switches the rule off):
    a preset without it is
    ``dataclasses.replace(PRESETS.get("paccet"), description="paccet without the personal
    space preference", objectives=functools.partial(partner_objectives,
    personal_space=0.0))``, registered with ``socialnav.sim.stack.register_preset`` (for the
    CLI, in a script that then calls ``socialnav.cli.app()``: docs/extending.md)."""
    return recommended_objectives(
        social,
        social_goal,
        params,
        partner_distance=True,
        hold_horizon=PASSING_HORIZON,
        approach_footprint="polygon",
        social_indifference=SOCIAL_INDIFFERENCE,
        passage_distance=True,
        personal_space=PREFERRED_PERSONAL_SPACE if personal_space is None else personal_space,
    )


#: ``paccet``'s personal space as a preference in ID (m; ``InterpersonalCritic.personal_space``,
#: ``objectives.PREFERRED_REASONS``): a holonomic robot among at most 3 people within 10 m, one
#: of whom walks (0.3 m/s or faster), keeps to the trajectories that stay 1.2 m (centre to
#: centre) from everyone now farther away, or their own distance where that is less (partners,
#: people beside a narrow passage), while there is one. With ID alone the PR2 drove on beside
#: a walker at 1.14 m for ten seconds (generated hallway dev seed 97), or past someone standing
#: at 0.90 m on the wall side while the other side had room once a walker overtaking there had
#: gone by (seed 107). Generated hallway dev seeds 0–199, passes of 200 (Pioneer / PR2): 191 /
#: 190 without; the rule for both robots, standing people alone included, 188 / 193 (PR2
#: gained 86, 97, 107, 152, lost 38; the Pioneer lost 2, 19, 40, 129 and gained 131: with
#: every move ahead inside someone's space, turning round and driving away remained, and twice
#: it was then left facing away against a wall); the same with the Pioneer's moves that end
#: farther from the goal also marked, Pioneer 181; walkers' personal space only, 188 / 191.
#: Kept for the holonomic robot only (the Pioneer is unchanged). With standing people alone the
#: PR2 stood 1.21 m from a gallery viewer it had to pass until the time limit (gallery_pass dev
#: 0–59: 60 → 57), hence only while someone walks: PR2 dev 0–59 gallery_present, gallery_pass,
#: queue, group_join, group_lead and mixed unchanged (58, 60, 60, 60, 60, 60 passes), crowdnav
#: and crowdnav_visible too (58, 60; five people), hallway 0–199 193 (time on the scenes both
#: pass +0.7 %). Recorded crowds dev 0–89, PR2: successes 180 → 180, active-contact episodes
#: 0 → 0, passive 50 → 51, time within 1.2 m 6.18 → 6.19 s, path ratio 1.317 → 1.321.
#: Paper suite 34/34, Table 1 unchanged. (Measured first with partners and passages at 1.2 m
#: times their own distance over 1.5 m, i.e. 1.0 m beside a passage that allows 1.25 m: hallway
#: the same 193.)
PREFERRED_PERSONAL_SPACE = 1.2


#: ``paccet``'s indifference threshold on every social objective (raw units; ID and GD are
#: ``exp(1/d)``, where 0.001 is about 1 mm of distance at the 1.5 m threshold and less nearer):
#: a smaller range over the archive is raised to it (``PaccetOptions.indifference``), so a
#: 1e-6 difference no longer weighs as much as navigation's whole range. Generated dev seeds
#: 0–59, both robots: 1051 → 1053 of 1080 (crowdnav 34 and crowdnav_visible 46 on the Pioneer
#: stopped dithering beside someone standing still), time on the scenes both pass unchanged;
#: recorded crowds dev 0–89: successes 345 → 345, active-contact episodes 9 → 8, passive
#: 109 → 108. 0.01 gained the same two generated scenes but lost crowds: 340, 11, 112. Also
#: tried and not kept: dropping archive members beaten by more than the threshold
#: (epsilon-dominance) — a robot in a corridor test then stopped 1.5 m short of a person.
#: Measured and not kept: ID made continuous at its threshold (``exp(1/d) - exp(1/1.5)``, so a
#: walker forecast at 1.49 m no longer costs as much as one at 1.2 m against 0 at 1.51 m).
#: Generated dev seeds 0–59 of crowdnav, crowdnav_visible, hallway and mixed, both robots:
#: passes 472 → 467, collision runs 2 → 4, time ratio to hl crowdnav 1.27 → 1.29 (Pioneer),
#: mixed 1.45 → 1.48; with this indifference at 0.1: 469 passes, 3 collision runs, ratios
#: within ±0.05 (mixed PR2 1.35 → 1.30).
SOCIAL_INDIFFERENCE = 0.001


#: ``paccet``'s ID looks this long (s) past the rollout for walkers passing its end point
#: (``InterpersonalCritic.hold_horizon``), so standing still is not preferred to moving on only
#: because the closest approach falls after the rollout (Table 1 PR2 time 11.5 s without, 11.0 s
#: with). 3 s: the Pioneer stopped in hallway_oncoming's lane and the walker passed at 0.95 m;
#: 2 s and below: the PR2 of navground's Cross example froze mid-crossing and reached no target.
#: It also makes the robot yield early to walkers far ahead (mixed dev seed 73, Pioneer: it
#: stopped with the walker 6.9 m away and stood 6 s while they crossed its way). Measured and
#: not kept, generated dev seeds 0–59 of crowdnav, crowdnav_visible, hallway and mixed, both
#: robots (472 passes, 2 collision runs): ID's threshold 1.3 m for everyone walking (0.3 m/s
#: or faster), 472 passes, 3 collision runs, time ratio to hl crowdnav PR2 1.20 → 1.17 and
#: mixed PR2 1.35 → 1.27, but crowdnav_visible and mixed on the Pioneer unchanged (1.31 →
#: 1.32, 1.45 → 1.46).
PASSING_HORIZON = 2.5
#: ``paccet``'s arrival at a social spot (m, rad): inside the generated suite's 0.10 m / 0.2 rad
#: (the social goals' default 0.25 m / 0.25 rad ends 0.24–0.25 m from the spot)
RECOMMENDED_SPOT_TOLERANCE = (0.07, 0.15)
#: ``paccet``'s local-planner parameters: rollouts that stop at the goal (no slow final approach:
#: Table 1 time 14.4 → 10.5 s Pioneer, 15.2 → 11.0 s PR2) and a 0.07 m xy tolerance on the given
#: goal too (at 0.10 m the robot stopped on the edge of the suite's 0.10 m and a generated
#: hallway failed ``reached_goal`` by 0.5 mm). navground's Cross and Corridor examples, where
#: ``stop_at_goal`` once ended in a collision, pass without contact in this configuration.
#: The goal term measures the plan's length still to go (``goal_distance_measure``,
#: ``critics.plan_progress``): generated dev seeds 0–59, every family, both robots, 1045 →
#: 1051 of 1080 passes (Pioneer stalls short of a goal reached from the side fixed in
#: gallery_pass, group_join and crowdnav_visible; 3 crowdnav Pioneer runs now time out waiting
#: beside someone standing still); time on the scenes both pass +0–9 % (the PR2 no longer cuts
#: the plan's corners: +6.7 % summed, Pioneer +1 %); recorded crowds dev 0–89 347 → 345
#: successes, active-contact episodes 9 → 9; paper suite 34/34, Table 1 PR2 time 10.9 → 11.9 s
#: (+2.9 % over traditional). Legality stays the goal distance's (``unreachable``): without
#: it the robot crept up to a person blocking a 1 m corridor instead of waiting.
#: A holonomic base turns to the goal's yaw on the way in (``heading_goal_align``,
#: ``critics.heading``): once the goal is within its rollouts' reach, every rollout's heading
#: is scored against the goal's yaw. Before, the plan's last grid segment had turned the PR2 up
#: to 1.4 rad away from it in the last metre, then it turned in place for up to 2.4 s.
#: Generated dev seeds 0–39, every family, PR2: passes 357 → 357, collision runs 1 → 1; the
#: turn in place at the goal 0.0–0.7 s instead of 1.0–2.4 s per family, so the episode until
#: ``GOAL_REACHED`` ends 0.8–2.4 s sooner; time to goal (the xy tolerance held) −0.07 to
#: +0.05 s. Recorded crowds dev 0–89, PR2: 180 successes and 0 active-contact episodes as
#: before, passive 51 → 50, time within 1.2 m 6.40 → 6.18 s, path ratio 1.32 → 1.32. A first
#: version (the goal's yaw as the plan's last tangent, and within 0.5 m only) slowed a PR2
#: down 1 m short of a goal facing back the way it came (newcomer trial): only the rollouts
#: reaching the plan's end were judged by the goal's yaw. Measured for the Pioneer too and
#: not kept: generated dev passes 357 → 357 with its turn in place 0.4–0.7 s shorter, but
#: recorded crowds dev successes 179 → 177, active-contact episodes 0 → 1, time to goal
#: 27.9 → 28.9 s (it bends its path to turn). Paper suite 34/34, Table 1 unchanged.
#: Rollouts that cannot brake (each sample held for ``sim_time``: a robot at full speed never
#: sees a stop until it has slowed down) measured against two remedies, generated dev seeds
#: 0–59 of crowdnav, crowdnav_visible, hallway and mixed, both robots (shipped: 472 passes,
#: 2 collision runs; mean time ratio to hl over the scenes both pass, crowdnav Pioneer / PR2,
#: crowdnav_visible, mixed: 1.27 / 1.20, 1.31 / 1.24, 1.45 / 1.35), neither kept:
#: one extra rollout per turn rate decelerating to a stop at ``acc_lim_x`` whenever the
#: window excludes standstill: 470 passes, 2 collision runs, 1.25 / 1.20, 1.31 / 1.24,
#: 1.40 / 1.33, but recorded crowds dev (first 239 of 360 episodes) 4 failures and 2
#: active-contact episodes where the shipped loop has 1 and 0 over all 360; ROS's
#: trajectory-rollout mode (``dwa: false``: the window over ``sim_time``, each rollout ramping
#: toward its sample at the acceleration limits; it also ends the Pioneer's turns in place
#: the long way round, mixed dev 56): 466 passes (hallway 116 → 111), 3 collision runs,
#: 1.24 / 1.21, 1.31 / 1.22, 1.37 / 1.33.
RECOMMENDED_PARAMS = LocalPlannerParams(
    stop_at_goal=True,
    xy_goal_tolerance=0.07,
    goal_distance_measure="along_plan",
    heading_goal_align=True,
)


#: The replan hysteresis measured with the meeting layer (``PlannerPreset.replan_hysteresis``;
#: both are off in ``paccet``, see ``MEETING_LAYER``): keep the plan unless a new one costs
#: this fraction less on the new costmap. Development seeds 0–19 of crowdnav,
#: crowdnav_visible, hallway and mixed, both robots, meeting layer at timing (1, 0.25), before
#: the evasion of ``RECOMMENDED_RECOVERY``: 146 of 160 passes at 0, 148 at 0.15, 149 at 0.3.
RECOMMENDED_HYSTERESIS = 0.3


#: ``paccet``'s control loop: evasion also when a walker's closest approach under the chosen
#: command falls inside the 1.2 m personal space within 4 s, and evasive moves that step out
#: of the walkers' lanes and hold there, judged over the whole encounter
#: (``RecoveryParams.evasion_personal_distance``, ``evasion_hold_step``). Generated dev seeds
#: 0–19, hallway + crowdnav + crowdnav_visible, both robots: 105 → 111 of 120 passes, collision
#: runs 4 → 1, no crowdnav timeout added (the saturated gap lets progress decide once clear).
#: A larger evasion_personal_distance (trigger and saturation alike) does not help: hallway dev
#: seeds 0–39, both robots, passes 69 (1.2 m), 70 (1.3 m), 68 (1.4 m, 2 collision runs); the
#: near misses (1.12–1.19 m) stay.
#: Measured and not adopted (commit 215af6d, reverted): timing the passes (a second
#: move-and-hold after the first walker, i.e. wait beside one wall, then cross; the plan kept
#: while it stays as clear; the gap saturating 0.05 m beyond the personal distance, ties only
#: at saturation once some move reaches it): hallway dev seeds 0–99, both robots,
#: 166 → 168 of 200 (PR2 85 → 88, Pioneer 81 → 80; 5 gained, 3 lost), collision runs 4 → 3;
#: the other families' dev seeds 0–11 unchanged (189 of 192). Measured without the kept plan,
#: each part alone stayed at 165–166 of 200: second moves only 165, the margin and strict ties
#: only 165, all but the kept plan 166 (the choice flipped between lanes from cycle to cycle).
#: Judging the planner's own command kept over the whole encounter (not driven for 1 s and
#: held) lost passes: 154 of 200, 8 collision runs.
#: Reporting split, hallway seeds 10000–10199, run once after: Pioneer 168 → 171, PR2 164 → 168
#: of 200, collision runs 11 → 10. Recorded crowds dev seeds 30–89: successes 209 → 211 of
#: 240. Its cost: the crowd suite's step p99 5.7 → 10.7 ms (``bench_suite_step.py``, deferred
#: replan), for a gain within the dev split's noise.
#: Measured on the recorded crowds and not adopted (paccet's passive-contact episodes and
#: successes, both recordings and robots, contacts judged on the centre's velocity as then;
#: dev seeds 0–29 = 120 episodes: 37 and 117 shipped; 30–89 = 240: 77 and 235 shipped):
#: giving way also while rotating to the goal, 42 and 113 (ttc trigger only: 39 and 116; it
#: delays finishing and new walkers arrive); every walker also forecast at its heading
#: ±0.35 rad, 53 and 115; evasion_personal_distance 0.9 m, 44 and 113; gaps discounted by
#: 0.1 m per second ahead, 41 and 114 (30–89: 78 and 234); the approach check at the mean of
#: the inscribed and circumscribed radii (30–89) 76 and 229, active 3 → 8; evasion_hold_step
#: 0.5 s (30–89) 83 and 231. With active contacts judged on the footprint (as now; shipped:
#: 0–29 34 passive, 11 active, 106 successes; 30–89 67, 30, 209), a turn guard that drops a
#: command's turn (or stops) when it would sweep the footprint into someone within 0.2 m:
#: 0–29 39, 5, 111; 30–89 74, 19, 220 (fewer active contacts, more passive ones); within
#: 0.05 m: 30–89 67, 27, 212. Adopted instead: the approach rule on the footprint polygon, in
#: the planner's critic and giving way's test alike (``partner_objectives``): 0–29 36, 3, 115;
#: 30–89 72, 6, 232.
#: ``paccet``'s timed passing (``RecoveryParams.passing_distance``; ``planner.passing``):
#: command sequences over 6 s that keep every person's centre 1.25 m away (1.2 m personal space
#: plus a margin for the gap between the search's 0.1 s samples and the loop's) and end where
#: the robot can stop untouched, the plan still to go traded 10 m per m of clearance short of
#: 1.5 m. Generated hallway dev seeds 0–59, both robots: 102 → 111 of 120 passes (12 gained,
#: all personal-space failures, 3 Pioneer runs lost to the time limit), time on the scenes
#: both pass +3.4 %; dev seeds 0–29 of crowdnav, crowdnav_visible and mixed: 178 → 178.
#: Paper suite 34/34; Table 1 D_l 1.51 → 1.56 m (Pioneer) and 1.44 → 1.50 m (PR2), time
#: 11.94 → 10.58 s on the PR2. Measured and not kept: the plan still to go alone (no
#: clearance term), D_l 1.34 / 1.28 m; weight 6 with a beam of 60 scored on progress only,
#: hallway 114 but PR2 D_l 1.38 m; a beam of 150 with every coarse cell kept, 60–70 ms per
#: search (step p99 60 ms); no gate on the people near: recorded crowds dev seeds 0–89
#: successes 345 → 327, active-contact episodes 8 → 22 (constant-velocity forecasts of
#: recorded pedestrians do not hold for 6 s), hence ``passing_max_people`` within 10 m.
#: Measured and not kept: when no sequence keeps 1.25 m, a second search at 1.21 m before
#: giving way (every dev hallway failure of ``no_personal_space_intrusion`` has a lattice path
#: whose closest approach is 1.20–1.76 m, 12 of 16 at 1.20–1.22 m;
#: ``benchmarks/hallway_feasibility.py``): hallway dev seeds 0–199 Pioneer 191 → 188, PR2
#: 190 → 191 of 200 (the 0.1 s samples pass nearer than the search's 1.21 m). Measured and
#: not kept: 1.3 m (5 of the 18 reporting-split hallway runs, both robots, that broke the
#: personal space came within 1.16–1.197 m): hallway dev seeds 0–199 Pioneer 191 → 183, PR2
#: 190 → 189.
PASSING_DISTANCE = 1.25
#: ``paccet``'s detour limit (``Navigator.detour_limit``): a social plan more than 1.5 times as
#: long as the plan around standing people only (slower than 0.3 m/s, ``MEETING_LAYER``'s
#: ``min_speed``; people slowing down to their goals count as standing) is replaced by that
#: plan. Switched off per run with ``StackController("paccet", detour_limit=0.0)`` or
#: ``build_navigator(..., detour_limit=0.0)``. Generated crowdnav
#: (five people crossing toward the centre of the robot's run): the plan around their forecast
#: lanes was 2–2.5 times as long, and the Pioneer turned round to follow it; hallway plans
#: are mostly within 1.25 times (at most about 1.5). Development seeds 0–59 of hallway,
#: crowdnav, crowdnav_visible and mixed, both robots (480 runs), and recorded crowds dev seeds
#: 0–89 (360 episodes), limit: passes, collision runs; mean time ratio to hl over the scenes
#: both pass, crowdnav Pioneer/PR2, crowdnav_visible, mixed; crowd successes, active- and
#: passive-contact episodes, time within 1.2 m (s), path length ratio:
#: off: 466, 3; 1.54/1.53, 1.63/1.61, 1.59/1.46; 343, 11, 108, 6.21, 1.45.
#: 0.15: 467, 2; 1.26/1.17, 1.28/1.22, 1.41/1.28; 344, 13, 113, 6.89, 1.25.
#: 0.3: 466, 4; 1.26/1.18, 1.29/1.23, 1.44/1.31; 347, 9, 108, 6.54, 1.29.
#: 0.5 (kept): 467, 3; 1.27/1.20, 1.33/1.25, 1.50/1.37; 351, 4, 108, 6.38, 1.33.
#: 1.0: 466, 3; 1.37/1.36, 1.50/1.45, 1.54/1.40; 343, 9, 102, 6.35, 1.42.
#: No walkers in the global plan at all (``standing_space_layer``): hallway 111 → 106 of 120
#: with 5 collision runs, crowds 347, 9, 134, 7.52, 1.24. The smaller limits shorten the crowd
#: paths but take the robot nearer people; 0.5 has the most crowd successes and the fewest
#: active contacts, at time ratios 0.01–0.12 above 0.15's.
#: Measured again with the contact guard (before its brake for people who just appeared;
#: recorded crowds dev seeds 0–89: successes, active- and passive-contact episodes, time within
#: 1.2 m, path ratio; generated dev seeds 0–59, mean time ratio to hl over the scenes both
#: pass, crowdnav Pioneer/PR2, crowdnav_visible, mixed, the same pass counts): 0.5: 358, 1,
#: 112, 6.51 s, 1.31; 1.27/1.20, 1.31/1.25, 1.47/1.36. 0.3: 356, 3, 113, 6.69 s, 1.28;
#: 1.25/1.18, 1.28/1.23, 1.43/1.31. 0.15: 356, 4, 113, 6.98 s, 1.24. The limit measured
#: against the standing plan's length plus 0.3 × the straight line (not 1.3 × the standing
#: plan, which is itself long round a group to be joined): mixed 1.41/1.29. Still a trade of
#: time near people and contacts for path length; kept at 0.5.
#: Measured and not adopted: a cap in metres beside the fraction (the social plan also gives
#: way when it is more than D m longer than the standing plan; the case: generated mixed dev
#: seed 23, where the Pioneer took a 15.6 m plan round the group's far side instead of a 10.6
#: m one, 39 s to the goal against hl's 12 s). Generated dev seeds 0–59 of crowdnav,
#: crowdnav_visible, hallway and mixed, both robots: 472 passes and 2 collision runs for every
#: D; mean time ratio to hl, crowdnav Pioneer/PR2, crowdnav_visible, mixed; recorded crowds dev
#: 0–89: successes, active- and passive-contact episodes, time within 1.2 m, path ratio.
#: No cap: 1.27/1.20, 1.31/1.24, 1.47/1.37; 359, 0, 112, 6.40 s, 1.31. 4 m: 1.27/1.20,
#: 1.31/1.24, 1.45/1.35; 358, 0, 109, 6.42 s, 1.30 (zara01 Pioneer 58 went into the crowd
#: and timed out). 3 m: 1.26/1.17, 1.30/1.23, 1.43/1.32; 358, 1, 104, 6.56 s, 1.29. 2 m:
#: 1.25/1.18, 1.28/1.23, 1.42/1.30; 356, 2, 114, 6.66 s, 1.26. The same trade as the fraction.
DETOUR_LIMIT = 0.5
#: ``paccet``'s no-fleeing rule and rotation shim after an evasion
#: (``RecoveryParams.evasion_max_retreat``, ``rotation_shim_threshold``). In generated
#: hallways where the walkers leave less than the personal distance, the Pioneer gave way by
#: driving ahead of them down the corridor, or was turned away from its plan by an evasion and
#: then driven that way by the local planner (its interpersonal objective rewards the distance),
#: until the walkers stopped at the corridor's end and blocked its way back (hallway dev seed
#: 155 after 5.8 m of it; 14 of the Pioneer's 23 dev failures were timeouts, 9 of them after
#: more than 1.5 m driven away from the goal). Generated dev
#: seeds, passes of paccet (Pioneer / PR2) and collision runs: hallway 0–199 (400 runs),
#: crowdnav + crowdnav_visible + mixed 0–59 (360 runs); recorded crowds dev seeds 0–89 (360
#: episodes: successes, active- and passive-contact episodes, time within 1.2 m, path ratio):
#: before: hallway 177 / 187, 7; others 356, 2; crowds 351, 4, 108, 6.38 s, 1.33.
#: no fleeing (0.5 m), ungated: hallway 180 / 187, 6; others 355, 3; crowds 352, 6, 119.
#: + shim at 90°, any drive, any time: hallway 186 / 187, 7; others 357, but time on the scenes
#: both pass +1–7 % there and +1–25 % in the families without walkers (queue Pioneer +25 %:
#: it turned to plans that bend round the queue, then crawled backward).
#: + shim after an evasion only: hallway 183 / 187, 7; others 355 (crowdnav PR2 34 turned to a
#: plan behind it and timed out) → differential drive only: others 356, 2; crowds 354, 4, 121.
#: + no fleeing gated as timed passing (at most 3 people within 10 m; kept): hallway
#: 183 / 187, 6; others 356, 2, time ratio to hl −0.00 to −0.02; crowds 354, 3, 112, 6.52 s,
#: 1.32. Shim at 45° (Nav2's default) with ungated no fleeing: hallway 186 / 186; no fleeing at
#: 1.0 m: 184 / 185; the encounter's retreat reference of timed passing taken as its best
#: point so far: 179 / 185. Measured after the reporting split had shown a Pioneer left
#: facing away 0.22 m from a wall (reporting seed 10116), and not adopted: where the shim's
#: turn on the spot is blocked in the local costmap, a slow arc (0.2 m/s) instead: hallway
#: Pioneer 183 → 184, but crowds 354 → 348 successes and 3 → 8 active-contact episodes (the
#: local costmap holds people too, so the arc also ran beside them).
MAX_RETREAT = 0.5
#: ``paccet``'s passing clear of contact (``RecoveryParams.passing_contact_fallback``): in a
#: corridor that leaves less than 3 m across a walker's path, where neither timed passing
#: at 1.25 m nor giving way keeps the personal distance, timed passing again at the contact
#: distance. Development seeds 0–199 of hallway (passes Pioneer / PR2, collision runs): before
#: 192 / 187, 7; on 191 / 190, 6; without the corridor gate 190 / 190, 2, but recorded crowds
#: 0–89 successes 354 → 349 and active-contact episodes 3 → 7 (with it: unchanged); gated on a
#: walker from behind instead, 191 / 189, 3 and crowds 351, 5. The corridor
#: (``passing_contact_corridor``) 3.0 m across instead of 2 × 1.2 m, measured with the escape's
#: wall check: hallway 191 / 190, 4 → 191 / 190, 2; crowds identical. More in the CHANGELOG.
RECOMMENDED_RECOVERY = RecoveryParams(
    evasion_personal_distance=1.2,
    evasion_personal_time=6.0,
    evasion_hold_step=1.0,
    passing_distance=PASSING_DISTANCE,
    passing_contact_fallback=True,
    evasion_max_retreat=MAX_RETREAT,
    rotation_shim_threshold=math.pi / 2,
)


def paper_selection(weights: list[float]) -> SelectionStrategy:
    """PaCcET with the reference code's weights and bisections."""
    return PaccetSelection(Weighted(weights), PaccetOptions.reference())


# The recommended scalarization: L1 distance to a target on the flattened front that gives the
# navigation objective 0.7 of the simplex and shares 0.3 among the social objectives.
RECOMMENDED_NAVIGATION_SHARE = 0.7


def recommended_target(m: int) -> np.ndarray:
    """Target point on the simplex for ``m`` objectives, navigation first."""
    if m == 1:
        return np.ones(1)
    target = np.full(m, (1.0 - RECOMMENDED_NAVIGATION_SHARE) / (m - 1))
    target[0] = RECOMMENDED_NAVIGATION_SHARE
    return target


def recommended_selection(weights: list[float]) -> SelectionStrategy:
    """PaCcET with the L1 target on the simplex (navigation share 0.7)."""
    return PaccetSelection(L1Target(recommended_target(len(weights))), PaccetOptions())


def weighted_sum(weights: list[float]) -> SelectionStrategy:
    """A weighted sum of the objectives with ``weights``."""
    return WeightedSum(weights)


def single_weight(weights: list[float]) -> SelectionStrategy:
    """A weighted sum over one objective: the ROS planner."""
    return WeightedSum([1.0])


PRESETS.add(
    "traditional",
    PlannerPreset(
        "ROS trajectory rollout, weighted sum, no social terms",
        navigation_only,
        single_weight,
        order=10,
    ),
)
PRESETS.add(
    "proxemic_layer",
    PlannerPreset(
        "traditional planner on a costmap with social_navigation_layers' proxemic Gaussians",
        navigation_only,
        single_weight,
        proxemic_layer=True,
        order=20,
    ),
)
PRESETS.add(
    "weighted_social",
    PlannerPreset(
        "the social objectives of paccet combined by a weighted sum",
        recommended_objectives,
        weighted_sum,
        social_goal=True,
        order=30,
    ),
)
PRESETS.add(
    "paccet_paper",
    PlannerPreset(
        "PaCcET as in the paper: per-person ID at the end point, reference weights and bisections",
        paper_objectives,
        paper_selection,
        social_goal=True,
        predict_people=False,
        order=70,
    ),
)
#: ``paccet``'s contact guard (``Navigator.contact_guard``, ``planner.contact_guard``):
#: no command closes the footprint on a person it touches while a reachable one does not, each
#: checked as the start of a full stop. Recorded crowds dev seeds 0–89, both recordings and
#: robots (360 episodes): successes 355 → 358, active-contact episodes 3 → 1 (three gone, one
#: new: on a course the guard changed, a person appears in the recording 12 cm inside the
#: PR2's footprint), passive 112 → 112;
#: generated dev seeds (hallway 0–199, crowdnav, crowdnav_visible and mixed 0–59, the other
#: families 0–29, both robots): every pass and fail the same, time on the scenes both pass
#: +0.00 % (PR2 hallway −0.05 %); paper suite Table 1 identical. A first version that only
#: looked one step ahead left the crowds at 356 successes and 3 active-contact episodes: a
#: Pioneer kept turning at 1 rad/s next to someone until no reachable command could stop the
#: turn before its corner reached them.
RECOMMENDED_CONTACT_GUARD = ContactGuardParams()
#: ``paccet`` draws the social goal's interaction partners at the interaction's own distance in
#: the global plan too (``Navigator.partner_spacing``), as its ID objective scores them. Before,
#: their full personal-space Gaussian made every way into a free spot between two members
#: dear, and the plan went round the group (generated group_join dev seed 45: a 7.7 m path
#: against 6.1 m). Generated dev seeds 0–59 of gallery_present, group_join, queue and mixed,
#: both robots (480 runs), off → on: passes 476 → 476, collision runs 0 → 0; mean time ratio to
#: hl over the scenes both pass, Pioneer / PR2: group_join 1.119 → 1.066 / 1.051 → 1.007,
#: queue 1.094 → 1.069 / 0.976 → 0.957, mixed 1.467 → 1.449 / 1.367 → 1.345,
#: gallery_present 1.015 → 1.012 / 1.156 → 1.155; mean closest centre distance to anyone
#: −0.001 to −0.006 m. group_lead 0–59: 120 → 120 passes, 1.108 → 1.092 / 1.037 → 1.026;
#: gallery_pass (a waypoint, no partners) every run identical. Without a stopping social
#: goal nothing changes: hallway, crowdnav and the recorded crowds (dev seeds 0–89: all 360
#: episodes identical). The cost: the robot comes straight in past its partners, so its time
#: within 1.2 m of anyone, partners included, rises (reporting seeds 10000–10199, family
#: means +0.02 to +0.69 s). Per run: ``StackController("paccet", partner_spacing=False)``.
PARTNER_SPACING = True


PRESETS.add(
    "paccet",
    PlannerPreset(
        "PaCcET, recommended: forecast people, L1 target, remedies on, social global path",
        partner_objectives,
        recommended_selection,
        social_goal=True,
        social_global_path=True,
        params=RECOMMENDED_PARAMS,
        spot_tolerance=RECOMMENDED_SPOT_TOLERANCE,
        order=80,
        recovery=RECOMMENDED_RECOVERY,
        detour_limit=DETOUR_LIMIT,
        contact_guard=RECOMMENDED_CONTACT_GUARD,
        partner_spacing=PARTNER_SPACING,
    ),
)


# The presenter spot's clearance from the activity space (m): the default 0.35 m, or the
# robot's circumscribed radius + 5 cm when larger, so its footprint stays outside at any yaw
# (a PR2's corners, 0.46 m out, entered it while turning at the spot: generated
# gallery_present dev seeds 5, 9, 14, 15).
PRESENTER_MARGIN = 0.05


def presenter_clearance(robot: RobotModel) -> float:
    """``max(0.35, circumscribed radius + PRESENTER_MARGIN)`` m (see ``PRESENTER_MARGIN``)."""
    return max(0.35, robot.circumscribed_radius + PRESENTER_MARGIN)


def footprint_front(robot: RobotModel) -> float:
    """How far (m) the footprint reaches ahead of the robot's centre along its heading (+x of
    the base frame): the ``queue_front`` of the social-goal rule, with which a PR2 (0.325 m)
    keeps the queue's body gap behind the last member instead of the people's centre
    spacing (:func:`~socialnav.social.goals.queue_tail_pose`)."""
    return max(0.0, float(robot.polygon[:, 0].max()))


def social_goal_options(robot: RobotModel) -> dict[str, float]:
    """Keyword options of :func:`~socialnav.social.resolve.resolve_social_goal` that depend on
    the robot: the presenter spot's ``art_clearance`` (:func:`presenter_clearance`) and the
    queue slot's ``queue_front`` (:func:`footprint_front`). One place, so the planner's rule and
    the spot a detected-context episode is judged at cannot drift apart."""
    return {"art_clearance": presenter_clearance(robot), "queue_front": footprint_front(robot)}


class StickySocialGoal:
    """Resolve the social goal once and keep it while the people who define it stay put.

    ``resolve_social_goal`` is stateless and depends on the robot's pose (e.g. which side of
    the artwork to present from); re-resolving every cycle would let the goal flip as the robot
    moves. It is recomputed when any person moved more than ``moved`` metres, or the
    structures changed (members of a group or queue, viewers of an artwork). People are matched
    by id: with a detected context the tracks' order changes (a missed person is coasted
    last) and false positives come and go; neither is a reason to move the goal, as long as
    they belong to no structure.

    Between those, a member of a structure whose estimate drifted more than ``refine`` metres
    (a detected context's running mean settling) re-resolves the goal from the robot pose of
    the last full resolution: the goal follows the better estimate (the social-goal rules are
    continuous in the people's positions) but not the robot, so choices keyed on the robot's
    pose (the presenting side, gap ties) stay as first made. With the context given, standing
    members never move and this never fires.
    """

    def __init__(
        self,
        moved: float = 0.3,
        tolerance: tuple[float, float] | None = None,
        art_clearance: float = 0.35,
        refine: float = 0.01,
        queue_front: float = 0.0,
    ) -> None:
        self.moved = moved
        self.refine = refine
        self.tolerance = tolerance
        self.art_clearance = art_clearance
        self.queue_front = queue_front
        self._positions: dict[int, tuple[float, float]] | None = None
        self._refined: dict[int, tuple[float, float]] = {}
        self._pose: np.ndarray | None = None
        self._structures: tuple[Any, ...] | None = None
        self._goal: SocialGoal | None = None

    def __call__(
        self, social: SocialContext, given_goal: np.ndarray, pose: np.ndarray
    ) -> SocialGoal | None:
        """The social goal for ``given_goal (3,)`` seen from ``pose (3,)``, or None."""
        positions = {p.id: p.position for p in social.people}
        structures = (
            tuple((g.member_ids, g.mode) for g in social.groups),
            tuple(q.member_ids for q in social.queues),
            tuple(a.viewer_ids for a in social.artworks),
            tuple((x.kind, x.member_ids, x.params) for x in social.structures),
        )
        last = self._positions
        stale = (
            last is None
            or structures != self._structures
            or any(
                math.hypot(x - last[i][0], y - last[i][1]) > self.moved
                for i, (x, y) in positions.items()
                if i in last
            )
        )
        members = {
            i
            for ids in (
                *(g.member_ids for g in social.groups),
                *(q.member_ids for q in social.queues),
                *(a.viewer_ids for a in social.artworks),
                *(x.member_ids for x in social.structures),
            )
            for i in ids
        }
        if stale:
            self._resolve(social, given_goal, pose)
            self._pose = np.array(pose, dtype=float)
            self._positions, self._structures = positions, structures
            self._refined = {i: positions[i] for i in members if i in positions}
        elif self._pose is not None and any(
            math.hypot(x - self._refined[i][0], y - self._refined[i][1]) > self.refine
            for i, (x, y) in positions.items()
            if i in self._refined
        ):
            self._resolve(social, given_goal, self._pose)
            self._refined = {i: positions[i] for i in members if i in positions}
        return self._goal

    def _resolve(self, social: SocialContext, given_goal: np.ndarray, pose: np.ndarray) -> None:
        from socialnav.social.resolve import resolve_social_goal

        self._goal = resolve_social_goal(
            social,
            given_goal,
            pose,
            art_clearance=self.art_clearance,
            queue_front=self.queue_front,
        )
        if self._goal is not None and self.tolerance is not None and not self._goal.is_waypoint:
            from dataclasses import replace

            xy, yaw = self.tolerance
            self._goal = replace(self._goal, position_tolerance=xy, yaw_tolerance=yaw)


class SceneObjectives:
    """A preset's objective set, resolved every cycle from the people, groups, queues and
    artworks in view (``ctx.social``): people appearing add their objectives, people leaving
    remove them. One (objectives, selection) pair is kept per set of objective names, so a
    navigator built with nobody in view plans exactly like one built with the people present.
    The objectives of a scene with one person are built once at construction (and dropped), so
    a critic's ``ConfigurationError`` is raised here, not in the first cycle someone is in view
    (where the loop could only answer ``INVALID_INPUT``).
    """

    def __init__(self, preset: PlannerPreset, params: LocalPlannerParams) -> None:
        self.preset = preset
        self.params = params
        self._sets: dict[tuple[str, ...], tuple[tuple[Objective, ...], SelectionStrategy]] = {}
        preset.objectives(SocialContext((Person(0, (0.0, 0.0)),)), False, params)

    def for_scene(self, social: SocialContext) -> tuple[tuple[Objective, ...], SelectionStrategy]:
        """The (objectives, selection) of the preset for the people and structures in
        ``social``, the same instances each time the set of objective names repeats."""
        preset = self.preset
        pairs = preset.objectives(
            social, preset.social_goal and has_social_goal(social), self.params
        )
        key = tuple(o.name for o, _ in pairs)
        if key not in self._sets:
            objectives = tuple(o for o, _ in pairs)
            selection = with_indifference(preset.selection([w for _, w in pairs]), objectives)
            self._sets[key] = (objectives, selection)
        return self._sets[key]

    def resolve(self, ctx: PlanningContext) -> tuple[tuple[Objective, ...], SelectionStrategy]:
        """:meth:`for_scene` of the cycle's ``ctx.social`` (the people in view)."""
        return self.for_scene(ctx.social)

    def reset(self) -> None:
        """Reset the state of every critic of every objective set kept so far."""
        for objectives, _ in self._sets.values():
            for obj in objectives:
                for critic, _ in obj.terms:
                    critic.reset()


def build_local_planner(
    name: str, robot: RobotModel, social: SocialContext, params: LocalPlannerParams | None = None
) -> LocalPlanner:
    """The local planner of preset ``name``; its objective set follows the scene every cycle
    (:class:`SceneObjectives`), starting from the one for ``social``."""
    preset = PRESETS.get(name)
    p = params or preset.params
    scene = SceneObjectives(preset, p)
    objectives, selection = scene.for_scene(social)
    return LocalPlanner(robot, objectives, selection, p, objective_set=scene)


def preset_with(
    name: str, detour_limit: float | None = None, partner_spacing: bool | None = None
) -> PlannerPreset:
    """Preset ``name`` with a per-run ``detour_limit`` and ``partner_spacing`` (``None``: its
    own). Raises ``ConfigurationError`` for an unknown name, a limit that is not a finite
    number >= 0, a positive one for a preset without a social global plan, or a
    ``partner_spacing`` that is not a bool."""
    preset = PRESETS.get(name)
    if partner_spacing is not None:
        preset = replace(preset, partner_spacing=partner_spacing)  # checked by the preset
    if detour_limit is None:
        return preset
    if detour_limit and not preset.social_global_path:
        raise ConfigurationError(f"preset {name!r} has no social global plan to limit")
    return replace(preset, detour_limit=detour_limit)  # checked by the preset


def build_navigator(
    name: str,
    robot: RobotModel,
    costmap: Costmap,
    goal: np.ndarray,
    social: SocialContext,
    record: bool = False,
    params: LocalPlannerParams | None = None,
    recovery: RecoveryParams | Mapping[str, Any] | None = None,
    default_tolerance: float = 1.0,
    planner_frequency: float = 0.5,
    global_search: GlobalSearch = "scipy",
    replan_mode: ReplanMode = "inline",
    replan_delay: int = 2,
    detour_limit: float | None = None,
    partner_spacing: bool | None = None,
) -> Navigator:
    """The stack of preset ``name``: global plan, local planner with recoveries, social goal.

    ROS-named options: ``params`` (``dwa_local_planner``), ``recovery`` (progress checker
    ``required_movement_radius``/``movement_time_allowance``, ``controller_patience``, waiting
    and evasion; :class:`~socialnav.planner.recovery.RecoveryParams`, or a mapping of field
    overrides of the preset's, e.g. ``{"evasion_max_retreat": 0.0}``; default the preset's),
    ``default_tolerance`` (m, navfn: how far a blocked goal may move to a reachable point) and
    ``planner_frequency`` (Hz, move_base: periodic global replanning); ``global_search``,
    ``replan_mode`` and ``replan_delay`` as in :class:`Navigator` (rate-separated replanning;
    the defaults replan inline with SciPy's Dijkstra); ``detour_limit`` as in
    :class:`Navigator` (``None``: the preset's; 0 switches it off); ``partner_spacing`` likewise
    (``None``: the preset's, ``False`` switches it off). The objective set follows
    the people in view every cycle (:class:`SceneObjectives`); ``social`` only seeds it.
    Raises ``ConfigurationError`` on an unknown preset or recovery field, a bad recovery value,
    a non-positive ``planner_frequency``
    or a ``detour_limit`` that is not a finite number >= 0 or is positive for a preset without
    a social global plan.
    """
    preset = preset_with(name, detour_limit, partner_spacing)
    if not (np.isfinite(planner_frequency) and planner_frequency > 0):
        raise ConfigurationError(f"planner_frequency must be positive, got {planner_frequency}")
    local = RecoveringPlanner(
        build_local_planner(name, robot, social, params),
        with_overrides(preset.recovery, recovery, "recovery"),
    )
    layer: CostmapLayer | None = None
    if preset.proxemic_layer:
        from socialnav.world.costmap import combine_max

        def proxemic(local_costmap: Costmap, people: SocialContext) -> Costmap:
            costs = proxemic_costs(local_costmap.geometry, people.positions(), people.velocities())
            return combine_max(local_costmap, costs)

        layer = proxemic

    global_layer: CostmapLayer | None = personal_space_layer if preset.social_global_path else None
    meeting: MeetingLayer | None = None
    if preset.social_global_path and preset.meeting_layer:
        global_layer, meeting = meeting_layers(robot)
    if preset.proxemic_layer:
        global_layer = layer  # a ROS user adds the social layer to both costmaps
    return Navigator(
        robot,
        local,
        costmap,
        goal,
        social_goal_fn=StickySocialGoal(
            tolerance=preset.spot_tolerance, **social_goal_options(robot)
        )
        if preset.social_goal
        else None,
        predict_people=preset.predict_people,
        record=record,
        costmap_layer=layer,
        global_layer=global_layer,
        window_size=LOCAL_WINDOW,
        goal_tolerance=default_tolerance,
        replan_period=1.0 / planner_frequency,
        global_search=global_search,
        replan_mode=replan_mode,
        replan_delay=replan_delay,
        meeting_layer=meeting,
        replan_hysteresis=preset.replan_hysteresis,
        detour_layer=standing_space_layer if preset.social_global_path else None,
        detour_limit=preset.detour_limit if preset.social_global_path else 0.0,
        contact_guard=preset.contact_guard,
        partner_spacing=spacing_on(preset),
    )


def spacing_on(preset: PlannerPreset) -> bool:
    """Whether ``preset``'s navigator draws interaction partners at their own distance: its
    ``partner_spacing``, on the personal-space layers of ``social_global_path`` only."""
    return preset.partner_spacing and preset.social_global_path and not preset.proxemic_layer


def proxemic_costs(geometry: GridGeometry, *args: Any, **kwargs: Any) -> NDArray[np.uint8]:
    """:func:`socialnav.world.proxemic_layer.proxemic_costs` on the compiled kernels when they
    are on (:func:`socialnav.planner.kernels.proxemic_costs`: the same layer), else NumPy."""
    from socialnav.world import proxemic_layer

    fn = kernels.proxemic_costs if kernels.enabled() else proxemic_layer.proxemic_costs
    return fn(geometry, *args, **kwargs)


# A Gaussian personal-space cost for global planning: 250 at the person, about 80 at 1.2 m
# (σ = 0.8 m), so the global path keeps to the social zone where the map leaves room; groups'
# o-spaces cost OSPACE_COST, so no plan threads between the members of a conversation.
# Measured and not adopted (generated dev seeds 0–29 of hallway, crowdnav, crowdnav_visible and
# mixed, both robots, 240 runs: 230 passes, 1 collision run): variance 0.36 228 and 4 (time
# ratios to hl in the crowd families −0.1 to −0.3); amplitude 150 228 and 3; a cutoff of 30 or
# 60 (no cost beyond about 1.65 or 1.4 m) 228 and 3, 228 and 2; cutoff 60 for standing people
# only 227 and 2; cutoff 30 with velocity_factor 10 (the walker's lobe as long as now)
# 231 and 0, and on seeds 30–59 228 against 226 with ratios −0.03 to −0.2, but recorded
# crowds dev seeds 0–89 lost 4 successes (345 → 341) and gained 5 active-contact episodes.
# Also measured and not adopted: leaving out walkers who recede from the plan's start faster
# than the robot's top speed (it can never catch them, so their forward lobe only bends the
# plan to the other side): generated hallway dev seeds 0–199, Pioneer 191 → 190 and PR2
# 190 → 190 passes, time +0.5 % / +0.3 %; a walker overtaking from behind is beside the
# robot, not receding, when the plan picks its side.
PERSONAL_SPACE_LAYER = {"amplitude": 250.0, "variance": 0.64, "cutoff": 5.0, "velocity_factor": 5.0}
OSPACE_COST = 220


def personal_space_layer(
    costmap: Costmap,
    social: SocialContext,
    drawn: NDArray[np.bool_] | None = None,
    partners: Mapping[int, float] | None = None,
) -> Costmap:
    """``costmap`` with a Gaussian personal-space cost per person (those ``drawn (K,)``, all
    by default) and every group's o-space cost. ``partners`` (``Person.id`` (int) → the
    interaction's own distance ``d`` in m, ``Navigator.partner_spacing``): below the 1.2 m
    personal distance, that person's Gaussian is narrowed by ``max(d, HUMAN_RADIUS) /
    PERSONAL`` (σ), so it costs at ``d`` what a stranger's costs at 1.2 m (a partner at 1.2 m
    or more is drawn as anyone else, and never narrower than their body, so a partner on the
    spot stays on the map). Ids not among ``social``'s people are ignored (the
    navigator's partners are the whole scene's). Raises ``InvalidInputError`` for a
    ``partners`` that is not a mapping, a key that is not an int, or a distance that is not a
    finite number > 0 (naming the person), whether or not that person is in view."""
    from socialnav.social.spaces import o_space
    from socialnav.world.costmap import combine_max

    _check_partners(partners)
    if not social.people:
        return costmap
    positions, velocities = social.positions(), social.velocities()
    scale = np.array([_narrowing(partners, p.id) for p in social.people])
    if drawn is not None:
        positions, velocities, scale = positions[drawn], velocities[drawn], scale[drawn]
    costs = np.zeros(costmap.geometry.shape, dtype=np.uint8)
    # One layer per distinct narrowing (everyone else shares one call).
    for s in np.unique(scale):
        these = scale == s
        costs = np.maximum(
            costs,
            proxemic_costs(
                costmap.geometry,
                positions[these],
                velocities[these],
                amplitude=PERSONAL_SPACE_LAYER["amplitude"],
                variance=PERSONAL_SPACE_LAYER["variance"] * float(s) ** 2,
                cutoff=PERSONAL_SPACE_LAYER["cutoff"],
                velocity_factor=PERSONAL_SPACE_LAYER["velocity_factor"],
            ),
        )
    if social.groups:
        xs, ys = costmap.geometry.cell_centers()
        for group in social.groups:
            if len(group.member_ids) < 2:
                continue
            center, radius = o_space(social.positions(group.member_ids))
            inside = np.hypot(xs - center[0], ys - center[1]) <= radius
            costs[inside] = np.maximum(costs[inside], OSPACE_COST)
    return combine_max(costmap, costs)


#: The meeting layer (:mod:`socialnav.world.meeting_layer`) in the global plan: the personal
#: space of PERSONAL_SPACE_LAYER at each walker's meeting point with the robot cruising at
#: ``speed_fraction`` of its top speed; people slower than ``min_speed`` (m/s) are standing
#: (their Gaussian where they are); ``tau0 + tau_rate · T`` (s) the timing uncertainty at
#: arrival time ``T``. Development seeds 0–19 of crowdnav, crowdnav_visible, hallway and mixed,
#: both robots, hysteresis 0.3 (worst cell no costlier): timing (1.5, 0.25) 149 of 160
#: passes, (1, 0.25) 147; speed fraction 1.0 lost 2 more than 0.8. The sharper (1, 0.25) and
#: (0.75, 0.2) gave up to 0.1 lower median time ratios to hl in the crowd families but left
#: the PR2 of navground's Cross example (examples/navground/cross.yaml) stuck in the
#: crossing, reaching no target. Off in ``paccet``: with ``RECOMMENDED_RECOVERY``'s evasion
#: the pair (meeting layer, hysteresis 0.3) gave 150 of those 160 against 151 without, with
#: median time ratios to hl 1.47/1.26 (crowdnav Pioneer/PR2), 1.46/1.30 (visible) against
#: 1.52/1.44 and 1.57/1.45, but lost hallway Pioneer seeds 10 and 19 (seed 10 is
#: tests/planner/test_control_loop.py's walking pair); hysteresis alone gave 149.
#: Measured again on the current planner (generated dev seeds 0–59 of those four families, both
#: robots, 480 runs): the pair gave 459 passes against 456 and 0 collision runs against 3,
#: time ratios to hl 0.04–0.25 lower in crowdnav and crowdnav_visible (still 1.37–1.48), and
#: the other five families' 600 runs the same outcomes; but recorded crowds dev seeds 0–89
#: went from 345 successes, 8 active-contact and 108 passive-contact episodes to 338, 13 and
#: 112 (meeting layer without hysteresis: 340, 10, 106), the path length ratio from 1.44 to
#: 1.52 (1.48), for 0.4 s less within 1.2 m; with a 5 s horizon 342, 8 and 107, path length
#: ratio 1.51. Still off.
#: Measured again with the detour limit and the contact guard (generated dev seeds 0–39 of
#: crowdnav, crowdnav_visible, hallway and mixed, both robots; recorded crowds dev 0–89): the
#: meeting layer alone gave passes 315 → 313 of 320 (hallway 77 → 74; crowdnav PR2 +1 with
#: one collision run fewer), mean time ratios to hl Pioneer/PR2 crowdnav 1.26/1.18 →
#: 1.27/1.22, crowdnav_visible 1.31/1.25 → 1.34/1.25, mixed 1.51/1.40 → 1.49/1.31; crowds
#: 359 → 357 successes, active-contact episodes 0 → 3 (all Pioneer), passive 113 → 111, time
#: within 1.2 m 6.44 → 6.49 s. With replan hysteresis 0.3 as well: 315 → 314 passes, mixed
#: 1.66/1.32, crowds 355 successes, 2 active, 118 passive, path ratio 1.31 → 1.36. Still off.
MEETING_LAYER = {
    "speed_fraction": 0.8,
    "min_speed": 0.3,
    "horizon": 10.0,
    "tau0": 1.5,
    "tau_rate": 0.25,
}


def meeting_layers(robot: RobotModel) -> tuple[CostmapLayer, MeetingLayer]:
    """The ``(global_layer, meeting_layer)`` pair of a navigator whose walkers' personal
    space is drawn where ``robot`` can meet them (``PlannerPreset.meeting_layer``): standing
    people and o-spaces where they are, walkers at the meeting point of the robot cruising at
    ``MEETING_LAYER["speed_fraction"]`` of its ``max_vel_x``."""
    speed = MEETING_LAYER["speed_fraction"] * robot.max_vel_x

    def meeting(costmap: Costmap, people: SocialContext, start: FloatArray) -> Costmap:
        return meeting_space_layer(costmap, people, start, speed)

    return standing_space_layer, meeting


def _walking(social: SocialContext) -> NDArray[np.bool_]:
    v = social.velocities().reshape(-1, 2)
    return np.asarray(np.hypot(v[:, 0], v[:, 1]) >= MEETING_LAYER["min_speed"])


def _check_partners(partners: object) -> None:
    """Raise ``InvalidInputError`` unless ``partners`` is None or a mapping of int person ids
    to finite distances > 0 (m) (:func:`personal_space_layer`)."""
    if partners is None:
        return
    if not isinstance(partners, Mapping):
        raise InvalidInputError(
            f"partners must be a mapping of person id (int) to distance (m), got"
            f" {type(partners).__name__}"
        )
    for person, d in partners.items():
        if isinstance(person, bool) or not isinstance(person, int | np.integer):
            raise InvalidInputError(f"partners: person ids are ints (Person.id), got {person!r}")
        if not is_non_negative_number(d) or d == 0:
            raise InvalidInputError(
                f"partners: person {person}'s distance must be a finite number > 0 (m), got {d!r}"
            )


def _narrowing(partners: Mapping[int, float] | None, person: int) -> float:
    """The factor on person ``person``'s Gaussian σ (:func:`personal_space_layer`; the
    mapping is checked there)."""
    if not partners or person not in partners:
        return 1.0
    return min(1.0, max(float(partners[person]), HUMAN_RADIUS) / PERSONAL)


def standing_space_layer(
    costmap: Costmap, social: SocialContext, partners: Mapping[int, float] | None = None
) -> Costmap:
    """:func:`personal_space_layer` of the people slower than ``MEETING_LAYER["min_speed"]``
    (with every group's o-space; ``partners`` as there); walkers are
    :func:`meeting_space_layer`'s."""
    if not social.people:
        return costmap
    return personal_space_layer(costmap, social, ~_walking(social), partners)


def meeting_space_layer(
    costmap: Costmap, social: SocialContext, start: FloatArray, speed: float
) -> Costmap:
    """``costmap`` with each walker's personal space where the robot, starting at ``start (3,)``
    and cruising at ``speed`` m/s, can meet them (:func:`socialnav.world.meeting_layer.\
meeting_costs` with ``PERSONAL_SPACE_LAYER``'s Gaussian and ``MEETING_LAYER``'s timing)."""
    from socialnav.world import meeting_layer
    from socialnav.world.costmap import combine_max

    # The compiled kernel when on (the same layer), else the NumPy reference.
    meeting_costs = kernels.meeting_costs if kernels.enabled() else meeting_layer.meeting_costs
    walking = _walking(social) if social.people else np.zeros(0, dtype=bool)
    if not walking.any():
        return costmap
    costs = meeting_costs(
        costmap.geometry,
        social.positions()[walking],
        social.velocities()[walking],
        np.asarray(start, dtype=float)[:2],
        speed,
        amplitude=PERSONAL_SPACE_LAYER["amplitude"],
        variance=PERSONAL_SPACE_LAYER["variance"],
        cutoff=PERSONAL_SPACE_LAYER["cutoff"],
        horizon=MEETING_LAYER["horizon"],
        tau0=MEETING_LAYER["tau0"],
        tau_rate=MEETING_LAYER["tau_rate"],
    )
    return combine_max(costmap, costs)

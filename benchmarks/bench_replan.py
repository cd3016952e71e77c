"""Global replan in a crowd: the navigator's replan (people as obstacles on the global map, the
personal-space layer, the search) against the implementation before, in the same run.

Run: ``.venv/bin/python benchmarks/bench_replan.py [--quick]``.

Setup (seeded, as ``bench_crowd_step.py``): the 27 m × 27 m room of the paper suite's
group/queue scenes (540 × 540 cells at 0.05 m), the ``paccet`` navigator's global stack
(``Navigator._compute_plan``: people as obstacle discs; with the meeting layer option, the
standing people's personal space and the walkers' where the robot can meet them
(``meeting_layers``), plan with navfn's tolerance), the PR2 at (3, 3) planning to
(24, 24) and to (12, 8) (a near goal: the compiled search stops there); 50 people walking
at 0.5–1.3 m/s, the fastest one at ``fast`` m/s (1, 3, 5 and 10: the cost must not grow with
it).

Rows per scene: ``before`` = full re-inflation of the map, the NumPy layers and SciPy's
Dijkstra (the reference implementation: the baseline); ``exact`` = the kept static inflation
and the compiled layers (the same costmap and the same plan, asserted) with SciPy's Dijkstra
(the default); ``compiled search`` = the same with ``global_search="compiled"`` (A*: the same
cost, asserted; among equal-cost paths it may pick another): what ``paccet`` ships;
``meeting layer option`` = the compiled stack with ``PlannerPreset.meeting_layer`` on (off by
default; also asserted equal to its own NumPy/SciPy reference), to show what it costs.
CPU-time medians (``time.thread_time``) and wall medians, interleaved round by round.
"""

from __future__ import annotations

import numpy as np

from bench_crowd_step import _context, _people
from harness import format_seconds, quick_option, time_interleaved
from socialnav.core.robot import PR2
from socialnav.core.scene import SocialContext
from socialnav.planner import kernels
from socialnav.planner.global_planner import plan_path
from socialnav.planner.presets import (
    MEETING_LAYER,
    build_navigator,
    meeting_layers,
    meeting_space_layer,
    personal_space_layer,
    standing_space_layer,
)
from socialnav.sim.scenario import load_scenario
from socialnav.world.costmap import add_obstacle_discs

SEED = 11
SPEED = MEETING_LAYER["speed_fraction"] * PR2.max_vel_x  # the navigator's cruising speed
GOALS = {
    "far goal (24, 24)": np.array([24.0, 24.0, 0.0]),
    "near goal (12, 8)": np.array([12.0, 8.0, 0.0]),
}


def main(quick: bool = False) -> None:
    repeats = 5 if quick else 15
    kernels.warmup()
    costmap = load_scenario("group_join").static_costmap(PR2)
    size = costmap.geometry.shape[1] * costmap.geometry.resolution
    pose = np.array([3.0, 3.0, 0.0])
    print(
        "\n## Global replan, 50 people (0.5–1.3 m/s, the fastest at `fast`), 540 × 540 map "
        f"(median of {repeats}, interleaved; kernel compile/cache load "
        f"{kernels.compile_seconds:.2f} s at construction)\n"
    )
    print("| goal | fast (m/s) | variant | CPU (median) | wall (median) | speed-up (CPU) |")
    print("|---|---|---|---|---|---|")
    for goal_name, goal in GOALS.items():
        for fast in (1.0, 3.0, 5.0, 10.0):
            rng = np.random.default_rng(SEED)
            pos, vel = _people(rng, 50, fast, size)
            social = _context(pos, vel)
            navs = {  # the shipped default: personal space where people are now
                search: build_navigator(
                    "paccet", PR2, costmap, goal, SocialContext(), global_search=search
                )
                for search in ("scipy", "compiled")
            }
            meet = {  # the meeting layer option (PlannerPreset.meeting_layer)
                search: build_navigator(
                    "paccet", PR2, costmap, goal, SocialContext(), global_search=search
                )
                for search in ("scipy", "compiled")
            }
            for nav in meet.values():
                nav.global_layer, nav.meeting_layer = meeting_layers(PR2)

            def reference(social: SocialContext, goal: np.ndarray, meeting: bool):
                previous = kernels.set_enabled(False)
                try:
                    # People grown by half a cell diagonal, as the navigator draws them.
                    grown = social.radii() + costmap.resolution * np.sqrt(2.0) / 2.0
                    discs = np.column_stack([social.positions(), grown])
                    cm = add_obstacle_discs(costmap, discs, PR2.inscribed_radius)
                    if meeting:
                        cm = standing_space_layer(cm, social)
                        cm = meeting_space_layer(cm, social, pose, SPEED)
                    else:
                        cm = personal_space_layer(cm, social)
                    return plan_path(
                        cm, pose[:2], goal[:2], tolerance=0.5 * PR2.circumscribed_radius
                    )
                finally:
                    kernels.set_enabled(previous)

            def before(social: SocialContext = social, goal: np.ndarray = goal):
                return reference(social, goal, False)

            def plan(nav, social: SocialContext = social, goal: np.ndarray = goal):
                return nav._compute_plan(pose, goal, social, True)

            # Each stack against its NumPy/SciPy reference: the same plan, the same cost.
            for stack, meeting in ((navs, False), (meet, True)):
                ref = reference(social, goal, meeting)
                same, fastest = plan(stack["scipy"]), plan(stack["compiled"])
                assert ref.status == same.status == fastest.status == "OK"
                assert np.array_equal(ref.path, same.path) and ref.cost == same.cost
                assert abs(fastest.cost - ref.cost) <= 1e-9 * ref.cost
            variants = {
                "before: full inflation, NumPy layer, SciPy Dijkstra (baseline)": before,
                "exact: kept inflation, compiled layer, SciPy Dijkstra (same plan)": (
                    lambda n=navs["scipy"]: plan(n)
                ),
                "**compiled search (A*, same cost): the default**": (
                    lambda n=navs["compiled"]: plan(n)
                ),
                "meeting layer option, compiled layers and search": (
                    lambda n=meet["compiled"]: plan(n)
                ),
            }
            timed = time_interleaved(list(variants.values()), repeats, warmup=1)
            base = timed[0][2]
            for name, (w, _, c) in zip(variants, timed, strict=True):
                ratio = "" if c == base else f"{base / c:.1f}x"
                print(
                    f"| {goal_name} | {fast:g} | {name} | {format_seconds(c)} | "
                    f"{format_seconds(w)} | {ratio} |"
                )


if __name__ == "__main__":
    main(quick_option(__doc__))

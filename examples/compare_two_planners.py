"""Run one scenario with two planners and compare what they measure.

The Table 1 hallway (a person walking toward the robot) with the ROS-style ``traditional``
planner and the recommended ``paccet`` planner; prints a few metrics and the success conditions
of each. Run: ``python examples/compare_two_planners.py [SCENARIO]``.
"""

from __future__ import annotations

import sys

from socialnav.experiments.planners import run_planner_episode
from socialnav.experiments.suite import EpisodeSpec
from socialnav.metrics import measure_episode


def main(scenario: str = "hallway_passing") -> None:
    for planner in ("traditional", "paccet"):
        record = run_planner_episode(EpisodeSpec(scenario, planner, "pr2")).record
        measured = measure_episode(record)
        m = measured.metrics
        print(
            f"{planner:12s} success={measured.success!s:5s} "
            f"time={m['time_to_goal']:.1f} s  min distance={m['min_distance_center']:.2f} m  "
            f"path={m['path_length']:.1f} m"
        )
        failed = [c.name for c in measured.conditions if not c.passed]
        print(f"{'':12s} failed conditions: {', '.join(failed) or 'none'}")


if __name__ == "__main__":
    main(*sys.argv[1:2])

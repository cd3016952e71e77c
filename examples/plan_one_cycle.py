"""Plan one control cycle with the recommended planner, without a simulator.

A robot in a 6 m × 4 m room meets one person standing ahead; the navigator (global plan + local
planner) returns the body twist to apply and why. Run: ``python examples/plan_one_cycle.py``.
"""

from __future__ import annotations

import numpy as np

from socialnav.core.robot import PR2
from socialnav.core.scene import Person, SocialContext
from socialnav.planner.presets import build_navigator
from socialnav.world.grid import GridGeometry
from socialnav.world.inflation import inflate
from socialnav.world.raster import rasterize


def main() -> None:
    geometry = GridGeometry(shape=(80, 120), resolution=0.05)  # 4 m × 6 m, origin (0, 0)
    corners = np.array([[0.0, 0.0], [6.0, 0.0], [6.0, 4.0], [0.0, 4.0]])
    walls = np.stack([corners, np.roll(corners, -1, axis=0)], axis=1)  # (4, 2, 2) segments
    costmap = inflate(rasterize(geometry, segments=walls), geometry, PR2.inscribed_radius)
    people = SocialContext((Person(1, (3.5, 2.1)),))
    navigator = build_navigator(
        "paccet", PR2, costmap=costmap, goal=np.array([5.5, 2.0, 0.0]), social=people, record=True
    )
    result = navigator.step(0.0, np.array([0.5, 2.0, 0.0]), np.zeros(3), people)
    print(f"status {result.status.value}, command {np.round(result.cmd, 3)} (m/s, m/s, rad/s)")
    if result.record is not None:
        print(result.record.rejection_summary())


if __name__ == "__main__":
    main()

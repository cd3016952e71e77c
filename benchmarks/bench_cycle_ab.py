"""The ``paccet`` cycle of this checkout against another source tree, alternating processes.

Run: ``git archive main | tar -x -C /tmp/base`` then, a few times each, alternating:
``PYTHONPATH=/tmp/base/src .venv/bin/python benchmarks/bench_cycle_ab.py base`` and
``.venv/bin/python benchmarks/bench_cycle_ab.py new``.

Scene: ``bench_social_planner.py``'s (10 and 50 people, N ≈ 2000, the same planner and
context every cycle, so prepared grids are reused); per label one line with the CPU-time
median over 40 cycles and the chosen candidate (it must be the same in both trees). Two
versions cannot share a process, hence the alternation: compare lines run back to back.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_social_planner as b
from socialnav.planner.local_planner import LocalPlannerParams
from socialnav.planner.presets import PRESETS, build_local_planner


def main(label: str) -> None:
    static = b.static_costmap()
    out = []
    for n in (10, 50):
        scene = b.build_scene(n, static)
        params = LocalPlannerParams(*b.SAMPLINGS[-1])
        planner = build_local_planner("paccet", b.ROBOT, scene.social, params)
        predict = PRESETS.get("paccet").predict_people
        for _ in range(3):
            planner.plan(b.make_context(scene, predict), record=True)
        times = []
        for _ in range(40):
            c0 = time.process_time()
            result = planner.plan(b.make_context(scene, predict), record=True)
            times.append(time.process_time() - c0)
        assert result.record is not None
        out.append(f"{n} people {np.median(times) * 1e3:.2f} ms chosen={result.record.chosen}")
    print(label, " | ".join(out))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "this")

"""The README's navground and Gymnasium sections are what the examples and the code do."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]


def _section(title: str) -> str:
    text = (ROOT / "README.md").read_text()
    start = text.index(f"## {title}")
    end = text.find("\n## ", start + 1)
    return text[start:end]


def test_the_navground_yaml_is_the_example_file_and_navground_loads_it() -> None:
    from navground import core, sim

    block = re.search(r"```yaml\n(.*?)```", _section("For navground users"), re.S)
    assert block is not None
    shown = yaml.safe_load(block.group(1))
    assert shown == yaml.safe_load((ROOT / "examples" / "navground" / "cross.yaml").read_text())
    core.load_plugins()
    experiment = sim.load_experiment(block.group(1))
    world = sim.World()
    experiment.scenario.init_world(world, seed=0)
    robot = world.agents[-1].behavior
    assert robot.type == "SocialNav" and robot.planner == "paccet" and robot.sim_time == 1.7


def test_the_gymnasium_example_runs() -> None:
    pytest.importorskip("gymnasium")
    block = re.search(r"```python\n(.*?)```", _section("For Gymnasium users"), re.S)
    assert block is not None
    namespace: dict[str, object] = {}
    exec(compile(block.group(1), "README.md", "exec"), namespace)
    obs = namespace["obs"]
    assert set(obs) == {"robot", "goal", "social_goal", "people", "costmap"}  # type: ignore[arg-type]
    assert obs["costmap"].shape == (64, 64)  # type: ignore[index]
    namespace["envs"].close()  # type: ignore[attr-defined]

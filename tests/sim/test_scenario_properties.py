"""Scenarios as a property: any (randomized) scenario written as YAML reads back equal."""

from __future__ import annotations

import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from socialnav.sim.scenario import builtin_scenarios, load_scenario


@settings(max_examples=20, deadline=None)
@given(name=st.sampled_from(builtin_scenarios()), seed=st.integers(0, 2**31 - 1))
def test_a_scenario_written_as_yaml_reads_back_equal(tmp_path_factory, name, seed):
    scenario = load_scenario(name).randomize(seed)
    path = tmp_path_factory.mktemp("scenario") / f"{name}.yaml"
    path.write_text(yaml.safe_dump(scenario.model_dump(mode="json"), sort_keys=False))
    back = load_scenario(path)
    assert back.model_dump(mode="json") == scenario.model_dump(mode="json")

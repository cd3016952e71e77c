"""Episode storage as a property: any record reads back equal, in every format."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from test_storage import assert_records_equal, rich_record

from socialnav.experiments.storage import load_episode, save_episode


@settings(max_examples=15, deadline=None)
@given(
    steps=st.integers(6, 60),
    seed=st.integers(0, 2**31 - 1),
    fmt=st.sampled_from(["parquet", "csv"]),
)
def test_any_record_reads_back_equal(tmp_path_factory, steps, seed, fmt):
    record = rich_record(steps=steps, seed=seed)
    folder = tmp_path_factory.mktemp("episode")
    save_episode(record, folder, fmt=fmt)
    assert_records_equal(load_episode(folder), record)

"""The shared ETH/UCY recordings (skipped cleanly when the data folder is absent)."""

from __future__ import annotations

from pathlib import Path

import pytest

from shared import crowd_data


@pytest.fixture
def hotel_slice(tmp_path: Path) -> Path:
    """The first 400 rows of ETH hotel (its first ~100 s), with its group list beside it."""
    src = crowd_data("eth_hotel_obsmat.txt")
    out = tmp_path / "hotel_obsmat.txt"
    out.write_text("".join(src.read_text().splitlines(keepends=True)[:400]))
    groups = crowd_data("eth_hotel_groups.txt")
    (tmp_path / "hotel_groups.txt").write_text(groups.read_text())
    return out

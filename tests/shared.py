"""Expectations and parsers shared by several test folders (on the path via pytest's
``pythonpath``)."""

from __future__ import annotations

import html
import re

from socialnav.experiments.planners import compared_planners

# Every planner a comparison runs by default, in display order: a view of the controller
# registry (tests/experiments/test_baselines_e2e.py checks it against the README's list).
ALL_PLANNERS = compared_planners()

# The paper's Table 1 metrics, named as in socialnav.metrics.
TABLE1_KEYS = (
    "total_distance",
    "time_to_goal",
    "lateral_distance",
    "proxemic_intrusions",
    "deviation_distance",
)


def md_tables(text: str) -> list[list[list[str]]]:
    """Markdown tables as rows of cells; ``\\|`` is a literal pipe inside a cell."""
    tables, current = [], []
    for line in [*text.splitlines(), ""]:
        if line.startswith("|"):
            if set(line) <= {"|", "-"}:
                continue
            cells = re.split(r"(?<!\\) \| ", line[2:-2])
            cells = [c.replace("\\|", "|").replace("**", "").replace("`", "") for c in cells]
            current.append(cells)
        elif current:
            tables.append(current)
            current = []
    return tables


def html_tables(text: str) -> list[list[list[str]]]:
    """HTML tables as rows of cell texts (tags stripped, entities decoded, spaces folded)."""
    out = []
    for table in re.findall(r"<table>(.*?)</table>", text, re.S):
        rows = re.findall(r"<tr>(.*?)</tr>", table, re.S)
        cells = [re.findall(r"<t[hd]>(.*?)</t[hd]>", r, re.S) for r in rows]
        text_of = [[html.unescape(re.sub(r"<[^>]+>", "", c)) for c in r] for r in cells]
        out.append([[" ".join(c.split()) for c in r] for r in text_of])
    return out


def crowd_data(name: str):
    """A file of the shared crowd recordings (``../shared/data/crowds`` beside the repository);
    skips the test when the data folder is absent."""
    from pathlib import Path

    import pytest

    path = Path(__file__).resolve().parents[1] / ".." / "shared" / "data" / "crowds" / name
    if not path.is_file():
        pytest.skip(f"shared dataset {name} not available")
    return path

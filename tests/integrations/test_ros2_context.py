"""Context file (no ROS): structures placed by position, attached to tracked people."""

from __future__ import annotations

from pathlib import Path

import pytest

from socialnav.core.errors import ConfigurationError
from socialnav.core.scene import Person
from socialnav.integrations.ros2.context import load_context_file

TEXT = """
groups:
  - members: [[3.0, 1.0], [3.8, 1.2], [3.4, 1.8]]
queues:
  - members: [[5.0, 0.0], [5.0, -0.8]]
    service_point: [5.0, 0.8]
artworks:
  - center: [13.0, 25.0]
    width: 1.2
    facing: -1.5708
    viewers: [[13.0, 23.5]]
"""


def people(*xy: tuple[float, float]) -> tuple[Person, ...]:
    return tuple(Person(10 + i, p) for i, p in enumerate(xy))


@pytest.fixture
def context(tmp_path: Path):
    path = tmp_path / "context.yaml"
    path.write_text(TEXT)
    return load_context_file(path, match_radius=0.5)


def test_structures_attach_to_nearby_people(context) -> None:
    # queue members listed last-first and a little off their spots: order follows the file
    seen = people((3.1, 1.0), (3.7, 1.3), (3.4, 1.7), (5.1, -0.7), (4.9, 0.1), (13.2, 23.4))
    social = context.resolve(seen)
    assert social.groups[0].member_ids == (10, 11, 12)
    assert social.queues[0].member_ids == (14, 13)
    assert social.artworks[0].viewer_ids == (15,)


def test_structures_with_missing_members_are_left_out(context) -> None:
    social = context.resolve(people((3.1, 1.0), (3.7, 1.3), (5.0, 0.0), (20.0, 20.0)))
    assert social.groups == () and social.queues == ()
    assert social.artworks[0].viewer_ids == ()
    assert context.resolve(()).people == ()


def test_one_person_fills_one_slot(context) -> None:
    """Two member spots near one person: one is matched, so the pair is not a group."""
    social = context.resolve(people((3.4, 1.1)))
    assert social.groups == ()


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("groups:\n  - members: [[1, 2]]\n", "groups\\[0\\].members: needs at least 2"),
        ("groups:\n  - members: [[1, 2], [2, 2]]\n    mode: chat\n", "groups\\[0\\]: group mode"),
        ("queues:\n  - members: [[1, 2]]\n", "queues\\[0\\].service_point"),
        ("artworks:\n  - center: [1, 2]\n    width: -1\n", "artworks\\[0\\]: artwork width"),
        ("crowds: []\n", "unknown keys"),
        (
            "queues:\n  - members: [[1, 2]]\n    service_point: [0, 0]\n    spacing: wide\n",
            "queues",
        ),
    ],
)
def test_bad_files_name_file_and_field(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "context.yaml"
    path.write_text(text)
    with pytest.raises(ConfigurationError, match=match) as info:
        load_context_file(path)
    assert str(path) in str(info.value)

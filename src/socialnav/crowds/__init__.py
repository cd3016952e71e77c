"""Recorded pedestrian crowds: loaders, the interpolated recording, and the open-space scene.

No simulator imports: replay lives in ``socialnav.sim.replay``.
"""

from socialnav.crowds.loaders import (
    FORMATS,
    RecordingFormatError,
    load_four_column,
    load_groups,
    load_obsmat,
    load_recording,
    load_trajnet,
    sibling_groups_file,
)
from socialnav.crowds.recording import Area, CrowdState, Recording, Track
from socialnav.crowds.space import area_walls, open_space_costmap

__all__ = [
    "FORMATS",
    "Area",
    "CrowdState",
    "Recording",
    "RecordingFormatError",
    "Track",
    "area_walls",
    "load_four_column",
    "load_groups",
    "load_obsmat",
    "load_recording",
    "load_trajnet",
    "open_space_costmap",
    "sibling_groups_file",
]

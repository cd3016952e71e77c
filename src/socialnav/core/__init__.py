"""Layer 0: types and helpers every other layer shares (NumPy only)."""

from socialnav.core.errors import ConfigurationError, InvalidInputError, SocialNavError
from socialnav.core.geometry import wrap_angle
from socialnav.core.registry import Registry
from socialnav.core.robot import PIONEER, PR2, ROBOT_MODELS, RobotModel
from socialnav.core.scene import Artwork, Group, Person, Queue, SocialContext
from socialnav.core.trajectories import Trajectories

__all__ = [
    "PIONEER",
    "PR2",
    "ROBOT_MODELS",
    "Artwork",
    "ConfigurationError",
    "Group",
    "InvalidInputError",
    "Person",
    "Queue",
    "Registry",
    "RobotModel",
    "SocialContext",
    "SocialNavError",
    "Trajectories",
    "wrap_angle",
]

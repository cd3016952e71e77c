"""A social-structure kind in one module: people waiting at a door (an elevator, a shop door).

The robot that is sent to the door should wait *beside* it, facing it, on the side away from the
people already waiting — not in front of the opening, where it would block whoever comes out.
This module is everything the kind needs: its parameter model (the scenario YAML schema), its
social goal, its success condition and its drawing.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from socialnav.core.episode import EpisodeRecord
from socialnav.core.scene import SocialContext
from socialnav.core.success import CONDITIONS, ConditionCheck, ConditionSpec
from socialnav.social.goals import SocialGoal
from socialnav.social.structures import STRUCTURES, StructureKind


class DoorWaitingParams(BaseModel):
    """``door`` centre (m), ``facing`` yaw of the door's normal into the waiting area (rad),
    ``width`` of the opening (m), ``members`` the people waiting, ``standoff`` (m) from the door
    plane and ``side_offset`` (m) from the door axis of the spot where the robot waits."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    door: tuple[float, float]
    facing: float
    width: float = Field(1.0, gt=0)
    members: tuple[int, ...] = ()
    standoff: float = Field(0.8, gt=0)
    side_offset: float = Field(1.2, gt=0)
    applies_within: float = Field(2.0, gt=0, description="given goal within this of the door (m)")


def _frame(p: DoorWaitingParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    door = np.asarray(p.door, dtype=float)
    normal = np.array([math.cos(p.facing), math.sin(p.facing)])
    return door, normal, np.array([-normal[1], normal[0]])


class DoorWaiting(StructureKind):
    name: ClassVar[str] = "door_waiting"
    description: ClassVar[str] = "people waiting at a door: wait beside it, not in front of it"
    params = DoorWaitingParams
    conditions: ClassVar[tuple[ConditionSpec, ...]] = (ConditionSpec("beside_door"),)

    def social_goal(
        self, params: Any, social: SocialContext, given_goal: np.ndarray, robot_pose: np.ndarray
    ) -> tuple[float, SocialGoal] | None:
        door, normal, along = _frame(params)
        anchor = float(np.linalg.norm(given_goal[:2] - door))
        if anchor > params.applies_within:
            return None
        # The side opposite the waiting people (their mean offset along the door plane).
        lateral = (
            float(np.mean((social.positions(params.members) - door) @ along))
            if (params.members)
            else 0.0
        )
        side = -1.0 if lateral > 0 else 1.0
        spot = door + params.standoff * normal + side * params.side_offset * along
        yaw = math.atan2(door[1] - spot[1], door[0] - spot[0])  # facing the door
        goal = SocialGoal(np.array([spot[0], spot[1], yaw]), kind="door_side")
        return anchor, goal

    def draw(self, ax: Any, params: Any, social: SocialContext) -> None:
        door, _, along = _frame(params)
        a, b = door - 0.5 * params.width * along, door + 0.5 * params.width * along
        ax.plot([a[0], b[0]], [a[1], b[1]], color="#8b5a00", linewidth=4, zorder=3)


def beside_door(record: EpisodeRecord, tolerance: float) -> bool:
    """The robot ends within ``tolerance`` (m) of the target and outside the opening's strip."""
    structure = next(s for s in record.context.structures if s.kind == DoorWaiting.name)
    door, _, along = _frame(structure.params)
    end = record.robot_xy[-1]
    at_spot = float(np.linalg.norm(end - record.target[:2])) <= tolerance
    clear_of_opening = abs(float((end - door) @ along)) > 0.5 * structure.params.width
    return at_spot and clear_of_opening


if DoorWaiting.name not in STRUCTURES:
    STRUCTURES.add(DoorWaiting.name, DoorWaiting())
    CONDITIONS.add(
        "beside_door", ConditionCheck(beside_door, 0.3, "m", "waits beside the door, not before")
    )

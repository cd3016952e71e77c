"""Robot models: kinematics class, footprint and limits (ROS parameter names where they exist)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from socialnav.core.geometry import FloatArray, point_segment_distance, polygon_edges


def rectangle(length: float, width: float) -> tuple[tuple[float, float], ...]:
    """Footprint polygon of a ``length`` (along x) × ``width`` rectangle centred on the robot."""
    hx, hy = length / 2.0, width / 2.0
    return ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))


@dataclass(frozen=True)
class RobotModel:
    """Kinematics and limits. Velocities in m/s and rad/s, accelerations in m/s² and rad/s²."""

    name: str
    holonomic: bool
    footprint: tuple[tuple[float, float], ...]
    max_vel_x: float
    min_vel_x: float
    max_vel_y: float
    max_vel_theta: float
    acc_lim_x: float
    acc_lim_y: float
    acc_lim_theta: float
    min_vel_trans: float = 0.05
    min_vel_theta: float = 0.1
    min_in_place_vel_theta: float = 0.4
    _polygon: FloatArray = field(init=False, repr=False, compare=False)
    # The footprint is frozen: its radii are computed once (planners read them every cycle).
    _radii: tuple[float, float] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        polygon = np.asarray(self.footprint, dtype=float)
        object.__setattr__(self, "_polygon", polygon)
        a, b = polygon_edges(polygon)
        circumscribed = float(np.linalg.norm(polygon, axis=1).max())
        inscribed = float(point_segment_distance(np.zeros(2), a, b).min())
        object.__setattr__(self, "_radii", (circumscribed, inscribed))

    @property
    def max_speed(self) -> float:
        """Top translational speed (m/s): ``hypot(max_vel_x, max_vel_y)`` for a holonomic base
        (ROS ``base_local_planner`` samples x and y independently; the simulator's
        omnidirectional kinematics cap the norm there), ``max_vel_x`` otherwise."""
        return float(np.hypot(self.max_vel_x, self.max_vel_y)) if self.holonomic else self.max_vel_x

    def kinematic_limits(self) -> dict[str, list[float]]:
        """``{"acc_lim": [x, y, theta], "max_vel": [x, y, theta]}`` (m/s², rad/s²; m/s,
        rad/s; ``max_vel`` x is the larger of ``|max_vel_x|`` and ``|min_vel_x|``): what an
        episode record's ``meta`` carries so that metrics can tell how fast the robot can brake
        (``socialnav.metrics.crowd.robot_limits``)."""
        return {
            "acc_lim": [float(self.acc_lim_x), float(self.acc_lim_y), float(self.acc_lim_theta)],
            "max_vel": [
                float(max(abs(self.max_vel_x), abs(self.min_vel_x))),
                float(abs(self.max_vel_y)),
                float(abs(self.max_vel_theta)),
            ],
        }

    @property
    def polygon(self) -> FloatArray:
        """Footprint vertices ``(V, 2)`` in the body frame."""
        return self._polygon

    @property
    def circumscribed_radius(self) -> float:
        """Radius (m) of the smallest circle around the footprint, centred on the robot."""
        return self._radii[0]

    @property
    def inscribed_radius(self) -> float:
        """Radius (m) of the largest circle inside the footprint, centred on the robot."""
        return self._radii[1]


# The scenario suite's two robots, the paper's PR2 and Pioneer.
PR2 = RobotModel(
    name="pr2",
    holonomic=True,
    footprint=rectangle(0.65, 0.65),
    max_vel_x=0.55,
    min_vel_x=-0.1,
    max_vel_y=0.3,
    max_vel_theta=1.0,
    acc_lim_x=2.5,
    acc_lim_y=2.5,
    acc_lim_theta=3.2,
)
PIONEER = RobotModel(
    name="pioneer",
    holonomic=False,
    footprint=rectangle(0.45, 0.38),
    max_vel_x=0.5,
    min_vel_x=-0.1,
    max_vel_y=0.0,
    max_vel_theta=1.0,
    acc_lim_x=1.5,
    acc_lim_y=0.0,
    acc_lim_theta=3.0,
)
ROBOT_MODELS: dict[str, RobotModel] = {PR2.name: PR2, PIONEER.name: PIONEER}

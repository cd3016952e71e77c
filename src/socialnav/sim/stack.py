"""Our navigation stack behind the simulator's :class:`Controller` interface.

Every planner preset (``socialnav.planner.presets.PRESETS``) is registered in ``CONTROLLERS``
under its name and display order, so ``run_episode(scenario, "paccet", …)``, the CLI and
navground's own YAML experiments (through the ``SocialNav`` behaviour) can use it.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from socialnav.core.errors import ConfigurationError, with_overrides
from socialnav.core.geometry import FloatArray
from socialnav.core.robot import RobotModel
from socialnav.core.scene import SocialContext
from socialnav.planner.local_planner import LocalPlannerParams, PlannerResult, PlannerStatus
from socialnav.planner.presets import (
    PRESETS,
    PlannerPreset,
    build_navigator,
    preset_with,
    social_goal_options,
)
from socialnav.planner.recovery import RecoveryParams
from socialnav.sim.controller import CONTROLLERS, register_controller

if TYPE_CHECKING:
    from socialnav.planner.navigator import Navigator
    from socialnav.sim.scenario import Scenario


class StackController:
    """Global plan + local planner of preset ``preset``; ``record`` keeps per-cycle records.

    ``params``: the local planner's ROS-named parameters — a :class:`LocalPlannerParams`, or a
    mapping of field overrides applied to the preset's own parameters (``None``: the preset's).
    ``recovery``: the control loop's progress, waiting, evasion and recovery parameters — a
    :class:`RecoveryParams` or a mapping of field overrides of the preset's (``None``: the
    preset's); e.g. ``{"evasion_ttc": 0}`` switches evasion off.
    ``detour_limit``: the navigator's detour limit on the social global plan (``None``: the
    preset's, :data:`~socialnav.planner.presets.DETOUR_LIMIT` in ``paccet``; 0 switches it off).
    ``partner_spacing``: whether the global plan draws the social goal's interaction partners
    at the interaction's own distance (``None``: the preset's, on in ``paccet``; ``False``
    switches it off; :data:`~socialnav.planner.presets.PARTNER_SPACING`).
    ``global_search``, ``replan_mode``, ``replan_delay``: the navigator's rate-separated
    replanning (:class:`~socialnav.planner.navigator.Navigator`). The defaults are the compiled
    search and ``"deferred"``: the plan requested at step k is applied at step k + 2 (on a
    worker thread, reproducible under any load), so a periodic replan never sits inside a
    control step; ``"inline"`` replans in the step (the implementation before), ``"threaded"``
    is for a real control loop only (not reproducible).
    Raises :class:`~socialnav.core.errors.ConfigurationError` for an unknown preset or field.
    """

    def __init__(
        self,
        preset: str = "paccet",
        record: bool = False,
        params: LocalPlannerParams | Mapping[str, Any] | None = None,
        recovery: RecoveryParams | Mapping[str, Any] | None = None,
        global_search: str = "compiled",
        replan_mode: str = "deferred",
        replan_delay: int = 2,
        detour_limit: float | None = None,
        partner_spacing: bool | None = None,
    ) -> None:
        self.preset_spec = preset_with(preset)
        preset_with(preset, detour_limit, partner_spacing)  # a bad override fails here
        self.detour_limit = detour_limit
        self.partner_spacing = None if partner_spacing is None else bool(partner_spacing)
        self.preset = preset
        self.record = record
        self.params = with_overrides(self.preset_spec.params, params, "local planner")
        self.recovery = with_overrides(self.preset_spec.recovery, recovery, "recovery")
        if global_search not in ("scipy", "compiled"):
            raise ConfigurationError(f"global_search must be scipy|compiled, got {global_search!r}")
        if replan_mode not in ("inline", "deferred", "threaded"):
            raise ConfigurationError(
                f"replan_mode must be inline|deferred|threaded, got {replan_mode!r}"
            )
        self.replan = {
            "global_search": global_search,
            "replan_mode": replan_mode,
            "replan_delay": int(replan_delay),
        }
        self.navigator: Navigator | None = None
        self._robot: RobotModel | None = None

    def social_goal_options(self) -> dict[str, Any]:
        """Keyword options of :func:`~socialnav.social.resolve.resolve_social_goal` that this
        stack's social-goal rule uses for the robot of the last :meth:`reset`
        (:func:`~socialnav.planner.presets.social_goal_options`).
        A context-detected episode measures success at the spot this rule gives on the *true*
        context, so the robot is judged on what it perceived, not on a rule it never used."""
        if self._robot is None or not self.preset_spec.social_goal:
            return {}
        return social_goal_options(self._robot)

    def reset(
        self, scenario: Scenario, robot: RobotModel, social: SocialContext | None = None
    ) -> None:
        """Build the stack for ``scenario``; ``social`` is the context the robot sees at the
        start (default: the scenario's own, i.e. the context given)."""
        if self.navigator is not None:
            self.navigator.close()  # a replan still in flight belongs to the last episode
        self._robot = robot
        self.navigator = build_navigator(
            self.preset,
            robot,
            costmap=scenario.static_costmap(robot),
            goal=np.asarray(scenario.goal, dtype=float),
            social=scenario.social_context(scenario.start) if social is None else social,
            record=self.record,
            params=self.params,
            recovery=self.recovery,
            detour_limit=self.detour_limit,
            partner_spacing=self.partner_spacing,
            **self.replan,  # type: ignore[arg-type]
        )

    def step(
        self, time: float, pose: FloatArray, velocity: FloatArray, social: SocialContext
    ) -> PlannerResult:
        if self.navigator is None:
            return PlannerResult(np.zeros(3), PlannerStatus.INVALID_INPUT, None, "reset() first")
        return self.navigator.step(time, pose, velocity, social)


def register_preset(name: str, preset: PlannerPreset, *, compared: bool = True) -> None:
    """Add ``preset`` to :data:`~socialnav.planner.presets.PRESETS` as ``name`` and its stack
    (:class:`StackController`) as a controller of the same name, so that ``run_episode``,
    ``socialnav run --planner NAME`` and (unless ``compared=False``) ``socialnav compare``
    run it; e.g. ``register_preset("paccet_no_detour", dataclasses.replace(
    PRESETS.get("paccet"), detour_limit=0.0))``. Raises ``ConfigurationError`` if ``name`` is
    taken by another preset or controller."""
    if name in CONTROLLERS and name not in PRESETS:
        raise ConfigurationError(f"controller {name!r} is already registered")
    PRESETS.add(name, preset)
    if name not in CONTROLLERS:
        factory = partial(StackController, name)
        register_controller(
            name, factory, preset.description, order=preset.order, compared=compared, kind="stack"
        )


for _name in PRESETS.names():
    register_preset(_name, PRESETS.get(_name))

"""Policies for the socialnav environments: our planners, and a random baseline.

A :class:`PlannerPolicy` runs any registered controller (our presets ``paccet``,
``traditional``, …; navground's ``hl``, ``orca``, … wrapped as controllers) inside the
environment. Like ``socialnav compare``, it plans on the
scenario's map and the people's true state (``SocialNavEnv.planner_input``), not on the
observation vector — the comparison a learned policy has to win is against the planner as it is
deployed, with its map and tracker. :class:`RandomPolicy` samples the action space.
"""

from __future__ import annotations

from typing import Any

import numpy as np

import socialnav.sim.baselines
import socialnav.sim.stack  # noqa: F401  (importing both registers every controller)
from socialnav.sim.controller import CONTROLLERS, clamp_to_robot

__all__ = ["PlannerPolicy", "RandomPolicy"]


class PlannerPolicy:
    """``policy(obs) -> action`` driving ``env`` (a ``SocialNavEnv``, possibly wrapped) with the
    registered controller ``planner``; call :meth:`reset` after each ``env.reset``."""

    def __init__(self, env: Any, planner: str = "paccet", **params: Any) -> None:
        self.env = env.unwrapped
        self.name = planner
        self.factory = CONTROLLERS.get(planner).factory
        self.params = params
        self.controller: Any = None
        self.last_status = ""

    def reset(self) -> None:
        self.controller = self.factory(**self.params)
        self.controller.reset(self.env.scenario, self.env.robot)

    def __call__(self, observation: Any) -> np.ndarray:
        if self.controller is None:
            self.reset()
        out = self.controller.step(*self.env.planner_input())
        self.last_status = str(out.status)
        return clamp_to_robot(out.cmd, self.env.robot).astype(np.float32)


class RandomPolicy:
    """Uniform samples of the env's action space, seeded (``seed``)."""

    name = "random"

    def __init__(self, env: Any, seed: int = 0) -> None:
        self.space = env.action_space
        self.space.seed(seed)

    def reset(self) -> None:
        pass

    def __call__(self, observation: Any) -> np.ndarray:
        return np.asarray(self.space.sample(), dtype=np.float32)

"""Gymnasium environments of socialnav (the ``gym`` extra: ``pip install 'socialnav[gym]'``).

Importing this package registers, in Gymnasium's registry, under the ``socialnav`` namespace:

- ``socialnav/SocialNav-v0``: every scenario family (hallway, gallery, queue, group), jittered;
- ``socialnav/SocialNavHallway-v0``, ``SocialNavGallery-v0``, ``SocialNavQueue-v0``,
  ``SocialNavGroup-v0``: one family each.

Gymnasium 1.x has no plugin discovery (it was removed in 1.0), so import the package first, or
name it in the id::

    import gymnasium as gym
    import socialnav.integrations.gym

    gym.register_envs(socialnav.integrations.gym)
    env = gym.make("socialnav/SocialNav-v0", robot="pioneer", render_mode="rgb_array")
    # or: gym.make("socialnav.integrations.gym:socialnav/SocialNav-v0")
    envs = gym.make_vec("socialnav/SocialNav-v0", num_envs=4, vectorization_mode="async")

Every keyword of :class:`SocialNavEnv` can be passed to ``make``/``make_vec``.
"""

from __future__ import annotations

from gymnasium.envs.registration import register, registry

from socialnav.integrations.gym.env import SocialNavEnv
from socialnav.integrations.gym.policies import PlannerPolicy, RandomPolicy
from socialnav.integrations.gym.reward import RewardConfig
from socialnav.integrations.gym.scenes import FAMILY_GROUPS, ScenarioPool

__all__ = [
    "ENV_IDS",
    "PlannerPolicy",
    "RandomPolicy",
    "RewardConfig",
    "ScenarioPool",
    "SocialNavEnv",
]

ENTRY_POINT = "socialnav.integrations.gym.env:SocialNavEnv"

#: id → the keyword arguments it adds
ENV_IDS: dict[str, dict[str, object]] = {"socialnav/SocialNav-v0": {}}
for _name, _families in FAMILY_GROUPS.items():
    ENV_IDS[f"socialnav/SocialNav{_name}-v0"] = {"families": list(_families)}

for _id, _kwargs in ENV_IDS.items():
    if _id not in registry:
        # No max_episode_steps: the scenario's own time limit truncates (from inside the env).
        register(id=_id, entry_point=ENTRY_POINT, kwargs=dict(_kwargs))

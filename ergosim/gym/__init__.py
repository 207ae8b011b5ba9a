"""Gymnasium environments (the ``gym`` extra: ``pip install ergosim[gym]``).

Importing this package registers ``ergosim/Allocation-v0`` (:class:`~ergosim.gym.env.AllocationEnv`)::

    import gymnasium as gym
    import ergosim.gym  # noqa: F401 - registers the environment

    env = gym.make("ergosim/Allocation-v0", scenario="multi-subject", repetitions=3)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample(mask=info["action_mask"]))

docs/gym.md describes observations, actions, rewards and the policies of :mod:`ergosim.gym.policies`.
"""

from gymnasium.envs.registration import register, registry

from ergosim.gym.env import TAKT_PENALTY, AllocationEnv
from ergosim.gym.policies import evaluate, mode_policy, random_policy

__all__ = ["AllocationEnv", "TAKT_PENALTY", "ENV_ID", "evaluate", "mode_policy", "random_policy"]

ENV_ID = "ergosim/Allocation-v0"

if ENV_ID not in registry:
    register(id=ENV_ID, entry_point="ergosim.gym.env:AllocationEnv")

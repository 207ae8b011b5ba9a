"""Policies for ``ergosim/Allocation-v0`` and an evaluation loop: a random valid choice, and a mode's own
allocator (``hrc``, the paper's rule; ``kwear-lookahead``) answering through the environment."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["Policy", "random_policy", "mode_policy", "Episode", "evaluate"]

Policy = Callable[[dict, dict, object], int]
"""(observation, info, env) -> action index."""


def random_policy(rng: np.random.Generator) -> Policy:
    """A uniformly random valid (action, agent), drawn from ``rng``."""

    def act(obs: dict, info: dict, env) -> int:
        return int(rng.choice(np.flatnonzero(info["action_mask"])))

    return act


def mode_policy(obs: dict, info: dict, env) -> int:
    """What the environment's mode's allocator decides now (its ``mode_action``); the paper's rule for
    ``mode="hrc"``, the look-ahead for ``mode="kwear-lookahead"``."""
    return env.unwrapped.mode_action()


@dataclass(frozen=True)
class Episode:
    """One episode's return (Σ rewards), steps, KWear integral [s], seconds past the takt, and the
    (action, agent) choices in order."""

    ret: float
    steps: int
    kwear_integral: float
    late_s: float
    choices: tuple[tuple[str, str], ...]


def evaluate(env, policy: Policy, *, seed: int, max_steps: int = 10_000) -> Episode:
    """Run one episode of ``env`` from ``reset(seed=seed)`` with ``policy``."""
    obs, info = env.reset(seed=seed)
    total = kwear = late = 0.0
    steps = 0
    choices = []
    terminated = truncated = False
    while not (terminated or truncated) and steps < max_steps:
        action = policy(obs, info, env)
        if action < 0:
            break
        choices.append(env.unwrapped.choices[action])
        obs, reward, terminated, truncated, info = env.step(action)
        total += float(reward)
        kwear += info.get("kwear_integral", 0.0)
        late += info.get("late_s", 0.0)
        steps += 1
    return Episode(total, steps, kwear, late, tuple(choices))

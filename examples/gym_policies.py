"""Three allocation policies through the Gymnasium environment: random, the paper's rule, the look-ahead.

    python examples/gym_policies.py
    python examples/gym_policies.py --scenario gearbox --reps 4 --seeds 0,1,2

Each policy decides every (action, agent) of one subject's run through ``ergosim/Allocation-v0`` (the same
simulation as ``ergosim run``): a random valid choice, the paper's rule (the ``hrc`` mode's allocator,
eq. 9-11 and AO*) and the look-ahead (``kwear-lookahead``). It prints each policy's return per seed (minus
the KWear integral and the takt penalty, docs/gym.md), the KWear integral, the seconds past the takt, and
the choices of the first repetition.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import ergosim.gym  # noqa: F401 - registers ergosim/Allocation-v0
from ergosim.gym import ENV_ID, evaluate, mode_policy, random_policy


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="multi-subject")
    p.add_argument("--reps", type=int, default=3, help="repetitions per episode")
    p.add_argument("--seeds", default="0,1", help="population seeds, comma-separated")
    a = p.parse_args()
    seeds = [int(s) for s in a.seeds.split(",")]
    policies = {"random": ("hrc", None), "paper's rule (hrc)": ("hrc", mode_policy),
                "look-ahead (kwear-lookahead)": ("kwear-lookahead", mode_policy)}
    print(f"{a.scenario}, subject 0, {a.reps} repetitions per episode")
    print(f"{'policy':30} {'seed':>4} {'return':>9} {'KWear ∫':>9} {'late [s]':>9}  first repetition")
    for name, (mode, policy) in policies.items():
        env = gym.make(ENV_ID, scenario=a.scenario, repetitions=a.reps, mode=mode)
        returns = []
        for seed in seeds:
            act = policy or random_policy(np.random.default_rng(seed))
            ep = evaluate(env, act, seed=seed)
            returns.append(ep.ret)
            first = " ".join(f"{x}:{g[0].upper()}" for x, g in ep.choices[:len(env.unwrapped.actions)])
            print(f"{name:30} {seed:>4} {ep.ret:9.1f} {ep.kwear_integral:9.1f} {ep.late_s:9.1f}  {first}")
        print(f"{name:30} mean return {np.mean(returns):.1f}")


if __name__ == "__main__":
    main()

"""Throughput of ``ergosim/Allocation-v0`` (``scripts/bench_gym.py``): environment steps per second and
simulated seconds per wall second, with one environment per process on every core, side by side.

Each process builds an environment, resets it once (the subject's calibration, timed apart: a seed's
calibration is cached, so later episodes of the same seed skip it), then runs ``episodes`` whole episodes
with a policy (random valid choices, or the mode's allocator) and reports its steps, simulated seconds and
wall seconds. The team's figures are the sums over processes divided by the slowest process's wall time.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import statistics
import time

import numpy as np

__all__ = ["bench_env", "run_episodes"]


def run_episodes(scenario: str, overrides: dict, mode: str, seed: int, episodes: int, repetitions: int | None,
                 policy: str) -> dict:
    """In this process: reset once (timed), then ``episodes`` timed episodes of ``seed``."""
    from ergosim.gym.env import AllocationEnv  # noqa: PLC0415 - imported in the worker process
    from ergosim.gym.policies import evaluate, mode_policy, random_policy  # noqa: PLC0415

    env = AllocationEnv(scenario, overrides=overrides, mode=mode, repetitions=repetitions)
    t0 = time.perf_counter()
    env.reset(seed=seed)
    calibration = time.perf_counter() - t0
    act = mode_policy if policy == "mode" else random_policy(np.random.default_rng(seed))
    steps = 0
    sim = 0.0
    walls = []
    for _ in range(episodes):
        t1 = time.perf_counter()
        episode = evaluate(env, act, seed=seed)
        walls.append(time.perf_counter() - t1)
        steps += episode.steps
        sim += env.result.horizon
    return {"calibration_s": calibration, "wall_s": sum(walls), "steps": steps, "sim_s": sim,
            "episode_wall_s": statistics.median(walls)}


def bench_env(scenario: str = "multi-subject", *, processes: int = 2, episodes: int = 3,
              repetitions: int | None = 10, seed: int = 0, mode: str = "hrc", policy: str = "random",
              overrides: dict | None = None) -> dict:
    """The throughput figures of the module docstring, with ``processes`` environments at once."""
    args = (scenario, dict(overrides or {}), mode, seed, episodes, repetitions, policy)
    ctx = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(max_workers=processes, mp_context=ctx) as pool:
        rows = list(pool.map(run_episodes, *zip(*[args] * processes, strict=True)))
    wall = max(r["wall_s"] for r in rows)
    steps, sim = sum(r["steps"] for r in rows), sum(r["sim_s"] for r in rows)
    return {"scenario": scenario, "mode": mode, "policy": policy, "processes": processes,
            "episodes": episodes, "repetitions": repetitions, "steps": steps, "sim_s": sim, "wall_s": wall,
            "steps_per_s": steps / wall, "realtime_factor": sim / wall,
            "realtime_factor_per_process": [r["sim_s"] / r["wall_s"] for r in rows],
            "calibration_s": [r["calibration_s"] for r in rows]}

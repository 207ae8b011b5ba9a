"""Benchmark ergosim/Allocation-v0: steps per second and real-time factor, one environment per core.

    python scripts/bench_gym.py [--scenario multi-subject] [--processes 2] [--episodes 3] [--reps 10]
                                [--policy random|mode] [--mode hrc] [--json PATH]

Target (issue 24): at least 100x real time on 2 cores. The logic lives in benchmarks.gym.
"""

from __future__ import annotations

import argparse

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from benchmarks.gym import bench_env
from ergosim.atomic import write_json

TARGET_RTF = 100.0


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="multi-subject")
    p.add_argument("--processes", type=int, default=2)
    p.add_argument("--episodes", type=int, default=3)
    p.add_argument("--reps", type=int, default=10, help="repetitions per episode")
    p.add_argument("--policy", choices=("random", "mode"), default="random")
    p.add_argument("--mode", default="hrc")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", dest="json_path")
    a = p.parse_args()
    res = bench_env(a.scenario, processes=a.processes, episodes=a.episodes, repetitions=a.reps, seed=a.seed,
                    mode=a.mode, policy=a.policy)
    print(f"{res['scenario']} ({res['mode']}, {res['policy']} policy): {res['processes']} processes x "
          f"{res['episodes']} episodes of {res['repetitions']} repetitions")
    print(f"  {res['steps']} steps, {res['sim_s']:.0f} s simulated in {res['wall_s']:.1f} s wall")
    print(f"  steps per second      {res['steps_per_s']:8.1f}")
    print(f"  real-time factor      {res['realtime_factor']:8.1f}x  (target >= {TARGET_RTF:g}x on 2 cores); "
          "per process " + ", ".join(f"{x:.0f}x" for x in res["realtime_factor_per_process"]))
    print("  calibration per reset " + ", ".join(f"{x:.1f} s" for x in res["calibration_s"])
          + " (once per seed and subject)")
    verdict = "met" if res["realtime_factor"] >= TARGET_RTF else "MISSED"
    print(f"{verdict:>12}  real-time factor >= {TARGET_RTF:g}x: {res['realtime_factor']:.0f}x")
    if a.json_path:
        write_json(a.json_path, res)


if __name__ == "__main__":
    main()

"""Benchmark the twin loop: real-time factor, overhead over raw mj_step, recording cost, full-run wall time.

    python scripts/bench_sim.py [--mode hrc] [--reps 1] [--repeats 3] [--full] [--json PATH]

``--reps 10`` times a whole subject's run (robot actions included) instead of the first repetition.

Targets (issue 6/7): real-time factor >= 75x; overhead ratio <= 2; recording adds <= 50 %;
the full multi-subject run (240 repetitions) under 180 s on 2 cores.
"""

from __future__ import annotations

import argparse

from ergosim.atomic import write_json
from ergosim.twin.benchmark import bench_full, bench_sim


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="multi-subject")
    parser.add_argument("--mode", default="hrc")
    parser.add_argument("--repeats", type=int, default=3, help="subjects timed; the median is reported")
    parser.add_argument("--reps", type=int, default=1, help="repetitions per timed run")
    parser.add_argument("--full", action="store_true", help="also time the whole scenario with --jobs 2")
    parser.add_argument("--json", dest="json_path")
    args = parser.parse_args()
    res = bench_sim(args.scenario, args.mode, args.repeats, repetitions=args.reps)
    if args.full:
        res["full_run"] = bench_full(args.scenario, jobs=2)
    what = "one repetition" if args.reps == 1 else f"{args.reps} repetitions"
    print(f"{what} of {res['scenario']} ({res['mode']}), median of {res['repeats']} subjects:")
    print(f"  simulated {res['sim_time_s']:.1f} s in {res['wall_s']:.2f} s wall")
    print(f"  real-time factor      {res['realtime_factor']:7.1f}x   (target >= 75x)")
    print(f"  raw mj_step RTF       {res['raw_realtime_factor']:7.1f}x")
    print(f"  overhead ratio        {res['overhead_ratio']:7.2f}    (target <= 2)")
    print(f"  with rerun recording  {res['realtime_factor_recording']:7.1f}x, overhead "
          f"{res['overhead_ratio_recording']:.2f}, recording adds {100 * res['recording_cost']:.0f} % "
          "(target <= 50 %)")
    if "full_run" in res:
        f = res["full_run"]
        print(f"  full {f['scenario']}: {f['repetitions']} repetitions in {f['wall_s']:.0f} s with "
              f"{f['jobs']} jobs (target < 180 s)")
    if args.json_path:
        write_json(args.json_path, res)


if __name__ == "__main__":
    main()

"""Benchmark the twin loop: real-time factor, overhead over raw mj_step, recording cost, full-run wall time.

    python scripts/bench_sim.py [--mode hrc] [--reps 1] [--repeats 3] [--full] [--video] [--json PATH]

``--reps 10`` times a whole subject's run (robot actions included) instead of the first repetition.
``--video`` also measures ``ergosim run --video``: ms per frame (wall and CPU) with worker processes and,
side by side, in one process, on 10 s of a recorded repetition at 960x540, 30 fps; whether the two MP4s
are byte-identical; and what keeping the body poses adds to the simulation. Target (issues 28, 38): <= 40
ms per frame of wall time on 2 cores; ``scripts/bench_video.py --baseline REV`` compares two revisions.

Targets (issue 6/7): real-time factor >= 75x; overhead ratio <= 2; recording adds <= 50 %;
the full multi-subject run (240 repetitions) under 180 s on 2 cores.
"""

from __future__ import annotations

import argparse

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from ergosim.atomic import write_json
from ergosim.cli import headless_gl

headless_gl()  # offscreen rendering for --video, before MuJoCo is imported

from benchmarks.sim import bench_full, bench_sim, bench_video  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="multi-subject")
    parser.add_argument("--mode", default="hrc")
    parser.add_argument("--repeats", type=int, default=3, help="subjects timed; the median is reported")
    parser.add_argument("--reps", type=int, default=1, help="repetitions per timed run")
    parser.add_argument("--full", action="store_true", help="also time the whole scenario with --jobs 2")
    parser.add_argument("--video", action="store_true", help="also measure the cost of --video")
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
    if args.video:
        res["video"] = v = bench_video(args.scenario, repeats=args.repeats)
        print(f"  video ({v['size'][0]}x{v['size'][1]}, 30 fps, {v['frames']} frames, median of "
              f"{v['repeats']}):")
        one = v["one_process"]
        print(f"    {v['ms_per_frame']:.1f} ms per frame with {v['workers']} worker processes "
              f"({v['cpu_ms_per_frame']:.1f} ms of CPU), {one['ms_per_frame']:.1f} ms in one process "
              f"({one['cpu_ms_per_frame']:.1f} ms of CPU): x{v['speedup_over_one_process']:.2f}; MP4 files "
              f"{'byte-identical' if v['identical_mp4'] else 'DIFFER'}")
        print(f"    summed over the workers: scene {v['render_ms_per_frame']:.1f}, overlay "
              f"{v['overlay_ms_per_frame']:.1f} ms per frame; encoder {v['encode_ms_per_frame']:.1f}")
        print(f"    {v['wall_per_sim_second']:.2f} s of wall time per simulated second at x1 "
              f"(x{v['wall_per_sim_second']:.1f} slower than real time; --video-speed X divides it by X)")
        print(f"    filming takes {v['video_over_simulation']:.0f}x the wall time of simulating the same "
              "simulated time")
        print(f"    keeping body poses adds {100 * v['poses_cost']:.0f} % to the simulation "
              f"({v['sim_wall_s']:.2f} s -> {v['sim_wall_s_with_poses']:.2f} s for {v['sim_time_s']:.0f} s "
              "simulated); results are unchanged")
    if args.json_path:
        write_json(args.json_path, res)


if __name__ == "__main__":
    main()

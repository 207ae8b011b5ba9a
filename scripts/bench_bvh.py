"""Benchmark a BVH replay: 1 h of 60 Hz motion capture through ``ergosim replay``, end to end and by stage.

    python scripts/bench_bvh.py [--minutes 60] [--rate 60] [--repeats 3] [--seed 0] [--baseline REV]
                                [--json PATH]

Writes a synthetic recording (seeded) to a temporary directory, replays it ``--repeats`` times in-process
and prints the medians [s]: the whole command, and parse, mapping, RULA + KWear, ticks.csv and
summary.json on their own, as wall and CPU time (the CPU time is the wall time of an idle machine). With
``--baseline REV`` the same recording is then replayed by this checkout and by git revision REV side by
side (two processes asked in turn, benchmarks.replay_baseline), and their outputs are compared byte
for byte. The logic lives in benchmarks.replay.

Target (issue 28): 1 h of 60 Hz BVH in <= 2 s end to end.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from benchmarks.replay import bench_bvh
from benchmarks.replay_baseline import side_by_side
from ergosim.atomic import write_json

TARGET_S = 2.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=60.0, help="length of the recording [min]")
    parser.add_argument("--rate", type=float, default=60.0, help="frame rate of the recording [Hz]")
    parser.add_argument("--repeats", type=int, default=3, help="replays timed; the median is reported")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--baseline", metavar="REV", help="git revision replayed side by side (e.g. main)")
    parser.add_argument("--json", dest="json_path")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        res = bench_bvh(tmp, 60.0 * args.minutes, args.rate, args.repeats, args.seed, progress=print)
        if args.baseline:
            res["side_by_side"] = side_by_side(Path(tmp) / "bench.bvh", Path(tmp), args.baseline,
                                               args.repeats, progress=print)
    res["load_average"] = os.getloadavg()
    rec = res["recording"]
    print(f"{rec['frames']} frames at {rec['rate_hz']:g} Hz ({rec['bytes'] / 1e6:.0f} MB), median of "
          f"{res['repeats']}:")
    print(f"  end to end (ergosim replay): {res['end_to_end_s']:.2f} s wall, "
          f"{res['end_to_end_cpu_s']:.2f} s CPU")
    for stage, s in res["stages_s"].items():
        print(f"  {stage:<11} {s:.2f} s wall, {res['stages_cpu_s'][stage]:.2f} s CPU")
    print(f"  load average {', '.join(f'{x:.2f}' for x in res['load_average'])}")
    if args.minutes == 60.0 and args.rate == 60.0:
        met = "met" if res["end_to_end_s"] <= TARGET_S else "MISSED"
        print(f"{met}: 1 h of 60 Hz BVH in <= {TARGET_S:g} s end to end: {res['end_to_end_s']:.2f} s")
    if args.baseline:
        sbs = res["side_by_side"]
        for side in ("current", "baseline"):
            print(f"  {side:<8} ({args.baseline if side == 'baseline' else 'this checkout'}): "
                  f"{sbs[side]['end_to_end_s']:.2f} s wall, {sbs[side]['end_to_end_cpu_s']:.2f} s CPU")
        print(f"  speed-up {sbs['speedup_wall']:.2f}x wall, {sbs['speedup_cpu']:.2f}x CPU; byte-identical: "
              + ", ".join(f"{f} {'yes' if same else 'NO'}" for f, same in sbs["identical"].items()))
    if args.json_path:
        write_json(args.json_path, res)
        print(f"json: {args.json_path}")
    else:
        keys = ("end_to_end_s", "end_to_end_cpu_s", "stages_s", "stages_cpu_s", "load_average")
        print(json.dumps({k: res[k] for k in keys}))


if __name__ == "__main__":
    main()

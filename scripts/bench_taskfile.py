"""Task-file reading benchmark: parse + build time against the file's size (a linear reader).

    python scripts/bench_taskfile.py [--repeats N] [--json PATH]

The logic lives in benchmarks.planner_taskfile.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from benchmarks.planner_taskfile import run_taskfile_benchmark
from ergosim.atomic import write_json


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="repeats per size (median)")
    parser.add_argument("--json", metavar="PATH", help="write {'rows': [...]} to PATH")
    args = parser.parse_args(argv)
    load = os.getloadavg()[0]
    rows = run_taskfile_benchmark(repeats=args.repeats)
    print(f"{'shape':>8} {'operations':>10} {'lines':>8} {'MB':>6} {'wall [ms]':>10} {'CPU [ms]':>10} "
          f"{'growth':>7}")
    for r in rows:
        growth = "" if r.growth is None else f"{r.growth:.2f}"
        print(f"{r.shape:>8} {r.operations:>10} {r.lines:>8} {r.megabytes:>6.1f} {r.median_ms:>10.1f} "
              f"{r.cpu_ms:>10.1f} {growth:>7}")
    worst = max((r.growth for r in rows if r.growth is not None), default=1.0)
    verdict = "met" if worst <= 1.5 else "MISSED"
    print(f"\n{verdict:>8}  linear reader: worst CPU-time growth {worst:.2f} per size ratio (1 linear in the "
          f"file's size; target <= 1.5); load average {load:.1f} before, {os.getloadavg()[0]:.1f} after")
    if args.json:
        write_json(args.json, {"rows": [dataclasses.asdict(r) for r in rows]})
    return 0


if __name__ == "__main__":
    sys.exit(main())

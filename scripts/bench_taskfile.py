"""Task-file reading benchmark: parse + build time against the number of operations (linear reader).

    python scripts/bench_taskfile.py [--repeats N] [--json PATH]

The logic lives in ergosim.planner.benchmark_taskfile.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from ergosim.atomic import write_json
from ergosim.planner.benchmark_taskfile import run_taskfile_benchmark


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="repeats per size (median)")
    parser.add_argument("--json", metavar="PATH", help="write {'rows': [...]} to PATH")
    args = parser.parse_args(argv)
    rows = run_taskfile_benchmark(repeats=args.repeats)
    print(f"{'operations':>10} {'median [ms]':>12} {'growth':>7}")
    for r in rows:
        growth = "" if r.growth is None else f"{r.growth:.2f}"
        print(f"{r.operations:>10} {r.median_ms:>12.1f} {growth:>7}")
    worst = max((r.growth for r in rows if r.growth is not None), default=1.0)
    verdict = "met" if worst <= 1.5 else "MISSED"
    print(f"\n{verdict:>8}  linear reader: worst growth {worst:.2f} per doubling (1 linear, 2 quadratic; "
          "target <= 1.5)")
    if args.json:
        write_json(args.json, {"rows": [dataclasses.asdict(r) for r in rows]})
    return 0


if __name__ == "__main__":
    sys.exit(main())

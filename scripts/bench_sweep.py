"""Benchmark sweeps: units per second and parallel efficiency against one process, local and Ray.

    python scripts/bench_sweep.py [--units 12] [--repeats 3] [--scenario kwear-validation] [--json [PATH]]

Each configuration (one process; a local pool of 2; a local Ray of 2 CPUs) runs the same one-cell sweep
of --units subjects end to end, start-up included, interleaved within each repeat; medians are reported.
``--json`` alone prints the result as JSON; ``--json PATH`` also writes it to PATH.
"""

from __future__ import annotations

import argparse
import json

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from benchmarks.sweep import bench_sweep
from ergosim.atomic import write_json


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="kwear-validation")
    parser.add_argument("--units", type=int, default=12, help="subjects of the one-cell sweep, a unit each")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", dest="json_path", nargs="?", const="-", metavar="PATH")
    args = parser.parse_args()
    res = bench_sweep(args.scenario, units=args.units, repeats=args.repeats)
    if args.json_path:
        print(json.dumps(res, indent=2, sort_keys=True))
        if args.json_path != "-":
            write_json(args.json_path, res)
        return
    print(f"{res['units']} units of {res['scenario']} (one repetition, {res['mode']}), median of "
          f"{res['repeats']} repeats, {res['cores']} cores:")
    print(f"  {'configuration':<14} {'wall [s]':>9} {'units/s':>8} {'efficiency':>10} {'steady u/s':>10} "
          f"{'steady eff.':>11} {'s per unit':>10}")
    for key, c in res["configs"].items():
        print(f"  {key:<14} {c['wall_s']:9.1f} {c['units_per_s']:8.3f} {c['parallel_efficiency']:10.2f} "
              f"{c['steady_units_per_s']:10.3f} {c['steady_parallel_efficiency']:11.2f} "
              f"{c['unit_wall_s']:10.2f}")
    load = res["load_average"]
    print(f"  ray.init of the local Ray instance: {res['ray_startup_s']:.1f} s (in ray_2's wall time); load "
          f"average before/after {load['before'][0]:.1f}/{load['after'][0]:.1f}")


if __name__ == "__main__":
    main()

"""Compare two layouts of a workcell: who does what, and how much the worker wears, side by side.

    python examples/compare_layouts.py
    python examples/compare_layouts.py --subjects 6 --reps 5 --seed 1
    python examples/compare_layouts.py --scenario gearbox --set scene.furniture.riser.center=0.48,0.20,0.98 \
        --set scene.furniture.riser.half=0.10,0.13,0.08

Layout A is the scenario as its files describe it; layout B is the same scenario with the ``--set``
overrides (default: the multi-subject cell with S1 and S2 moved onto the side table, next to the robot).
Both run with the same synthetic subjects (the same seed), in KWear-driven allocation (``hrc``), through
the Python API (docs/api.md): ``api.load`` with overrides, ``api.run``, and the results as objects.
"""

from __future__ import annotations

import argparse

import numpy as np

from ergosim import api
from ergosim.errors import ErgosimError
from ergosim.overrides import parse_assignments

DEFAULT_B = ["scene.s1_xy=0.40,0.62", "scene.s2_xy=0.52,0.66"]


def compare(scenario: str, layout_b: dict[str, str], *, subjects: int, reps: int, seed: int, jobs: int,
            mode: str = "hrc") -> dict[str, api.Results]:
    """Run ``scenario`` as it is (A) and with ``layout_b`` (B); the results by layout name."""
    protocol = {"subjects": subjects, "repetitions": reps, "modes": [mode]}
    layouts = {"A (as filed)": api.load(scenario, **protocol),
               "B (" + " ".join(f"{k}={v}" for k, v in layout_b.items()) + ")":
                   api.load(scenario, layout_b, **protocol)}
    return {name: api.run(sc, seed=seed, jobs=jobs) for name, sc in layouts.items()}


def report(results: dict[str, api.Results], mode: str = "hrc") -> str:
    """A table: robot share overall and per action, the worker's KWear integral and time above V_th."""
    lines = []
    for name, res in results.items():
        shares = sorted(res.robot_share_by_action(mode).items())
        by_action = "  ".join(f"{a} {100 * s:3.0f}%" for a, s in shares)
        runs = res.runs(mode)
        above = np.mean([r.time_above_threshold for r in runs])
        failures = sum(not a.done for a in res.allocations)
        lines += [f"layout {name}",
                  f"  robot share {100 * res.robot_share(mode):5.1f}%   by action: {by_action}",
                  f"  KWear integral {np.mean(res.kwear_integral(mode)):7.1f} s (mean of {len(runs)} "
                  f"subjects), time above V_th {above:5.1f} s, failed attempts {failures}"]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenario", default="multi-subject", help="a bundled scenario or a scenario file")
    parser.add_argument("--set", dest="assign", action="append", default=None, metavar="KEY=VALUE",
                        help=f"layout B's overrides (default: {' '.join(DEFAULT_B)})")
    parser.add_argument("--subjects", type=int, default=4)
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    try:
        layout_b = parse_assignments(args.assign or DEFAULT_B)
        results = compare(args.scenario, layout_b, subjects=args.subjects, reps=args.reps, seed=args.seed,
                          jobs=args.jobs)
    except ErgosimError as err:  # a bad scenario, key or value: one line, as `ergosim run` says it
        raise SystemExit(f"compare_layouts: error: {err}") from None
    print(report(results))


if __name__ == "__main__":
    main()

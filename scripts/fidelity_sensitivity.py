"""Sensitivity of the fidelity figures: each calibrated parameter moved by -10 % and +10 % (issue 13).

    python scripts/fidelity_sensitivity.py [--out DIR] [--factors 0.9,1.1] [--parameters a,b] [--jobs N]
                                           [--ms-subjects 12] [--robot-subjects 3] [--json PATH]

For every parameter of ergosim.fidelity.sensitivity (shelf height, piece distances, worker pace, robot
transit speed) and factor, runs §7.1 over seeds 0-4 and §7.2 with 12 subjects (``--ms-subjects``) x 10
repetitions (seed 0) and the robot-only repetition (3 subjects, ``--robot-subjects``), and prints the
figures that make the paper's shape. The nominal calibration is the first row.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

from ergosim.atomic import write_json
from ergosim.fidelity.checks import FULL_BOUNDS
from ergosim.fidelity.experiments import Plan
from ergosim.fidelity.sensitivity import PARAMETERS, SensitivityRow, run_sensitivity


def _line(r: SensitivityRow) -> str:
    by = " / ".join(f"{r.share_by_action[a]:.0%}" for a in ("a1", "a2", "a3", "a4"))
    return (f"| {r.parameter} | {r.factor:g} | {r.table1_seeds} | {r.robot_share:.1%} | {by} | "
            f"{r.hrc_repetition_s:.1f} | {r.robot_only_s:.1f} | {r.rows_ok} of {r.rows} |")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results") / "fidelity-sensitivity")
    parser.add_argument("--factors", default="0.9,1.1")
    parser.add_argument("--parameters", default=",".join(PARAMETERS))
    parser.add_argument("--jobs", type=int, default=None)
    parser.add_argument("--ms-subjects", type=int, default=12)
    parser.add_argument("--robot-subjects", type=int, default=3)
    parser.add_argument("--json", metavar="PATH")
    args = parser.parse_args(argv)
    plan = Plan("sensitivity", kv_seeds=(0, 1, 2, 3, 4), ms_seeds=(0,), ms_subjects=args.ms_subjects,
                ms_reps=10, robot_only_subjects=args.robot_subjects)
    factors = tuple(float(f) for f in args.factors.split(","))
    parameters = tuple(p for p in args.parameters.split(",") if p)
    print("| parameter | factor | §7.1 seeds with Table 1's shape | §7.2 robot share | a1 / a2 / a3 / a4 | "
          "mean HRC repetition [s] | robot-only [s] | rows within bounds |")
    print("|---|---|---|---|---|---|---|---|")
    nominal = run_sensitivity(plan, FULL_BOUNDS, args.out, factors=(1.0,), parameters=("pace",),
                              jobs=args.jobs)
    rows = [dataclasses.replace(nominal[0], parameter="nominal")]
    print(_line(rows[0]), flush=True)
    for parameter in parameters:
        for factor in factors:
            row = run_sensitivity(plan, FULL_BOUNDS, args.out, factors=(factor,), parameters=(parameter,),
                                  jobs=args.jobs)[0]
            rows.append(row)
            print(_line(row), flush=True)
    if args.json:
        write_json(args.json, {"rows": [dataclasses.asdict(r) for r in rows]})
    return 0


if __name__ == "__main__":
    sys.exit(main())

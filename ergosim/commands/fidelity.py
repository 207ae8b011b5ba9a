"""``ergosim fidelity``: run the paper's two experiments and compare the twin with the paper, row by row.

ergosim fidelity [--quick] [--seeds N] [--out DIR] [--jobs N]

The full form runs §7.1 (kwear-validation) over seeds 0-4, §7.2 (multi-subject, 12 subjects x 10
repetitions, HRC and H only) over seeds 0-2, and a robot-only (r-only) repetition that times the robot's
whole assembly; ``--quick`` runs a reduced form with looser bounds (what CI runs). Prints the twin-vs-paper
table with ✓ or ✗ per row and writes ``DIR/fidelity.json``, ``DIR/fidelity.png`` and every run's outputs
under ``DIR/runs``. Exit status 0 when every row is within its bound, 1 when one is not (the report is
written either way), 2 on bad input.
"""

from __future__ import annotations

import argparse
import logging
from pathlib import Path

from ergosim.errors import ConfigError

__all__ = ["add_parser", "run"]

log = logging.getLogger(__name__)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "fidelity", help="reproduce the paper's experiments and compare the twin with the paper",
        description="Run §7.1 and §7.2 in the twin and print the twin-vs-paper table (docs/fidelity.md).",
    )
    p.add_argument("--quick", action="store_true", help="the reduced form (fewer seeds and subjects, loose "
                                                       "bounds): what CI runs")
    p.add_argument("--seeds", type=int, metavar="N", help="seeds per experiment, from 0 (default: 5 for §7.1 "
                                                         "and 3 for §7.2; --quick 2 and 1)")
    p.add_argument("--out", default=None, metavar="DIR", help="output directory (default results/fidelity)")
    p.add_argument("--jobs", type=int, metavar="N", help="parallel processes per run (default: all cores)")
    return p


def run(args) -> int:
    from ergosim.fidelity.checks import FULL_BOUNDS, QUICK_BOUNDS, fidelity_rows  # noqa: PLC0415
    from ergosim.fidelity.experiments import FULL, QUICK, run_experiments  # noqa: PLC0415
    from ergosim.fidelity.report import report_text, write_report  # noqa: PLC0415

    if args.seeds is not None and args.seeds < 1:
        raise ConfigError(f"must be >= 1, got {args.seeds}", where="--seeds")
    if args.jobs is not None and args.jobs < 1:
        raise ConfigError(f"must be >= 1, got {args.jobs}", where="--jobs")
    plan, bounds = (QUICK, QUICK_BOUNDS) if args.quick else (FULL, FULL_BOUNDS)
    out = Path(args.out) if args.out else Path("results") / "fidelity"
    if out.exists() and not out.is_dir():
        raise ConfigError(f"{out} exists and is not a directory", where="--out")
    runs = run_experiments(plan, out, seeds=args.seeds, jobs=args.jobs,
                           log=lambda msg: log.info("running %s", msg))
    rows = fidelity_rows(runs, bounds)
    write_report(out, rows, runs, plan)
    print(report_text(rows, plan))
    print(f"\nreport: {(out / 'fidelity.json').resolve()}, figure: {(out / 'fidelity.png').resolve()}")
    return 0 if all(r.ok for r in rows) else 1

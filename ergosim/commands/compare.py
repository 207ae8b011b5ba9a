"""``ergosim compare DIR_A [DIR_B]``: which settings differ and the metric differences between two run or
sweep folders, or between two cells of one sweep.

For every matched cell and every mode in both: the settings that differ, the mean of each metric in A
and in B, the difference B − A with its 95 % confidence interval, and a test, paired (Wilcoxon
signed-rank) where the same subjects of the same seed are in both; with few pairs, the smallest p that
test could give. ``--a-cell`` / ``--b-cell NAME=LEVEL`` choose cells of a sweep (``layout=B``,
``takt=45``, ``cell=3``); with one folder they compare two of its cells.
"""

from __future__ import annotations

import argparse
import json
import sys

from ergosim.errors import ConfigError

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "compare", help="compare two run or sweep folders, or two cells of a sweep: settings, differences, "
                        "tests",
        description="Compare the metrics of two folders written by `ergosim run` or `ergosim sweep`, or of "
                    "two cells of one sweep (one folder, --a-cell and --b-cell).",
    )
    p.add_argument("a", metavar="DIR_A", help="a run folder or a sweep folder")
    p.add_argument("b", metavar="DIR_B", nargs="?", help="a run folder or a sweep folder (default: DIR_A)")
    p.add_argument("--a-cell", action="append", default=[], metavar="NAME=LEVEL",
                   help="the cells of A to compare: a factor's level (layout=B, takt=45) or cell=N "
                        "(repeatable: all must hold)")
    p.add_argument("--b-cell", action="append", default=[], metavar="NAME=LEVEL", help="the cells of B")
    p.add_argument("--metric", action="append", metavar="NAME",
                   help="a metric to compare (repeatable; default: the sweeps' metrics, or robot_share, "
                        "kwear_integral, time_above_vth, takt_overruns)")
    p.add_argument("--json", action="store_true", help="print the comparison as JSON")
    return p


def run(args) -> int:
    from ergosim.sweep.compare import compare_folders, comparison_text, read_folder, select  # noqa: PLC0415

    if args.b is None and not (args.a_cell and args.b_cell):
        raise ConfigError("give a second folder, or --a-cell and --b-cell to compare two cells of one sweep",
                          where="ergosim compare")
    a = read_folder(args.a)
    b = read_folder(args.b) if args.b is not None else a
    a, b = select(a, args.a_cell, "--a-cell"), select(b, args.b_cell, "--b-cell")
    for said in dict.fromkeys(w for w in (a.warning(), b.warning()) if w):
        print(f"ergosim: warning: {said}", file=sys.stderr)
    rows = compare_folders(a, b, args.metric)
    if args.json:
        doc = {"a": str(a.path), "b": str(b.path), "a_cells": list(a.selected), "b_cells": list(b.selected),
               "warnings": list(dict.fromkeys(w for w in (a.warning(), b.warning()) if w)), "rows": rows}
        print(json.dumps(doc, indent=2, allow_nan=False))
    else:
        print(comparison_text(a, b, rows))
    return 0

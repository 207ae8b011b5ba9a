"""``ergosim compare DIR_A DIR_B``: metric differences between two run or sweep folders.

For every cell the two folders share (or the one cell of each) and every mode in both: the mean of each
metric in A and in B, the difference B − A with its 95 % confidence interval, and a test, paired
(Wilcoxon signed-rank) where the same subjects of the same seed are in both folders.
"""

from __future__ import annotations

import argparse
import json

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "compare", help="compare two run or sweep folders: differences with CIs, paired tests",
        description="Compare the metrics of two folders written by `ergosim run` or `ergosim sweep`.",
    )
    p.add_argument("a", metavar="DIR_A", help="a run folder or a sweep folder")
    p.add_argument("b", metavar="DIR_B", help="a run folder or a sweep folder")
    p.add_argument("--metric", action="append", metavar="NAME",
                   help="a metric to compare (repeatable; default: the sweep's metrics, or robot_share, "
                        "kwear_integral, time_above_vth, takt_overruns)")
    p.add_argument("--json", action="store_true", help="print the comparison as JSON")
    return p


def run(args) -> int:
    from ergosim.sweep.compare import compare_folders, comparison_text, read_folder  # noqa: PLC0415

    a, b = read_folder(args.a), read_folder(args.b)
    rows = compare_folders(a, b, args.metric)
    if args.json:
        print(json.dumps({"a": str(a.path), "b": str(b.path), "rows": rows}, indent=2, allow_nan=False))
    else:
        print(comparison_text(a, b, rows))
    return 0

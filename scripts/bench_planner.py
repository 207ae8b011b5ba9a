"""Planner benchmark: fast vs paper replan times on the paper's generated tasks (§6), and beyond.

    python scripts/bench_planner.py [--json PATH] [--plot PATH] [--quick] [--cap SECONDS] [--seed S]
                                    [--team-only] [--lookahead [--baseline REV] [--repeats N]]

First the team decisions (one decision for a whole idle team, beside a replan on the same graph), then the
replan table as rows complete, then the targets; writes a PNG plot and optionally the rows as JSON. The
logic lives in benchmarks.planner and benchmarks.planner_team. ``--lookahead`` times only the
kwear-lookahead decisions (benchmarks.planner_lookahead); ``--baseline REV`` times git revision REV's
look-ahead beside them, decision by decision, and says whether every plan is the same.
"""

from __future__ import annotations

import argparse
import os
import sys

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from benchmarks.planner import (
    DEFAULT_CAP_S,
    check_targets,
    format_row,
    format_table,
    rows_json,
    run_benchmark,
)
from benchmarks.planner_lookahead import (
    beam_quality,
    check_lookahead_target,
    format_lookahead_rows,
    lookahead_rows_json,
    run_lookahead_benchmark,
)
from benchmarks.planner_plot import plot_benchmark
from benchmarks.planner_revision import planner_at
from benchmarks.planner_team import (
    check_team_target,
    format_team_rows,
    run_team_benchmark,
    team_rows_json,
)
from ergosim.atomic import write_json
from ergosim.errors import ErgosimError


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", metavar="PATH", help="write {'rows': [...]} to PATH")
    parser.add_argument("--plot", metavar="PATH", default="bench_planner.png", help="PNG plot path")
    parser.add_argument("--quick", action="store_true", help="fewer, smaller rows (a smoke run)")
    parser.add_argument(
        "--cap",
        type=float,
        default=None,
        help=f"paper planner cap per row [s] (default {DEFAULT_CAP_S:g}, quick 5)",
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of the task and replan costs")
    parser.add_argument("--team-only", action="store_true", help="only the team-decision rows")
    parser.add_argument("--lookahead", action="store_true",
                        help="only the kwear-lookahead rows (decision times; the beam against exact search)")
    parser.add_argument("--baseline", metavar="REV",
                        help="with --lookahead: time revision REV's look-ahead beside, decision by decision")
    parser.add_argument("--repeats", type=int, default=None,
                        help="with --lookahead: decisions per row (default 31, quick 5)")
    args = parser.parse_args(argv)
    if args.lookahead:
        return lookahead(args)
    print("team decisions (every agent idle at the start; times are medians [ms]):", flush=True)
    team = run_team_benchmark(seed=args.seed, quick=args.quick)
    print(format_team_rows(team), flush=True)
    target, met, value = check_team_target(team)
    print(f"{'not measured' if met is None else ('met' if met else 'MISSED'):>12}  {target}: {value}\n")
    if args.team_only:
        if args.json:
            write_json(args.json, {"team": team_rows_json(team)})
        return 0
    cap = args.cap if args.cap is not None else (5.0 if args.quick else DEFAULT_CAP_S)
    print(f"paper planner cap: {cap:g} s per row; times are medians of replans [ms]", flush=True)
    print(format_table([]), flush=True)
    rows = run_benchmark(
        quick=args.quick, cap_s=cap, seed=args.seed, progress=lambda r: print(format_row(r), flush=True)
    )
    print()
    print(format_table(rows))
    print()
    for target, met, value in check_targets(rows):
        verdict = "not measured" if met is None else ("met" if met else "MISSED")
        print(f"{verdict:>12}  {target}: {value}")
    plot_benchmark(rows, args.plot)
    print(f"plot: {args.plot}")
    if args.json:
        write_json(args.json, {**rows_json(rows), "team": team_rows_json(team)})
        print(f"json: {args.json}")
    return 0


def lookahead(args) -> int:
    """The kwear-lookahead rows (issue 24): decision times beside the replan, then the beam's quality."""
    try:
        baseline = planner_at(args.baseline) if args.baseline else None
    except ErgosimError as err:
        print(f"bench_planner: {err}", file=sys.stderr)
        return 2
    print("look-ahead decisions (fresh wear per decision; times are medians [ms]"
          + (f"; beside {args.baseline}'s, alternating" if baseline else "") + "; load average "
          + " ".join(f"{x:.2f}" for x in os.getloadavg()) + "):", flush=True)
    rows = run_lookahead_benchmark(seed=args.seed, quick=args.quick, baseline=baseline, repeats=args.repeats)
    print(format_lookahead_rows(rows), flush=True)
    print("load average after: " + " ".join(f"{x:.2f}" for x in os.getloadavg()), flush=True)
    target, met, value = check_lookahead_target(rows)
    print(f"{'not measured' if met is None else ('met' if met else 'MISSED'):>12}  {target}: {value}\n")
    quality = beam_quality(draws=10 if args.quick else 40, seed=args.seed)
    print("beam against the exact search on sequential:7 (6 free actions, 2 agents):")
    print("   width  same first step  optimal plan  mean excess [%]  max excess [%]  mean reported gap [%]")
    for width, q in quality.items():
        print(f"{width:>8}  {q['same_first']:>15.0%}  {q['optimal']:>12.0%}  {q['mean_excess_pct']:>15.3f}"
              f"  {q['max_excess_pct']:>14.3f}  {q['mean_reported_gap_pct']:>21.1f}")
    if args.json:
        write_json(args.json, {"lookahead": lookahead_rows_json(rows),
                               "beam_quality": {str(k): v for k, v in quality.items()}})
    return 0


if __name__ == "__main__":
    sys.exit(main())

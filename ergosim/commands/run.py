"""``ergosim run SCENARIO``: the paper's experiments end to end in the twin (Fig. 1, §7)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from ergosim.errors import ConfigError
from ergosim.overrides import parse_assignments

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    from ergosim.twin.modes import mode_names  # noqa: PLC0415 - keep `ergosim --help` fast
    from ergosim.twin.scenariofile import scenario_names  # noqa: PLC0415

    p = sub.add_parser(
        "run", help="run a scenario (a bundled one by name, or a scenario file) headless",
        description="Run a scenario in the twin and write summary.json, allocations.csv, ticks.csv and plots "
                    "to --out. Bundled scenarios are listed by `ergosim scenarios`.",
    )
    p.add_argument("scenario", help=f"a scenario file (.toml) or one of: {', '.join(scenario_names())}")
    p.add_argument("--subjects", type=int, help="number of synthetic subjects (default: the scenario's)")
    p.add_argument("--reps", type=int, help="repetitions per subject and mode")
    p.add_argument("--mode", choices=mode_names(), help="run only this mode (default: the scenario's modes)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0); same seed, same results")
    p.add_argument("--jobs", type=int, help="parallel processes (default: all cores)")
    p.add_argument("--out", default=None, help="output directory (default results/<scenario>)")
    p.add_argument("--rrd", metavar="FILE", help="save a rerun recording of the first subject's first mode")
    p.add_argument("--spawn", action="store_true", help="open a rerun viewer and stream to it")
    p.add_argument("--connect", nargs="?", const="default", metavar="URL",
                   help="stream to a running rerun viewer (default URL if none given)")
    p.add_argument("--set", dest="assign", action="append", default=[], metavar="KEY=VALUE",
                   help="override a protocol field (e.g. takt=40) or a workcell field by its dotted path "
                        "or alias (e.g. scene.shelf_height=1.6, scene.parts.L.xy=0.2,0.8)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def _scenario(args):
    from ergosim.twin.scenariofile import load_scenario  # noqa: PLC0415

    own = parse_assignments(args.assign)
    counts = (("--subjects", "subjects", args.subjects), ("--reps", "repetitions", args.reps))
    for flag, field, value in counts:
        if value is not None:
            if value < 1:
                raise ConfigError(f"must be >= 1, got {value}", where=flag)
            own[field] = str(value)
    if args.mode is not None:
        own["modes"] = args.mode
    if args.jobs is not None and args.jobs < 1:
        raise ConfigError(f"must be >= 1, got {args.jobs}", where="--jobs")
    return load_scenario(args.scenario, own)


def _precheck(scenario) -> None:
    """Refuse a run certain to fail before any subject starts (reachability of every action)."""
    from ergosim.scenes import build_cell  # noqa: PLC0415
    from ergosim.twin.scenario_check import check_reachability  # noqa: PLC0415

    check_reachability(scenario, scenario.task(), build_cell(scenario.cell()))


def run(args) -> int:
    from ergosim.twin.scenario_run import run_scenario  # noqa: PLC0415
    from ergosim.twin.summary_text import summary_text  # noqa: PLC0415
    from ergosim.viz import open_recording  # noqa: PLC0415

    scenario = _scenario(args)
    cfg = scenario.protocol
    _precheck(scenario)
    out = Path(args.out) if args.out else Path("results") / scenario.name
    recorder = open_recording(rrd=args.rrd, spawn=args.spawn, connect=args.connect,
                              recording_name=f"ergosim {args.scenario} seed {args.seed}")
    committed = False
    try:
        result = run_scenario(scenario, seed=args.seed, out=out, jobs=args.jobs or os.cpu_count(),
                              progress=not args.quiet, recorder=recorder)
        committed = True
    finally:
        recorder.close(commit=committed)
    print(summary_text(result.summary, cfg))
    print(f"\nresults: {out.resolve()} (summary.json, allocations.csv, ticks.csv, *.png)")
    if args.rrd:
        print(f"recording: {Path(args.rrd).resolve()}  (open it with: rerun {args.rrd})")
    print(f"wall time {result.wall:.1f} s", file=sys.stderr)
    return 0


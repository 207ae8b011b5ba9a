"""``ergosim sweep SWEEP.toml --out DIR``: a design study over layouts, subjects and parameters.

Exit status: 0 every unit completed; 2 bad input (one line, nothing simulated); 3 every unit finished but
some failed or had a repetition abandoned (``results.parquet`` says which and why); 130 / 143 interrupted
by SIGINT / SIGTERM (the finished units are kept; run the same command again to resume).
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
        "sweep", help="run a design study (a sweep file) locally or on a Ray cluster",
        description="Run every (cell, subject, mode, seed) unit of a sweep file and write results.parquet, "
                    "cells.parquet and response plots to --out. A re-run over the same folder skips the "
                    "units already finished. The format is in docs/sweeps.md.",
    )
    p.add_argument("sweep", help="the sweep file (.toml)")
    p.add_argument("--out", help="output folder (default results/<sweep name>)")
    p.add_argument("--executor", choices=("local", "ray"), default="local",
                   help="local: a process pool on this machine (default); ray: Ray tasks")
    p.add_argument("--ray-address", metavar="ADDR",
                   help="a running Ray cluster (e.g. 10.0.0.5:6379, or 'auto'); default: start a local Ray")
    p.add_argument("--jobs", type=int, help="parallel processes (local) or CPUs of a local Ray (default: all "
                                            "cores); with --ray-address, the most units in flight")
    p.add_argument("--retry-failed", action="store_true", help="run failed units again")
    p.add_argument("--dry-run", action="store_true", help="check the file and print the plan; run nothing")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar; log warnings only")
    return p


def _plan_text(sweep, finished: int) -> str:
    lines = [f"sweep {sweep.name}: scenario {sweep.scenario}, {len(sweep.cells)} cell(s) × "
             f"{len(sweep.subjects)} subject(s) × {len(sweep.seeds)} seed(s) × {len(sweep.modes)} mode(s) = "
             f"{sweep.n_units} units ({finished} finished in the folder)"]
    for a in sweep.axes:
        shown = ", ".join(str(v) for v in a.values[:8]) + (", ..." if len(a.values) > 8 else "")
        lines.append(f"  axis {a.key} [{a.block}]: {shown}")
    if sweep.fixed:
        lines.append("  fixed: " + ", ".join(f"{k}={v}" for k, v in sweep.fixed.items()))
    lines.append(f"  modes {', '.join(sweep.modes)}; metrics {', '.join(sweep.metrics)}")
    return "\n".join(lines)


def _cells_text(out: Path, sweep) -> str:
    from ergosim.sweep.tables import read_parquet  # noqa: PLC0415

    rows = read_parquet(out / "cells.parquet").to_pylist()
    if not rows:
        return "no cell has finished every unit yet"
    metrics = list(sweep.metrics)[:4]
    lines = ["cell  mode     " + "  ".join(f"{m:>24}" for m in metrics) + "  cell values"]
    for r in rows[:40]:
        vals = []
        for m in metrics:
            mean, lo, hi = r[f"{m}.mean"], r[f"{m}.ci_low"], r[f"{m}.ci_high"]
            ci = f" [{lo:.3g}, {hi:.3g}]" if lo is not None else ""
            text = "-" if mean is None else f"{mean:.3g}{ci}"
            vals.append(f"{text:>24}")
        lines.append(f"{r['cell']:>4}  {r['mode']:<8} " + "  ".join(vals) + f"  {r['label']}")
    if len(rows) > 40:
        lines.append(f"... {len(rows) - 40} more rows in cells.parquet")
    return "\n".join(lines)


def run(args) -> int:
    from ergosim.sweep.design import load_sweep  # noqa: PLC0415 - keep `ergosim --help` fast
    from ergosim.sweep.folder import SweepFolder  # noqa: PLC0415
    from ergosim.sweep.runner import EXIT_INCOMPLETE, run_sweep  # noqa: PLC0415
    from ergosim.sweep.units import plan_units  # noqa: PLC0415

    if args.jobs is not None and args.jobs < 1:
        raise ConfigError(f"must be >= 1, got {args.jobs}", where="--jobs")
    if args.ray_address and args.executor != "ray":
        raise ConfigError("--ray-address needs --executor ray", where="--ray-address")
    sweep = load_sweep(args.sweep)
    out = Path(args.out) if args.out else Path("results") / sweep.name
    if args.dry_run:
        finished = 0
        if out.is_dir():
            finished = len(SweepFolder(out).finished(u.id for u in plan_units(sweep)))
        print(_plan_text(sweep, finished))
        return 0
    text = Path(args.sweep).read_text(encoding="utf-8")
    log.info("%s", _plan_text(sweep, 0).split("\n", 1)[0].replace(" (0 finished in the folder)", ""))
    result = run_sweep(sweep, out, executor=args.executor, jobs=args.jobs, ray_address=args.ray_address,
                       progress=not args.quiet, retry_failed=args.retry_failed, sweep_text=text)
    print(_cells_text(out, sweep))
    ran = f"{result.ran} run"
    if result.ran:
        ran += f" on {result.executor.get('executor')} with {result.executor.get('workers')} workers"
    print(f"\n{result.finished}/{result.units} units finished ({result.skipped} found done, {ran}), "
          f"{result.failed} failed, {result.abandoned} abandoned, in {result.wall:.1f} s")
    print(f"results: {out.resolve()} (results.parquet, cells.parquet, allocations.parquet"
          + (", " + ", ".join(result.plots) if result.plots else "") + ")")
    if result.status == "incomplete":
        log.warning("ergosim: %d unit(s) failed and %d abandoned a repetition; see the status and error "
                    "columns of results.parquet (exit status 3)", result.failed, result.abandoned)
        return EXIT_INCOMPLETE
    return 0

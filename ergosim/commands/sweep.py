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
    from ergosim.sweep.design import set_string  # noqa: PLC0415
    from ergosim.sweep.stats import SMALL_N  # noqa: PLC0415

    lines = [f"sweep {sweep.name}: scenario {sweep.scenario}, {len(sweep.cells)} cell(s) × "
             f"{len(sweep.subjects)} subject(s) × {len(sweep.seeds)} seed(s) × {len(sweep.modes)} mode(s) = "
             f"{sweep.n_units} units ({finished} finished in the folder)"]
    for f in sweep.factors:
        if f.block == "zip":
            values = {a.key: a.values for a in sweep.axes}
            shown = "; ".join(f"{lv} (" + ", ".join(f"{k}={set_string(values[k][i], k)}" for k in f.keys)
                              + ")" for i, lv in enumerate(f.levels[:8]))
        else:
            shown = ", ".join(f.levels[:8])
        lines.append(f"  factor {f.name} [{f.block}]: {shown}" + (", ..." if len(f.levels) > 8 else ""))
    if sweep.fixed:
        lines.append("  fixed: " + ", ".join(f"{k}={v}" for k, v in sweep.fixed.items()))
    lines.append(f"  modes {', '.join(sweep.modes)}; metrics {', '.join(sweep.metrics)}")
    people = len(sweep.subjects) * len(sweep.seeds)
    if people < SMALL_N:
        lines.append(f"  small n: {people} subject(s) per cell and mode; with fewer than {SMALL_N} the "
                     "intervals are wide and no paired test can reach p < 0.05")
    return "\n".join(lines)


MAX_CELLS_SHOWN = 12
"""Cells the end-of-sweep table shows; the rest are in cells.parquet."""


def _estimate(mean, lo, hi, n) -> str:
    if mean is None:
        return "-"
    from ergosim.sweep.stats import interval_text, round_off  # noqa: PLC0415 - keep `ergosim --help` fast

    ci = f" [{interval_text(lo, hi, mean)}]" if lo is not None and hi is not None else ""
    return f"{round_off(mean, max(abs(mean), abs(lo or 0.0), abs(hi or 0.0))):.3g}{ci} n={n}"


def _cells_text(out: Path, sweep) -> str:
    """Every metric of every cell (up to MAX_CELLS_SHOWN), one line per metric: each mode's mean with its
    95 % interval and n, and each later mode's paired difference from the first with the Wilcoxon p."""
    from ergosim.sweep.stats import SMALL_N  # noqa: PLC0415
    from ergosim.sweep.tables import read_parquet  # noqa: PLC0415

    rows = read_parquet(out / "cells.parquet").to_pylist()
    if not rows:
        return "no cell has finished every unit yet"
    base, others = sweep.modes[0], sweep.modes[1:]
    width = max(len(m) for m in sweep.metrics) + 2
    head = f"  {'metric':<{width}}" + "".join(f"{m:<30}" for m in sweep.modes)
    head += "".join(f"{f'{m} − {base} (paired)':<36}" for m in others)
    lines = ["mean [95 % interval] n=completed units; shares: Wilson, others: t clipped to the metric's "
             "range; abandoned and failed units are left out (docs/sweeps.md)"]
    by_cell: dict[int, dict[str, dict]] = {}
    for r in rows:
        by_cell.setdefault(r["cell"], {})[r["mode"]] = r
    for cell, modes in list(by_cell.items())[:MAX_CELLS_SHOWN]:
        first = next(iter(modes.values()))
        gone = sum(r["units_failed"] + r["units_abandoned"] for r in modes.values())
        note = f"{first['units_counted']} of {first['units']} units per mode counted"
        note += f"; {gone} failed or abandoned, listed below" if gone else ""
        note += f"; small n (< {SMALL_N})" if any(r["small_n"] for r in modes.values()) else ""
        lines += ["", f"cell {cell}  {first['label']}  ({note})", head.rstrip()]
        for m in sweep.metrics:
            line = f"  {m:<{width}}"
            for mode in sweep.modes:
                r = modes.get(mode, {})
                shown = _estimate(*(r.get(f"{m}.{k}") for k in ("mean", "ci_low", "ci_high", "n")))
                line += f"{shown:<30}"
            for mode in others:
                r = modes.get(mode, {})
                d, p, floor = r.get(f"{m}.diff"), r.get(f"{m}.wilcoxon_p"), r.get(f"{m}.wilcoxon_min_p")
                text = "-"
                if d is not None:
                    text = _estimate(d, r.get(f"{m}.diff_ci_low"), r.get(f"{m}.diff_ci_high"),
                                     r.get(f"{m}.pairs"))
                    text += f" p={p:.2g}" if p is not None else ""
                    text += f" (≥{floor:.2g})" if floor is not None and 0.05 <= floor < 1 else ""
                line += f"{text:<36}"
            lines.append(line.rstrip())
    if len(by_cell) > MAX_CELLS_SHOWN:
        lines.append(f"\n... {len(by_cell) - MAX_CELLS_SHOWN} more cells in cells.parquet")
    if any(r["small_n"] for r in rows):
        lines.append("\n(≥p): with so few pairs the Wilcoxon signed-rank test cannot give a p below it "
                     "(2 / 2^n): it cannot show a difference at 0.05")
    return "\n".join(lines) + _left_out_text(out)


def _left_out_text(out: Path, limit: int = 10) -> str:
    """The abandoned and failed units, reported apart from the statistics they are left out of."""
    from ergosim.sweep.tables import read_parquet  # noqa: PLC0415

    rows = [r for r in read_parquet(out / "results.parquet").to_pylist() if r["status"] != "complete"]
    if not rows:
        return ""
    lines = ["", f"{len(rows)} unit(s) left out of the statistics (results.parquet has their rows):"]
    for r in rows[:limit]:
        what = f"  cell {r['cell']} {r['mode']} subject {r['subject']} seed {r['seed']}: {r['status']}"
        if r["status"] == "abandoned":
            what += (f" after {r['repetitions_completed']} completed repetition(s), kwear_integral "
                     f"{r['kwear_integral']:.3g} (partial)")
        lines.append(f"{what}: {r['error']}"[:200])
    if len(rows) > limit:
        lines.append(f"  ... {len(rows) - limit} more")
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

"""kwear-lookahead against the paper's rule on every bundled scenario: three sweeps, a table, a figure.

    python scripts/compare_allocation_modes.py [--out results/allocation_modes] [--jobs 2]
                                               [--figure docs/img/allocation_modes.png] [--quick]

Runs the sweeps of examples/sweeps/allocation_modes/ (kwear-validation: subject 0 of seeds 0-11;
multi-subject: 12 subjects x 10 repetitions; gearbox: 6 subjects x 5 repetitions; both modes per
subject), then prints per scenario and metric the two means, the paired difference with its 95 % interval
and the Wilcoxon signed-rank p over the pairs (the cells.parquet of each sweep), and draws the figure of
docs/allocation_modes.md. A finished sweep is not run again (the sweep resumes). ``--quick``: 3 subjects
(seeds) and 3 repetitions, for a smoke run. The logic lives in benchmarks.mode_study.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path

import _root  # noqa: F401 - the repository's root on sys.path: benchmarks/ is not installed

from benchmarks.mode_study import format_mode_table, mode_rows, plot_mode_study
from ergosim.atomic import write_json
from ergosim.sweep import parse_sweep, run_sweep

SWEEPS = Path(__file__).resolve().parents[1] / "examples" / "sweeps" / "allocation_modes"
SCENARIOS = ("kwear-validation", "multi-subject", "gearbox")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("results/allocation_modes"))
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--figure", type=Path, default=Path("docs/img/allocation_modes.png"))
    p.add_argument("--quick", action="store_true", help="3 subjects (seeds) x 3 repetitions")
    a = p.parse_args(argv)
    studies, folders = {}, {}
    for name in SCENARIOS:
        path = SWEEPS / f"{name}.toml"
        doc = tomllib.loads(path.read_text())
        if a.quick:  # 3 subjects, or 3 seeds of one subject, and 3 repetitions
            seeds = doc.get("seeds", [0])
            doc["seeds"] = seeds[:3] if isinstance(seeds, list) else seeds
            doc["subjects"] = 1 if isinstance(seeds, list) and len(seeds) > 1 else 3
            doc.setdefault("set", {})["repetitions"] = 3
        sweep = parse_sweep(doc, source=str(path), base_dir=path.parent)
        out = a.out / name
        print(f"sweep {sweep.name}: {sweep.n_units} units", flush=True)
        result = run_sweep(sweep, out, jobs=a.jobs, progress=True)
        if result.status != "complete":
            print(f"error: sweep {sweep.name} ended {result.status}", file=sys.stderr)
            return 3
        studies[name] = mode_rows(out, sweep.metrics)
        folders[name] = out
    print()
    print(format_mode_table(studies))
    write_json(a.out / "allocation_modes.json", {k: {"baseline": b, "challenger": c, "rows": rows}
                                                 for k, (b, c, rows) in studies.items()})
    print(f"\nfigure: {plot_mode_study(folders, a.figure)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

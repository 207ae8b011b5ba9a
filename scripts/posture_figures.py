"""Print how the simulated worker stood and moved in finished runs, as a markdown table per run.

    python scripts/posture_figures.py RUN_DIR [RUN_DIR ...]

One row per action of the worker's and one for the whole run: acting ticks, the share with the neck
within 3 deg of its limit, the share standing more than 3 cm behind the spot, the longest step [m], the
deepest knee flexion [deg], the smallest balance margin and clearance [m], G(a_k) and the KWear wear per
execution (ergosim.experiment.posture_checks).
"""

from __future__ import annotations

import argparse
import math

from ergosim.experiment.posture_checks import action_wear, posture_figures


def table(run_dir: str) -> str:
    figures = posture_figures(run_dir)
    wear = action_wear(run_dir)
    rows = ["| action | acting ticks | neck at its limit | behind the spot | step [m] | knees [°] | "
            "balance margin [m] | clearance [m] | G(a_k) | wear per execution |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, f in figures.items():
        g, dv, _ = wear.get(name, (math.nan, math.nan, 0))
        clear = "–" if math.isnan(f.clearance) else f"{f.clearance:.3f}"
        cells = (f"{f.acting_ticks}", f"{100 * f.neck_at_limit:.1f} %", f"{100 * f.behind_spot:.1f} %",
                 f"{f.step:.2f}", f"{f.knee:.0f}", f"{f.com_margin:.3f}", clear,
                 "–" if math.isnan(g) else f"{g:g}", "–" if math.isnan(dv) else f"{dv:.3f}")
        rows.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", help="run folders (ticks.csv, allocations.csv)")
    args = parser.parse_args()
    for run in args.runs:
        print(f"{run}\n\n{table(run)}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Sequential against parallel team execution on one scenario: the figures of issue 17's acceptance.

    python scripts/team_study.py [--scenario multi-subject] [--subjects 12] [--reps 10] [--seed 0]
                                 [--mode hrc] [--jobs 2] [--negotiation] [--out results/team_study]

Runs the scenario twice in one mode, with ``execution = "sequential"`` (the paper's loop) and
``"parallel"`` (every idle agent gets the best ready operation), the same subjects and seeds, into
``OUT/sequential`` and ``OUT/parallel``; then prints, from each run's team figures (``team.json``; the
sequential run's, which writes none, computed the same way from its runs in memory) and ``summary.json``,
throughput, makespan, takt overruns, idle time, the KWear integral, time above V_th, the separation and the
monitor's time, with the parallel/sequential ratios, and writes them to ``OUT/team_study.json``.
``--negotiation`` adds a third run, parallel with negotiation on. Nothing is tuned: both runs use the
scenario's calibrated defaults.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
from scipy.stats import wilcoxon

from ergosim import api
from ergosim.atomic import write_json
from ergosim.errors import ConfigError
from ergosim.experiment.team_metrics import team_document


def _figures(scenario, results, out: Path, mode: str) -> dict:
    runs = [r.runs[mode] for r in results.subjects]
    team = team_document(scenario.protocol, {mode: runs})["modes"][mode]
    summary = json.loads((out / "summary.json").read_text())["modes"][mode]
    safety = team["safety"] or {}
    return {
        "throughput_per_hour": team["throughput_per_hour"],
        "paced_throughput_per_hour": team["paced_throughput_per_hour"],
        "makespan_mean_s": team["makespan_mean_s"],
        "repetitions_completed": team["repetitions_completed"],
        "takt_overruns": team["takt_overruns"],
        "idle_fraction_human": team["idle_fraction"]["human"],
        "idle_fraction_robot": sum(v for k, v in team["idle_fraction"].items() if k != "human"),
        "both_busy_s": team["both_busy_s"],
        "overlapping_repetitions": team["overlapping_repetitions"],
        "kwear_integral": team["kwear_integral"],
        "kwear_integral_by_subject": summary["kwear_integral_by_subject"],
        "time_above_vth_s": team["time_above_vth_s"],
        "robot_share": summary["robot_share"],
        "refusals": team["refusals"],
        "offers": team["offers"],
        "min_separation_m": safety.get("min_separation_m"),
        "end_separation_min_m": safety.get("end_separation_min_m"),
        "robot_slowed_s": safety.get("robot_slowed_s"),
        "robot_stopped_s": safety.get("robot_stopped_s"),
        "overlap_moving_s": safety.get("overlap_moving_s"),
    }


def _fmt(x) -> str:
    if x is None:
        return "–"
    return f"{x:.3g}" if isinstance(x, float) else str(x)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="multi-subject")
    p.add_argument("--subjects", type=int, default=12)
    p.add_argument("--reps", type=int, default=10)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--mode", default="hrc")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--negotiation", action="store_true", help="a third run: parallel with negotiation on")
    p.add_argument("--out", type=Path, default=Path("results/team_study"))
    a = p.parse_args(argv)
    base = {"modes": a.mode, "subjects": str(a.subjects), "repetitions": str(a.reps)}
    settings = {"sequential": {"execution": "sequential"}, "parallel": {"execution": "parallel"}}
    if a.negotiation:
        settings["parallel+negotiation"] = {"execution": "parallel", "negotiation": "true"}
    figures = {}
    try:
        for label, extra in settings.items():
            scenario = api.load(a.scenario, base | extra)
            out = a.out / label.replace("+", "_")
            print(f"running {a.scenario} {label}: {a.subjects} subjects x {a.reps} repetitions", flush=True)
            results = api.run(scenario, seed=a.seed, out=out, jobs=a.jobs)
            figures[label] = _figures(scenario, results, out, a.mode)
    except ConfigError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    seq, par = figures["sequential"], figures["parallel"]
    ratios = {k: par[k] / seq[k] for k in ("throughput_per_hour", "kwear_integral", "makespan_mean_s")
              if seq[k]}
    diff = np.asarray(par["kwear_integral_by_subject"]) - np.asarray(seq["kwear_integral_by_subject"])
    p_kwear = float(wilcoxon(diff).pvalue) if len(diff) >= 2 and np.any(diff != 0) else None
    keys = [k for k in seq if k != "kwear_integral_by_subject"]
    print(f"\n| figure ({a.mode}) | " + " | ".join(figures) + " |")
    print("|---|" + "---|" * len(figures))
    for k in keys:
        print(f"| {k} | " + " | ".join(_fmt(f[k]) for f in figures.values()) + " |")
    print(f"\nparallel / sequential: throughput x{ratios['throughput_per_hour']:.3f}, "
          f"KWear integral x{ratios['kwear_integral']:.3f}, makespan x{ratios['makespan_mean_s']:.3f}; "
          f"takt overruns {seq['takt_overruns']} -> {par['takt_overruns']}; paired Wilcoxon on the subjects' "
          f"KWear integrals p = {_fmt(p_kwear)}")
    write_json(a.out / "team_study.json", {"scenario": a.scenario, "mode": a.mode, "seed": a.seed,
                                           "subjects": a.subjects, "repetitions": a.reps,
                                           "figures": figures, "ratios": ratios, "p_kwear": p_kwear})
    return 0


if __name__ == "__main__":
    sys.exit(main())

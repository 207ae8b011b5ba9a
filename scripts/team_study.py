"""Sequential against parallel team execution on one scenario: the figures of issue 17's acceptance.

    python scripts/team_study.py [--scenario multi-subject] [--subjects 12] [--reps 10] [--seed 0]
                                 [--mode hrc] [--jobs 2] [--negotiation] [--lookahead | --only-lookahead]
                                 [--set KEY=VALUE ...] [--out results/team_study]

Runs the scenario twice in one mode, with ``execution = "sequential"`` (the paper's loop) and
``"parallel"`` (every idle agent gets the best ready operation), the same subjects and seeds, into
``OUT/sequential`` and ``OUT/parallel``; then prints, from each run's team figures (``team.json``; the
sequential run's, which writes none, computed the same way from its runs in memory) and ``summary.json``,
throughput, makespan, takt overruns, idle time, the KWear integral, time above V_th, the separation and the
monitor's time, with the parallel/sequential ratios, and writes them to ``OUT/team_study.json``.
``--negotiation`` adds a run, parallel with negotiation on; ``--lookahead`` a run in parallel with the
``kwear-lookahead`` mode's decisions, which look at time (issue 24); ``--only-lookahead`` runs only the
sequential baseline and that one. Each parallel run is compared with the sequential one (ratios and the
paired Wilcoxon test on the subjects' KWear integrals). Nothing is tuned: every run uses the scenario's
calibrated defaults, with ``--set`` overrides (``ergosim run``'s keys) applied to every run, e.g.
``--set time_weight=0.5`` for a sensitivity row.
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
    p.add_argument("--lookahead", action="store_true",
                   help="another run: parallel with the kwear-lookahead mode's decisions (issue 24)")
    p.add_argument("--only-lookahead", action="store_true",
                   help="run only the sequential baseline and the parallel look-ahead")
    p.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                   help="a protocol or scene override for every run (repeatable)")
    p.add_argument("--out", type=Path, default=Path("results/team_study"))
    a = p.parse_args(argv)
    base = {"modes": a.mode, "subjects": str(a.subjects), "repetitions": str(a.reps)}
    for item in a.overrides:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            print(f"error: --set {item!r}: expected KEY=VALUE", file=sys.stderr)
            return 2
        base[key.strip()] = value.strip()
    settings = {"sequential": {"execution": "sequential"}, "parallel": {"execution": "parallel"}}
    if a.only_lookahead:
        del settings["parallel"]
    if a.negotiation:
        settings["parallel+negotiation"] = {"execution": "parallel", "negotiation": "true"}
    if a.lookahead or a.only_lookahead:
        settings["parallel+lookahead"] = {"execution": "parallel", "modes": "kwear-lookahead"}
    figures = {}
    try:
        for label, extra in settings.items():
            scenario = api.load(a.scenario, base | extra)
            mode = scenario.protocol.modes[0]
            out = a.out / label.replace("+", "_")
            print(f"running {a.scenario} {label} ({mode}): {a.subjects} subjects x {a.reps} repetitions",
                  flush=True)
            results = api.run(scenario, seed=a.seed, out=out, jobs=a.jobs)
            figures[label] = _figures(scenario, results, out, mode)
    except ConfigError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    seq = figures["sequential"]
    keys = [k for k in seq if k != "kwear_integral_by_subject"]
    print(f"\n| figure (sequential: {a.mode}) | " + " | ".join(figures) + " |")
    print("|---|" + "---|" * len(figures))
    for k in keys:
        print(f"| {k} | " + " | ".join(_fmt(f[k]) for f in figures.values()) + " |")
    ratios, p_kwear = {}, {}
    for label, par in figures.items():
        if label == "sequential":
            continue
        ratios[label] = {k: par[k] / seq[k] for k in ("throughput_per_hour", "kwear_integral",
                                                       "makespan_mean_s") if seq[k]}
        diff = np.asarray(par["kwear_integral_by_subject"]) - np.asarray(seq["kwear_integral_by_subject"])
        p_kwear[label] = float(wilcoxon(diff).pvalue) if len(diff) >= 2 and np.any(diff != 0) else None
        r = ratios[label]
        print(f"{label} / sequential: throughput x{r['throughput_per_hour']:.3f}, KWear integral "
              f"x{r['kwear_integral']:.3f}, makespan x{r['makespan_mean_s']:.3f}; takt overruns "
              f"{seq['takt_overruns']} -> {par['takt_overruns']}; paired Wilcoxon on the subjects' KWear "
              f"integrals p = {_fmt(p_kwear[label])}")
    write_json(a.out / "team_study.json", {"scenario": a.scenario, "mode": a.mode, "seed": a.seed,
                                           "subjects": a.subjects, "repetitions": a.reps,
                                           "figures": figures, "ratios": ratios, "p_kwear": p_kwear})
    return 0


if __name__ == "__main__":
    sys.exit(main())

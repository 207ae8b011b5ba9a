"""Turn subject runs into the files a user reads: summary.json, allocations.csv, ticks.csv, plots.

Every file is written atomically (:mod:`ergosim.atomic`), so an interrupted run leaves complete files.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from scipy import stats

from ergosim.atomic import atomic_open, write_json
from ergosim.twin.records import TICK_COLUMNS, Allocation, SubjectRun

__all__ = [
    "summarise",
    "wilcoxon_between",
    "allocation_table",
    "write_allocations",
    "write_ticks",
    "write_summary",
]

ALLOCATION_COLUMNS = (
    "subject", "mode", "repetition", "order", "action", "agent",
    "human_cost", "robot_cost", "t_start", "t_end",
)


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _mode_summary(runs: Sequence[SubjectRun]) -> dict:
    allocs = [a for r in runs for a in r.allocations if a.had_choice]
    robot = [a for a in allocs if a.agent != "human"]
    by_action: dict[str, float] = {}
    for action in sorted({a.action for a in allocs}):
        chosen = [a for a in allocs if a.action == action]
        by_action[action] = sum(a.agent != "human" for a in chosen) / len(chosen)
    ordered = sorted(runs, key=lambda r: r.subject)
    return {
        "actions": len(allocs),
        "robot_actions": len(robot),
        "robot_share": len(robot) / len(allocs) if allocs else 0.0,
        "robot_share_by_action": by_action,
        "repetitions_completed": sum(r.repetitions_completed for r in runs),
        "takt_overruns": sum(r.takt_overruns for r in runs),
        "kwear_integral_by_subject": [r.kwear_integral for r in ordered],
        "kwear_integral_run_by_subject": [r.kwear_integral_run for r in ordered],
        "kwear_mean_by_subject": [r.kwear_mean for r in ordered],
        "time_above_vth_by_subject": [r.time_above_threshold for r in ordered],
        "duration_by_subject": [r.duration for r in ordered],
        "robot_failures": sum(len(r.failures) for r in runs),
    }


def wilcoxon_between(a: Sequence[float], b: Sequence[float], metric: str) -> dict:
    """Paired Wilcoxon signed-rank test of ``a`` against ``b`` (two-sided), as in paper §7.2."""
    x, y = np.asarray(a, float), np.asarray(b, float)
    if x.shape != y.shape or x.size == 0:
        return {"metric": metric, "statistic": None, "p": None, "n": int(x.size)}
    if np.all(x == y):
        return {"metric": metric, "statistic": 0.0, "p": 1.0, "n": int(x.size)}
    res = stats.wilcoxon(x, y)
    return {"metric": metric, "statistic": _finite(res.statistic), "p": _finite(res.pvalue), "n": int(x.size)}


def allocation_table(runs: Sequence[SubjectRun], actions: Sequence[str]) -> list[list[str]]:
    """Per repetition, "H" or "R" for each action in ``actions`` order (paper Table 1)."""
    table: list[list[str]] = []
    for run in sorted(runs, key=lambda r: r.subject):
        reps = sorted({a.repetition for a in run.allocations})
        for rep in reps:
            row = {a.action: "H" if a.agent == "human" else "R"
                   for a in run.allocations if a.repetition == rep}
            table.append([row.get(action, "-") for action in actions])
    return table


def summarise(scenario: str, seed: int, runs_by_mode: dict[str, list[SubjectRun]], *,
              actions: Sequence[str], complete: bool = True, extra: dict | None = None) -> dict:
    summary: dict = {
        "scenario": scenario,
        "seed": seed,
        "complete": complete,
        "modes": {mode: _mode_summary(runs) for mode, runs in runs_by_mode.items()},
    }
    if "hrc" in runs_by_mode and "h-only" in runs_by_mode:
        # Paired by subject, hrc against h-only (paper §7.2). The headline metric is the KWear integral over
        # the production schedule; the others are reported beside it.
        h_only = {r.subject: r for r in runs_by_mode["h-only"]}
        common = [r for r in sorted(runs_by_mode["hrc"], key=lambda r: r.subject) if r.subject in h_only]
        tests = {
            metric: wilcoxon_between([getattr(r, attr) for r in common],
                                     [getattr(h_only[r.subject], attr) for r in common], metric)
            for metric, attr in (("kwear_integral", "kwear_integral"),
                                 ("kwear_integral_run", "kwear_integral_run"),
                                 ("kwear_mean", "kwear_mean"),
                                 ("time_above_vth", "time_above_threshold"))
        }
        summary["wilcoxon"] = tests["kwear_integral"]
        summary["wilcoxon_by_metric"] = tests
    tables = {
        key: allocation_table(runs_by_mode[mode], actions)
        for key, mode in (("kwear", "hrc"), ("rula", "rula"))
        if mode in runs_by_mode
    }
    if tables:
        summary["allocation_table"] = tables
    if extra:
        summary.update(extra)
    return summary


def write_summary(path: Path, summary: dict) -> None:
    write_json(path, summary)


def write_allocations(path: Path, allocations: Sequence[Allocation]) -> None:
    with atomic_open(path, "w") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(ALLOCATION_COLUMNS)
        for a in allocations:
            row = dataclasses.asdict(a)
            writer.writerow([
                row["subject"], row["mode"], row["repetition"], row["order"], row["action"], row["agent"],
                repr(float(row["human_cost"])), repr(float(row["robot_cost"])),
                f"{row['t_start']:.4f}", f"{row['t_end']:.4f}",
            ])


def write_ticks(path: Path, runs: Sequence[SubjectRun]) -> None:
    """ticks.csv: subject, mode, then :data:`TICK_COLUMNS` at the ergonomics rate (NaN = dropout)."""
    with atomic_open(path, "w") as f:
        f.write(",".join(("subject", "mode") + TICK_COLUMNS) + "\n")
        for run in sorted(runs, key=lambda r: (r.mode, r.subject)):
            rows = run.ticks.rows
            if rows.size == 0:
                continue
            buf = io.StringIO()
            # 9 significant digits keep KWear well below the 1e-6 used to compare with recordings.
            np.savetxt(buf, rows, fmt="%.9g", delimiter=",")
            prefix = f"{run.subject},{run.mode},"
            f.write("".join(prefix + line + "\n" for line in buf.getvalue().splitlines()))

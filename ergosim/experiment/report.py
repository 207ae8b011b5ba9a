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
from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.modes import mode_or_default
from ergosim.twin.records import TICK_COLUMNS, Allocation, Failure, SubjectRun

__all__ = [
    "summarise",
    "allocation_rows",
    "wilcoxon_between",
    "allocation_table",
    "write_allocations",
    "write_failures",
    "write_ticks",
    "write_summary",
    "write_subjects",
    "write_action_traces",
    "ALLOCATION_COLUMNS",
    "FAILURE_COLUMNS",
    "SUBJECT_COLUMNS",
    "ACTION_TRACE_COLUMNS",
]

ALLOCATION_COLUMNS = (
    "subject", "mode", "repetition", "order", "action", "agent",
    "human_cost", "robot_cost", "t_start", "t_end", "status", "attempt", "forced", "allocatable",
)
"""Columns of ``allocations.csv``: one row per attempt (see :class:`~ergosim.twin.records.Allocation`)."""

FAILURE_COLUMNS = ("time", "subject", "mode", "repetition", "action", "agent", "status", "message")
"""Columns of ``failures.csv``: one row per failed attempt or abandoned repetition."""

SUBJECT_COLUMNS = (
    "subject", "worker", "mode", "repetitions_completed", "repetitions_abandoned", "takt_overruns",
    "kwear_integral", "kwear_integral_run", "kwear_mean", "time_above_vth", "duration", "actions_completed",
    "robot_actions", "worker_agent",
)
"""Columns of ``subjects.csv``: one row per subject and mode; the per-subject figures of ``summary.json``
(``kwear_integral`` [s] over repetitions × takt, ``kwear_integral_run`` [s] over the whole run,
``kwear_mean``, ``time_above_vth`` [s], ``duration`` [s]), floats written exactly (``repr``)."""

ACTION_TRACE_COLUMNS = ("subject", "action", "t") + tuple(f"kwear_{j}" for j in KWEAR_JOINTS)
"""Columns of ``kwear_actions.csv``: KWear per joint while the worker performs each action once from zero wear
(the first calibration execution), ``t`` [s] from the action's start (paper §7.1, the KWear figure)."""


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _share(rows: Sequence[tuple[Allocation, bool]]) -> tuple[int, int, float, dict[str, float]]:
    """(robot rows, rows, robot share, robot share per action) of ``rows``, (allocation, by a robot) pairs."""
    robot = sum(r for _, r in rows)
    by_action = {}
    for action in sorted({a.action for a, _ in rows}):
        of = [r for a, r in rows if a.action == action]
        by_action[action] = sum(of) / len(of)
    return robot, len(rows), robot / len(rows) if rows else 0.0, by_action


def _cell(rows: Sequence[Allocation], human: str) -> str:
    """One action in one repetition: H / R for who completed it (the worker ``human``, a robot), ``*``
    forced, ``!`` after a failed attempt, ``-`` not done, ``x`` abandoned with every agent pruned."""
    done = [a for a in rows if a.done]
    mark = "x" if any(a.status == "pruned" for a in rows) else "-"
    if done:
        mark = ("H" if done[-1].agent == human else "R") + ("*" if done[-1].forced else "")
    return mark + ("!" if any(a.status.startswith("failed:") for a in rows) else "")


def allocation_rows(runs: Sequence[SubjectRun], actions: Sequence[str]) -> list[dict]:
    """Per subject and repetition: ``{"subject", "repetition", "outcome", "cells": {action: cell}}`` with
    the cells of :func:`_cell`, for every repetition of the schedule (ones not run have "-" cells)."""
    out = []
    for run in sorted(runs, key=lambda r: r.subject):
        outcomes = {o.repetition: o.outcome for o in run.outcomes}
        for rep in sorted(outcomes or {a.repetition for a in run.allocations}):
            of = [a for a in run.allocations if a.repetition == rep]
            out.append({"subject": run.subject, "repetition": rep, "outcome": outcomes.get(rep, ""),
                        "cells": {x: _cell([a for a in of if a.action == x], run.human) for x in actions}})
    return out


def _mode_summary(runs: Sequence[SubjectRun], actions: Sequence[str] = ()) -> dict:
    rows = [(a, r.by_robot(a.agent)) for r in runs for a in r.allocations]
    every = [a for a, _ in rows]
    # robot_share: completed actions only, whoever could be chosen (a forced robot action counts, a failed
    # robot attempt does not); robot_share_chosen: every decision where both agents could be chosen.
    robot, n, share, by_action = _share([(a, by) for a, by in rows if a.done and a.allocatable])
    chosen = [(a, by) for a, by in rows if a.had_choice]
    chosen_robot, chosen_n, chosen_share, chosen_by_action = _share(chosen)
    failures = [(f, r.by_robot(f.agent), f.agent == r.human) for r in runs for f in r.failures]
    outcomes = [o for r in sorted(runs, key=lambda r: r.subject) for o in r.outcomes]
    ordered = sorted(runs, key=lambda r: r.subject)
    return {
        "actions": n,
        "robot_actions": robot,
        "robot_share": share,
        "robot_share_by_action": by_action,
        "choices": chosen_n,
        "robot_choices": chosen_robot,
        "robot_share_chosen": chosen_share,
        "robot_share_chosen_by_action": chosen_by_action,
        "forced_robot_actions": sum(bool(a.forced) and by for a, by in rows),
        "forced_human_actions": sum(bool(a.forced) and not by for a, by in rows),
        "attempts": len([a for a in every if a.status != "pruned"]),
        "failed_attempts": sum(a.status.startswith("failed:") for a in every),
        "repetitions": [o.to_dict() for o in outcomes],
        "repetitions_abandoned": sum(o.outcome == "abandoned" for o in outcomes),
        "repetitions_not_run": sum(o.outcome == "not_run" for o in outcomes),
        "repetitions_completed": sum(r.repetitions_completed for r in runs),
        "takt_overruns": sum(r.takt_overruns for r in runs),
        "kwear_integral_by_subject": [r.kwear_integral for r in ordered],
        "kwear_integral_run_by_subject": [r.kwear_integral_run for r in ordered],
        "kwear_mean_by_subject": [r.kwear_mean for r in ordered],
        "time_above_vth_by_subject": [r.time_above_threshold for r in ordered],
        "duration_by_subject": [r.duration for r in ordered],
        "allocation_rows": allocation_rows(runs, actions),
        "robot_failures": sum(robot for _, robot, _ in failures),
        "worker_failures": sum(worker for _, _, worker in failures),
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
            row = {a.action: "R" if run.by_robot(a.agent) else "H"
                   for a in run.allocations if a.repetition == rep and a.done}
            table.append([row.get(action, "-") for action in actions])
    return table


def summarise(scenario: str, seed: int, runs_by_mode: dict[str, list[SubjectRun]], *,
              actions: Sequence[str], complete: bool = True, extra: dict | None = None) -> dict:
    summary: dict = {
        "scenario": scenario,
        "seed": seed,
        "complete": complete,
        "modes": {mode: _mode_summary(runs, actions) for mode, runs in runs_by_mode.items()},
        "action_labels": list(actions),
    }
    pairs = [(m, mode_or_default(m).paired_with) for m in runs_by_mode]
    pairs = [(m, other) for m, other in pairs if other in runs_by_mode]
    if pairs:
        # Paired by subject, a mode against the mode it is paired with: hrc against h-only (paper §7.2). The
        # headline metric is the KWear integral over the production schedule; the others are beside it.
        mode, other = pairs[0]
        h_only = {r.subject: r for r in runs_by_mode[other]}
        common = [r for r in sorted(runs_by_mode[mode], key=lambda r: r.subject) if r.subject in h_only]
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
    keys = [(mode_or_default(m).table_key, m) for m in runs_by_mode if mode_or_default(m).table_key]
    tables = {key: allocation_table(runs_by_mode[mode], actions) for key, mode in keys}
    if tables:
        summary["allocation_table"] = tables
    if extra:
        summary.update(extra)
    return summary


def write_summary(path: Path, summary: dict) -> None:
    write_json(path, summary)


def write_allocations(path: Path, allocations: Sequence[Allocation]) -> None:
    """allocations.csv: :data:`ALLOCATION_COLUMNS`, one row per attempt, atomically."""
    with atomic_open(path, "w") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(ALLOCATION_COLUMNS)
        for a in allocations:
            row = dataclasses.asdict(a)
            writer.writerow([
                row["subject"], row["mode"], row["repetition"], row["order"], row["action"], row["agent"],
                repr(float(row["human_cost"])), repr(float(row["robot_cost"])),
                f"{row['t_start']:.4f}", f"{row['t_end']:.4f}",
                row["status"], row["attempt"], row["forced"], int(row["allocatable"]),
            ])


def write_failures(path: Path, failures: Sequence[Failure]) -> None:
    """failures.csv: :data:`FAILURE_COLUMNS`, one row per failed attempt or abandoned repetition."""
    with atomic_open(path, "w") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(FAILURE_COLUMNS)
        for x in failures:
            writer.writerow([f"{x.time:.4f}", x.subject, x.mode, x.repetition, x.action, x.agent, x.status,
                             x.message])


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


def write_subjects(path: Path, runs: Sequence[tuple[str, SubjectRun]]) -> None:
    """subjects.csv: :data:`SUBJECT_COLUMNS` for each (worker name, run), in the order given."""
    with atomic_open(path, "w") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(SUBJECT_COLUMNS)
        for worker, r in runs:
            done = [a for a in r.allocations if a.done]
            writer.writerow([
                r.subject, worker, r.mode, r.repetitions_completed,
                sum(o.outcome == "abandoned" for o in r.outcomes), r.takt_overruns,
                repr(r.kwear_integral), repr(r.kwear_integral_run), repr(r.kwear_mean),
                repr(r.time_above_threshold), repr(r.duration), len(done),
                sum(r.by_robot(a.agent) for a in done), r.human,
            ])


def write_action_traces(path: Path, traces: Sequence[tuple[int, str, np.ndarray, np.ndarray]]) -> None:
    """kwear_actions.csv: :data:`ACTION_TRACE_COLUMNS` for each (subject, action, t (n,) [s], V (n, 5))."""
    with atomic_open(path, "w") as f:
        f.write(",".join(ACTION_TRACE_COLUMNS) + "\n")
        for subject, action, t, v in traces:
            buf = io.StringIO()
            np.savetxt(buf, np.column_stack([t, v]), fmt="%.9g", delimiter=",")
            f.write("".join(f"{subject},{action}," + line + "\n" for line in buf.getvalue().splitlines()))

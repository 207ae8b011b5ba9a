"""summary.json: the figures of a run, computed from its subject records (paper §7: robot share, Table 1,
the load proxies and the Wilcoxon test of §7.2).

``ergosim run`` computes it after every finished subject, ``ergosim merge`` from the records of several
shards; both go through :func:`summary_of`, so the merged summary of shards that cover every subject is the
unsharded one byte for byte. :func:`summarise` reads runs through the attributes
:class:`~ergosim.twin.records.SubjectRun` and :class:`~ergosim.experiment.subject_records.RunRecord` share.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ergosim.experiment.calibration_summary import calibration_summary
from ergosim.experiment.subject_records import SubjectRecord
from ergosim.twin.modes import mode_or_default
from ergosim.twin.records import Allocation, SubjectRun

__all__ = ["summarise", "summary_of", "allocation_rows", "wilcoxon_between", "wilcoxon_min_p",
           "too_few_pairs", "allocation_table"]


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


def wilcoxon_min_p(n: int) -> float:
    """The smallest two-sided p a Wilcoxon signed-rank test can give with ``n`` non-zero differences:
    every difference of one sign, probability 2 / 2ⁿ under the null (exact distribution)."""
    return 1.0 if n <= 0 else min(1.0, 2.0 / 2.0**n)


def too_few_pairs(n: int, alpha: float = 0.05) -> bool:
    """``n`` pairs cannot give a two-sided Wilcoxon p below ``alpha`` whatever the data (2 / 2ⁿ ≥ ``alpha``:
    fewer than 6 pairs at 0.05), so no statistic is worth printing for them."""
    return wilcoxon_min_p(n) >= alpha


def wilcoxon_between(a: Sequence[float], b: Sequence[float], metric: str) -> dict:
    """Paired Wilcoxon signed-rank test of ``a`` against ``b`` (two-sided), as in paper §7.2."""
    x, y = np.asarray(a, float), np.asarray(b, float)
    if x.shape != y.shape or x.size == 0:
        return {"metric": metric, "statistic": None, "p": None, "n": int(x.size)}
    if np.all(x == y):
        return {"metric": metric, "statistic": 0.0, "p": 1.0, "n": int(x.size)}
    from scipy import stats  # noqa: PLC0415 - 1.2 s of start-up that runs of one mode never need

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
        for test in tests.values():
            test["modes"] = [mode, other]  # what was compared, named as the run named its modes
        summary["wilcoxon"] = tests["kwear_integral"]
        summary["wilcoxon_by_metric"] = tests
    keys = [(mode_or_default(m).table_key, m) for m in runs_by_mode if mode_or_default(m).table_key]
    tables = {key: allocation_table(runs_by_mode[mode], actions) for key, mode in keys}
    if tables:
        summary["allocation_table"] = tables
    if extra:
        summary.update(extra)
    return summary


def summary_of(scenario: str, seed: int, config: Mapping[str, Any], records: Sequence[SubjectRecord], *,
               subject_range: tuple[int, int], complete: bool, status: str = "running") -> dict:
    """The ``summary.json`` document of ``records`` (any order). ``subject_range`` ``[first, end)``: the
    subjects the run was asked for; a shard (not ``[0, subjects)``) says so in ``subject_range``."""
    records = sorted(records, key=lambda r: r.subject)
    modes = {m: [r.runs[m] for r in records if m in r.runs] for m in config["modes"]}
    extra = {
        "subjects": [r.name for r in records],
        "calibration": calibration_summary(records),
        "config": dict(config),
    }
    actions = sorted(records[0].alphas) if records else []
    summary = summarise(scenario, seed, modes, actions=actions, complete=complete, extra=extra)
    summary["rula_g_by_action"] = extra["calibration"]["rula_g_by_action"]  # G(a_k) per action, over subjects
    if "reba_g_by_action" in extra["calibration"]:
        summary["reba_g_by_action"] = extra["calibration"]["reba_g_by_action"]
    abandoned = sum(m["repetitions_abandoned"] for m in summary["modes"].values())
    summary["status"] = "abandoned" if status == "complete" and abandoned else status
    summary["complete"] = complete and not abandoned
    summary["subjects_finished"] = len(records)
    summary["subjects_planned"] = subject_range[1] - subject_range[0]
    summary["repetitions_abandoned"] = abandoned
    if tuple(subject_range) != (0, config["subjects"]):
        summary["subject_range"] = list(subject_range)
    return summary

"""The CSV files of a run: allocations.csv, decisions.csv, failures.csv, ticks.csv, subjects.csv and
kwear_actions.csv.

Every file is written atomically (:mod:`ergosim.atomic`), so an interrupted run leaves complete files.
Floats that a figure is computed from are written exactly (``repr``).
"""

from __future__ import annotations

import csv
import dataclasses
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ergosim.atomic import atomic_open
from ergosim.g9_csv import g9_csv
from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.records import TICK_COLUMNS, Allocation, Failure, SubjectRun
from ergosim.viz.reason import reason_text

__all__ = ["subject_row", "write_allocations", "write_decisions", "write_failures", "write_ticks",
           "write_subjects", "write_action_traces", "ALLOCATION_COLUMNS", "DECISION_COLUMNS",
           "FAILURE_COLUMNS", "SUBJECT_COLUMNS", "ACTION_TRACE_COLUMNS"]

ALLOCATION_COLUMNS = (
    "subject", "mode", "repetition", "order", "action", "agent",
    "human_cost", "robot_cost", "t_start", "t_end", "status", "attempt", "forced", "allocatable",
)
"""Columns of ``allocations.csv``: one row per attempt (see :class:`~ergosim.twin.records.Allocation`)."""

DECISION_COLUMNS = ("time", "subject", "mode", "repetition", "action", "agent", "reason")
"""Columns of ``decisions.csv``: one row per allocation decision, ``reason`` the sentence of
:func:`~ergosim.viz.reason.reason_text` (what the recording and the video show)."""

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


def write_decisions(path: Path, runs: Sequence[SubjectRun]) -> None:
    """decisions.csv: :data:`DECISION_COLUMNS`, every decision of each run in the order given, atomically."""
    with atomic_open(path, "w") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(DECISION_COLUMNS)
        for run in runs:
            for d in run.decisions:
                writer.writerow([f"{d.time:.4f}", run.subject, run.mode, d.repetition, d.action, d.agent,
                                 reason_text(d)])


def write_failures(path: Path, failures: Sequence[Failure]) -> None:
    """failures.csv: :data:`FAILURE_COLUMNS`, one row per failed attempt or abandoned repetition."""
    with atomic_open(path, "w") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(FAILURE_COLUMNS)
        for x in failures:
            writer.writerow([f"{x.time:.4f}", x.subject, x.mode, x.repetition, x.action, x.agent, x.status,
                             x.message])


def write_ticks(path: Path, runs: Sequence[SubjectRun]) -> None:
    """ticks.csv: subject, mode, then :data:`TICK_COLUMNS` at the ergonomics rate (NaN = dropout), then the
    columns of any further posture feature a run's risk index read (REBA's, with ``kwear_legs``; NaN in the
    rows of a mode without them)."""
    columns = tuple(dict.fromkeys(c for run in runs for c in run.ticks.columns)) or TICK_COLUMNS
    with atomic_open(path, "w") as f:
        f.write(",".join(("subject", "mode") + columns) + "\n")
        for run in sorted(runs, key=lambda r: (r.mode, r.subject)):
            rows = run.ticks.rows
            if rows.size == 0:
                continue
            if run.ticks.columns != columns:
                full = np.full((len(rows), len(columns)), np.nan)
                full[:, [columns.index(c) for c in run.ticks.columns]] = rows
                rows = full
            # 9 significant digits keep KWear well below the 1e-6 used to compare with recordings: the bytes
            # of np.savetxt(fmt="%.9g"), built in bulk (ergosim/g9_csv.py)
            prefix = f"{run.subject},{run.mode},"
            f.write("".join(prefix + line + "\n" for line in g9_csv(rows).decode().splitlines()))


def subject_row(worker: str, r: SubjectRun) -> list:
    """The :data:`SUBJECT_COLUMNS` values of ``r``, the run of the worker named ``worker``."""
    done = [a for a in r.allocations if a.done]
    return [r.subject, worker, r.mode, r.repetitions_completed,
            sum(o.outcome == "abandoned" for o in r.outcomes), r.takt_overruns, float(r.kwear_integral),
            float(r.kwear_integral_run), float(r.kwear_mean), float(r.time_above_threshold),
            float(r.duration), len(done), sum(r.by_robot(a.agent) for a in done), r.human]


def write_subjects(path: Path, runs: Sequence[tuple[str, SubjectRun]]) -> None:
    """subjects.csv: :data:`SUBJECT_COLUMNS` for each (worker name, run), in the order given."""
    with atomic_open(path, "w") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(SUBJECT_COLUMNS)
        for worker, r in runs:
            writer.writerow([repr(v) if isinstance(v, float) else v for v in subject_row(worker, r)])


def write_action_traces(path: Path, traces: Sequence[tuple[int, str, np.ndarray, np.ndarray]]) -> None:
    """kwear_actions.csv: :data:`ACTION_TRACE_COLUMNS` for each (subject, action, t (n,) [s], V (n, 5))."""
    with atomic_open(path, "w") as f:
        f.write(",".join(ACTION_TRACE_COLUMNS) + "\n")
        for subject, action, t, v in traces:
            text = g9_csv(np.column_stack([t, v])).decode()
            f.write("".join(f"{subject},{action}," + line + "\n" for line in text.splitlines()))

"""A run's records as pandas DataFrames (the ``analysis`` extra: ``pip install 'ergosim[analysis]'``).

:func:`run_frames` gives the three tables of a run folder from the records in memory, the columns named as
the CSV files name them: ``allocations`` (one row per attempt, :class:`~ergosim.twin.records.Allocation`'s
fields), ``ticks`` (subject, mode, then the tick log's columns at the ergonomics rate; angles [deg], t [s])
and ``subjects`` (one row per subject and mode, :data:`~ergosim.experiment.csv_files.SUBJECT_COLUMNS`).
pandas is imported here only, on first use.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any, NamedTuple

from ergosim.errors import ConfigError
from ergosim.experiment.csv_files import SUBJECT_COLUMNS, subject_row
from ergosim.twin.records import Allocation

__all__ = ["Frames", "run_frames", "pandas"]

EXTRA = "analysis"


class Frames(NamedTuple):
    """The run's tables as pandas DataFrames."""

    allocations: Any
    ticks: Any
    subjects: Any


def pandas():
    """The pandas module, or a one-line :class:`~ergosim.errors.ConfigError` naming the extra to install."""
    try:
        import pandas as pd  # noqa: PLC0415 - an optional dependency, imported where it is used
    except ImportError:
        raise ConfigError(f"pandas is not installed: pip install 'ergosim[{EXTRA}]' (pandas and duckdb)",
                          where="frames") from None
    return pd


def run_frames(subjects: Sequence) -> Frames:
    """The :class:`Frames` of ``subjects`` (:class:`~ergosim.experiment.runner.SubjectResult` s in subject
    order): every mode of every subject, in the order the runs were made."""
    pd = pandas()
    runs = [(s.name, run) for s in subjects for run in s.runs.values()]
    fields = [f.name for f in dataclasses.fields(Allocation)]
    allocations = pd.DataFrame([dataclasses.astuple(a) for _, run in runs for a in run.allocations],
                               columns=fields)
    columns = list(dict.fromkeys(c for _, run in runs for c in run.ticks.columns))
    parts = []
    for _, run in runs:
        part = pd.DataFrame(run.ticks.rows, columns=list(run.ticks.columns))
        part.insert(0, "mode", run.mode)
        part.insert(0, "subject", run.subject)
        parts.append(part.reindex(columns=["subject", "mode", *columns]))
    ticks = (pd.concat(parts, ignore_index=True) if parts
             else pd.DataFrame(columns=["subject", "mode", *columns]))
    for name in ("repetition", "acting", "dropout"):
        if name in ticks and len(ticks):
            ticks[name] = ticks[name].astype(int)
    table = pd.DataFrame([subject_row(worker, run) for worker, run in runs], columns=list(SUBJECT_COLUMNS))
    return Frames(allocations, ticks, table)

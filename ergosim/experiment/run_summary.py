"""The files of a run computed from its subject records: summary.json, allocations.csv, failures.csv and
subject_records.json itself.

``ergosim run`` writes them after every finished subject; ``ergosim merge`` writes them from the records
of several shards. Both go through :func:`summary_of` and :func:`write_record_files`, so the merged summary
of shards that cover every subject is the unsharded summary byte for byte.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ergosim.experiment.calibration_summary import calibration_summary
from ergosim.experiment.report import summarise, write_allocations, write_failures
from ergosim.experiment.subject_records import RECORDS_FILE, SubjectRecord, write_records

__all__ = ["summary_of", "write_record_files"]


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
    abandoned = sum(m["repetitions_abandoned"] for m in summary["modes"].values())
    summary["status"] = "abandoned" if status == "complete" and abandoned else status
    summary["complete"] = complete and not abandoned
    summary["subjects_finished"] = len(records)
    summary["subjects_planned"] = subject_range[1] - subject_range[0]
    summary["repetitions_abandoned"] = abandoned
    if tuple(subject_range) != (0, config["subjects"]):
        summary["subject_range"] = list(subject_range)
    return summary


def write_record_files(out: Path, scenario: str, seed: int, config: Mapping[str, Any],
                       records: Sequence[SubjectRecord], *, subject_range: tuple[int, int]) -> None:
    """Write allocations.csv, failures.csv and subject_records.json (each atomically) into ``out``."""
    records = sorted(records, key=lambda r: r.subject)
    runs = [r.runs[m] for r in records for m in config["modes"] if m in r.runs]
    write_allocations(out / "allocations.csv", [a for run in runs for a in run.allocations])
    write_failures(out / "failures.csv", [f for run in runs for f in run.failures])
    write_records(out / RECORDS_FILE, scenario=scenario, seed=seed, config=config,
                  subject_range=subject_range, records=records)

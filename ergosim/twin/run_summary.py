"""The files of a run computed from its subject records: summary.json, allocations.csv, failures.csv and
subject_records.json itself.

``ergosim run`` writes them after every finished subject; ``ergosim merge`` writes them from the records
of several shards. Both go through :func:`write_summary_files`, so the merged summary of shards that
cover every subject is the unsharded summary byte for byte.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ergosim.twin.report import summarise, write_allocations, write_failures, write_summary
from ergosim.twin.subject_records import RECORDS_FILE, SubjectRecord, write_records

__all__ = ["write_summary_files", "summary_of"]


def summary_of(scenario: str, seed: int, config: Mapping[str, Any], records: Sequence[SubjectRecord], *,
               subject_range: tuple[int, int], complete: bool, status: str = "running") -> dict:
    """The ``summary.json`` document of ``records`` (any order). ``subject_range`` ``[first, end)``: the
    subjects the run was asked for; a shard (not ``[0, subjects)``) says so in ``subject_range``."""
    records = sorted(records, key=lambda r: r.subject)
    modes = {m: [r.runs[m] for r in records if m in r.runs] for m in config["modes"]}
    extra = {
        "subjects": [r.name for r in records],
        "calibration": {
            "eta_by_subject": [dict(r.eta) for r in records],
            "max_error_by_subject": [dict(r.calibration_errors) for r in records],
            "rula_g_by_subject": [dict(r.rula_g) for r in records],
            "alpha_by_subject": [dict(r.alphas) for r in records],
        },
        "config": dict(config),
    }
    actions = sorted(records[0].alphas) if records else []
    summary = summarise(scenario, seed, modes, actions=actions, complete=complete, extra=extra)
    abandoned = sum(m["repetitions_abandoned"] for m in summary["modes"].values())
    summary["status"] = "abandoned" if status == "complete" and abandoned else status
    summary["complete"] = complete and not abandoned
    summary["subjects_finished"] = len(records)
    summary["subjects_planned"] = subject_range[1] - subject_range[0]
    summary["repetitions_abandoned"] = abandoned
    if tuple(subject_range) != (0, config["subjects"]):
        summary["subject_range"] = list(subject_range)
    return summary


def write_summary_files(out: Path, scenario: str, seed: int, config: Mapping[str, Any],
                        records: Sequence[SubjectRecord], *, subject_range: tuple[int, int], complete: bool,
                        status: str = "running") -> dict:
    """Write summary.json, allocations.csv, failures.csv and subject_records.json (each atomically) into
    ``out``; return the summary."""
    records = sorted(records, key=lambda r: r.subject)
    summary = summary_of(scenario, seed, config, records, subject_range=subject_range, complete=complete,
                         status=status)
    runs = [r.runs[m] for r in records for m in config["modes"] if m in r.runs]
    write_allocations(out / "allocations.csv", [a for run in runs for a in run.allocations])
    write_failures(out / "failures.csv", [f for run in runs for f in run.failures])
    write_records(out / RECORDS_FILE, scenario=scenario, seed=seed, config=config,
                  subject_range=subject_range, records=records)
    write_summary(out / "summary.json", summary)
    return summary

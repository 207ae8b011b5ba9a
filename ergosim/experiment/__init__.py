"""The experiment around the simulation: scenarios, runs, their folders and outputs, shards, reports.

The twin (:mod:`ergosim.twin`) simulates one subject in one mode; this package decides what is simulated
and what becomes of it. A scenario file names a task, a workcell and a protocol
(:mod:`~ergosim.experiment.scenario`, checked by :mod:`~ergosim.experiment.scenario_check`); the runner
builds a subject's rig and runs its modes (:mod:`~ergosim.experiment.runner`); a scenario run simulates
every subject and writes its folder (:mod:`~ergosim.experiment.scenario_run`,
:mod:`~ergosim.experiment.run_folder`); shards merge (:mod:`~ergosim.experiment.run_merge`); summaries,
CSV files, plots, rerun recordings and videos are made from the records.

Names are imported on first use, so ``import ergosim.experiment`` stays cheap.
"""

from __future__ import annotations

from ergosim.exports import lazy_exports

_EXPORTS = {
    "Scenario": "scenario", "load_scenario": "scenario", "register_scenario": "scenario",
    "scenario_names": "scenario", "scenario_info": "scenario", "scenario_path": "scenario",
    "check_scenario": "scenario_check", "precheck": "scenario_check",
    "ScenarioConfig": "protocol",
    "SubjectResult": "subject", "scenario_subject": "subject", "subject_cell": "subject",
    "subject_session": "subject", "run_subject": "runner",
    "run_scenario": "scenario_run", "ScenarioResult": "scenario_run", "EXIT_ABANDONED": "scenario_run",
    "RunFolder": "run_folder", "merge_runs": "run_merge", "MergeResult": "run_merge",
    "summary_text": "summary_text", "write_plots": "plots", "record_run": "recording",
    "film_subject": "film",
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)

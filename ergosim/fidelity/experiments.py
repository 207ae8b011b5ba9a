"""Run the paper's two experiments in the twin for the fidelity report, through the ordinary scenario runs.

Each run is a normal ``ergosim run`` (:func:`~ergosim.experiment.scenario_run.run_scenario`) into its own
folder under the report's output folder, so every figure of the report can be traced to a summary.json and its
CSVs. A :class:`Plan` says what is run: the full form of issue 13 (§7.1 over seeds 0-4, §7.2 with 12
subjects x 10 repetitions over seeds 0-2, and the robot-only assembly), or the ``quick`` form CI runs.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Callable, Mapping
from pathlib import Path

from ergosim.atomic import write_json
from ergosim.experiment.robot_timing import robot_only_runs, timing_summary
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.scenario_run import run_scenario

__all__ = ["Plan", "FULL", "QUICK", "Runs", "run_experiments"]


@dataclasses.dataclass(frozen=True)
class Plan:
    """What the report runs. ``kv_seeds``: §7.1 seeds; ``ms_seeds``, ``ms_subjects``, ``ms_reps``: §7.2;
    ``robot_only_subjects``: subjects of the r-only repetition that times the robot's whole assembly."""

    name: str
    kv_seeds: tuple[int, ...]
    ms_seeds: tuple[int, ...]
    ms_subjects: int
    ms_reps: int
    robot_only_subjects: int


FULL = Plan("full", kv_seeds=(0, 1, 2, 3, 4), ms_seeds=(0, 1, 2), ms_subjects=12, ms_reps=10,
            robot_only_subjects=12)
QUICK = Plan("quick", kv_seeds=(0, 1), ms_seeds=(0,), ms_subjects=6, ms_reps=10, robot_only_subjects=2)


@dataclasses.dataclass(frozen=True)
class Runs:
    """The summaries (summary.json documents) of the report's runs, the robot-only timing
    (:func:`~ergosim.experiment.robot_timing.timing_summary`) and the files they are in."""

    kwear_validation: dict[int, dict]
    multi_subject: dict[int, dict]
    robot_only: dict
    folders: dict[str, str]


def _run(scenario: str, overrides: dict[str, str], seed: int, out: Path, jobs: int | None) -> dict:
    sc = load_scenario(scenario, overrides)
    result = run_scenario(sc, seed=seed, out=out, jobs=jobs, progress=False)
    return json.loads((result.out / "summary.json").read_text()) if result.summary else result.summary


def run_experiments(plan: Plan, out: Path, *, seeds: int | None = None, jobs: int | None = None,
                    log: Callable[[str], None] = lambda _msg: None,
                    overrides: Mapping[str, Mapping[str, str]] | None = None) -> Runs:
    """Run ``plan`` (``seeds`` overrides how many seeds of each experiment, from 0) into ``out/runs``.
    ``overrides``: extra ``--set`` overrides per scenario name ("kwear-validation", "multi-subject")."""
    extra = {k: dict(v) for k, v in (overrides or {}).items()}
    kv_over, ms_over = extra.get("kwear-validation", {}), extra.get("multi-subject", {})
    kv_seeds = tuple(range(seeds)) if seeds else plan.kv_seeds
    ms_seeds = tuple(range(min(seeds, 3))) if seeds else plan.ms_seeds
    runs = Path(out) / "runs"
    folders: dict[str, str] = {}
    kv: dict[int, dict] = {}
    for seed in kv_seeds:
        folder = runs / f"kwear-validation-seed{seed}"
        log(f"§7.1 kwear-validation, seed {seed}")
        kv[seed] = _run("kwear-validation", kv_over, seed, folder, jobs)
        folders[f"kwear-validation seed {seed}"] = str(folder)
    ms: dict[int, dict] = {}
    for seed in ms_seeds:
        folder = runs / f"multi-subject-seed{seed}"
        log(f"§7.2 multi-subject, seed {seed}: {plan.ms_subjects} subjects x {plan.ms_reps} repetitions")
        size = {"subjects": str(plan.ms_subjects), "repetitions": str(plan.ms_reps)}
        ms[seed] = _run("multi-subject", {**ms_over, **size}, seed, folder, jobs)
        folders[f"multi-subject seed {seed}"] = str(folder)
    log(f"§7.2 robot-only assembly: {plan.robot_only_subjects} subjects x 1 repetition, r-only")
    robot = timing_summary(robot_only_runs(load_scenario("multi-subject", ms_over), plan.robot_only_subjects))
    write_json(runs / "robot-only.json", robot)
    folders["robot-only"] = str(runs / "robot-only.json")
    return Runs(kv, ms, robot, folders)

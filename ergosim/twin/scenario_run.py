"""Run a whole scenario: subjects in parallel processes, results written atomically as they arrive.

Every subject is an independent job seeded by ``(seed, subject)``, so ``--jobs`` changes the wall time,
never the results. After each finished subject ``summary.json`` and ``allocations.csv`` are rewritten
(atomically); ``ticks.csv`` and the plots are written at the end. If the run is interrupted, everything
finished so far is written with ``"complete": false``.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
import time
from pathlib import Path

from ergosim.twin.plots import write_plots
from ergosim.twin.progress import Progress
from ergosim.twin.recording import record_run
from ergosim.twin.report import summarise, write_allocations, write_summary, write_ticks
from ergosim.twin.runner import SubjectResult, run_subject, subject_cell
from ergosim.twin.scenario import ScenarioConfig
from ergosim.twin.scenariofile import Scenario
from ergosim.worker.subjects import make_subjects

__all__ = ["run_scenario", "ScenarioResult"]


class ScenarioResult:
    """Subject results in subject order, the summary dict, and where the files are."""

    def __init__(self, results: list[SubjectResult], summary: dict, out: Path, wall: float) -> None:
        self.results = results
        self.summary = summary
        self.out = out
        self.wall = wall


def _job(args) -> SubjectResult:
    scenario, index, seed, modes, record_mode = args
    return run_subject(scenario, index, seed, modes, record_mode=record_mode)


def _write(out: Path, name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult],
           complete: bool, final: bool) -> dict:
    results = sorted(results, key=lambda r: r.subject)
    modes = {m: [r.runs[m] for r in results if m in r.runs] for m in cfg.modes}
    extra = {
        "subjects": [r.name for r in results],
        "calibration": {
            "eta_by_subject": [r.eta for r in results],
            "max_error_by_subject": [r.calibration_errors for r in results],
            "rula_g_by_subject": [r.rula_g for r in results],
            "alpha_by_subject": [r.alphas for r in results],
        },
        "config": {k: v for k, v in vars(cfg).items()},
    }
    summary = summarise(name, seed, modes, actions=list(_actions(results)), complete=complete, extra=extra)
    allocs = [a for r in results for m in cfg.modes if m in r.runs for a in r.runs[m].allocations]
    write_allocations(out / "allocations.csv", allocs)
    if final:
        write_ticks(out / "ticks.csv", [run for r in results for run in r.runs.values()])
        write_plots(out, name, results, cfg)
    write_summary(out / "summary.json", summary)
    return summary


def _actions(results: list[SubjectResult]) -> list[str]:
    for r in results:
        return sorted(r.alphas)
    return []


def run_scenario(scenario: Scenario, *, seed: int, out: Path, jobs: int | None = None, progress: bool = True,
                 recorder=None) -> ScenarioResult:
    """Run ``scenario`` for its subjects and write summary.json, allocations.csv, ticks.csv, PNGs.

    ``recorder`` (an enabled :class:`~ergosim.viz.TwinRecorder`): the first subject's run in the first mode
    is logged to it (3-D workcell, joint angles, RULA, KWear, decisions) once the run is over.
    """
    name, cfg = scenario.name, scenario.protocol
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jobs = max(1, min(jobs or os.cpu_count() or 1, cfg.subjects))
    record_mode = cfg.modes[0] if recorder is not None and recorder.enabled else None
    args = [(scenario, i, seed, tuple(cfg.modes), record_mode if i == 0 else None)
            for i in range(cfg.subjects)]
    bar = Progress(cfg.subjects, f"{name}: subjects", enabled=progress)
    results: list[SubjectResult] = []
    start = time.monotonic()
    complete = False
    try:
        if jobs == 1:
            for a in args:
                results.append(_job(a))
                _write(out, name, seed, cfg, results, complete=False, final=False)
                bar.advance()
        else:
            ctx = multiprocessing.get_context("spawn")
            with cf.ProcessPoolExecutor(max_workers=jobs, mp_context=ctx) as pool:
                futures = [pool.submit(_job, a) for a in args]
                try:
                    for fut in cf.as_completed(futures):
                        results.append(fut.result())
                        _write(out, name, seed, cfg, results, complete=False, final=False)
                        bar.advance()
                except BaseException:
                    for f in futures:
                        f.cancel()
                    raise
        complete = True
    finally:
        bar.close()
        summary = _write(out, name, seed, cfg, results, complete=complete, final=True) if results else {}
    results.sort(key=lambda r: r.subject)
    if record_mode is not None and results and results[0].subject == 0:
        first = results[0]
        cell = subject_cell(scenario, make_subjects(1, seed)[0])
        record_run(recorder, cell.model, first.runs[record_mode], cfg.v_th, cell.parts)
    return ScenarioResult(results, summary, out, time.monotonic() - start)

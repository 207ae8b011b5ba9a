"""Run a whole scenario: subjects in parallel processes, results written atomically as they arrive.

Every subject is an independent job seeded by ``(seed, subject)``, so ``--jobs`` changes the wall time,
never the results. The run owns its folder (:mod:`ergosim.experiment.run_folder`): ``run.json`` is written
before the first tick. The files are the outputs of :mod:`ergosim.experiment.outputs`: after each finished
subject those rewritten each time (``summary.json``, ``allocations.csv``, ``failures.csv``, ...), at the
end all of them (``ticks.csv``, the KWear state files, the plots, ...), each atomically. If the run is
interrupted (Ctrl-C or SIGTERM) or fails, everything finished so far is written with ``"complete":
false``; a run in which a repetition was abandoned is ``"complete": false`` too.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import logging
import multiprocessing
import os
import time
from collections.abc import Callable
from pathlib import Path

from ergosim.experiment.interrupt import (
    interrupt_on_signals,
    quiet_worker,
    signals_ignored,
    stop_pool,
    stop_reason,
)
from ergosim.experiment.outputs import Products, write_outputs
from ergosim.experiment.recording import record_run
from ergosim.experiment.run_folder import RunFolder
from ergosim.experiment.runner import SubjectResult, run_subject, scenario_subject, subject_cell
from ergosim.experiment.scenario import Scenario
from ergosim.experiment.subject_records import SubjectRecord
from ergosim.experiment.summary import summary_of
from ergosim.experiment.team_metrics import team_document, team_in_summary
from ergosim.logs import configured_level
from ergosim.plugins import extension_modules, import_extensions
from ergosim.progress import Progress
from ergosim.twin.protocol import ScenarioConfig

__all__ = ["run_scenario", "ScenarioResult", "EXIT_ABANDONED"]

log = logging.getLogger(__name__)

EXIT_ABANDONED = 3
"""Exit status of ``ergosim run`` when every subject finished but a repetition was abandoned."""


class ScenarioResult:
    """Subject results in subject order, the summary dict, and where the files are.

    ``status``: ``complete`` or ``abandoned`` (see :mod:`ergosim.experiment.run_folder`)."""

    def __init__(self, results: list[SubjectResult], summary: dict, out: Path, wall: float,
                 status: str = "complete", video=None) -> None:
        self.results = results
        self.summary = summary
        self.out = out
        self.wall = wall
        self.status = status
        self.video = video
        """:class:`~ergosim.video.VideoStats` of the video made, or None."""


def _job(args) -> SubjectResult:
    scenario, index, seed, modes, record_mode, extensions = args
    import_extensions(extensions)  # a worker process registers the user's modes, indices, kinds too
    return run_subject(scenario, index, seed, modes, record_mode=record_mode)


def _finished(results: list[SubjectResult], planned: int) -> None:
    r = results[-1]
    done = {m: f"{run.repetitions_completed}/{len(run.outcomes)}" for m, run in r.runs.items()}
    log.debug("subject %d (%s) finished, %d of %d: repetitions completed %s", r.subject, r.name,
              len(results), planned, done)


def _write(out: Path, name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult],
           complete: bool, final: bool, status: str = "running", plot_subjects=None,
           subjects: range | None = None) -> dict:
    """Write the run's outputs (:data:`~ergosim.experiment.outputs.OUTPUTS`): after a subject those rewritten
    each time, with ``final`` all of them. The summary is computed from the subject records, as ``ergosim
    merge`` computes it for shards."""
    results = sorted(results, key=lambda r: r.subject)
    records = tuple(SubjectRecord.of(r) for r in results)
    span = (subjects.start, subjects.stop) if subjects is not None else (0, cfg.population.subjects)
    config = cfg.record()
    summary = summary_of(name, seed, config, records, subject_range=span, complete=complete, status=status)
    modes = {m: [r.runs[m] for r in results if m in r.runs] for m in cfg.modes}
    team = None
    if team_in_summary(cfg, modes):  # a team setting is not the paper's: team.json, and in summary.json
        team = summary["team"] = team_document(cfg, modes)
    write_outputs(out, Products(name, seed, config, records, span, summary, team, tuple(results),
                                plot_subjects), final=final)
    return summary


def run_scenario(scenario: Scenario, *, seed: int, out: Path, jobs: int | None = None, progress: bool = True,
                 recorder=None, record_subject: int = 0, record_mode: str | None = None,
                 video=None, plot_subjects: tuple[int, ...] | None = None,
                 subjects: range | None = None) -> ScenarioResult:
    """Run ``scenario`` for its subjects and write summary.json, allocations.csv, failures.csv, ticks.csv,
    the KWear state files and PNGs into ``out``, which the run owns (run.json).

    ``recorder`` (an enabled :class:`~ergosim.viz.TwinRecorder`): subject ``record_subject``'s run in mode
    ``record_mode`` (default: the first mode) is logged to it (3-D workcell, joint angles, RULA, KWear,
    decisions, failures) once the run is over. ``video`` (a :class:`~ergosim.video.VideoRequest`): that
    subject's run in that mode is rendered to an MP4 after every result is written. ``plot_subjects``: the
    subjects the timelines and the per-action figure show (default: every subject). ``subjects``: run only
    these subjects of the population (a shard, ``ergosim run --subject-range``; default all), each seeded
    as in the whole run. SIGINT and SIGTERM stop the run the same way: the finished subjects are written,
    then :class:`~ergosim.experiment.interrupt.Interrupted` propagates.
    """
    name, cfg = scenario.name, scenario.protocol
    out = Path(out)
    recording = recorder is not None and recorder.enabled
    record_mode = (record_mode or cfg.modes[0]) if recording else None
    folder = RunFolder(out, scenario=name, seed=seed)
    folder.claim(cfg.record())
    subjects = subjects if subjects is not None else range(cfg.population.subjects)
    jobs = max(1, min(jobs or os.cpu_count() or 1, len(subjects)))
    kept = {(record_subject, record_mode)} if record_mode is not None else set()
    if video is not None:
        video = dataclasses.replace(video, mode=video.mode or cfg.modes[0])
        kept.add((video.subject, video.mode))
    args = [(scenario, i, seed, tuple(cfg.modes), tuple(sorted(m for s, m in kept if s == i)),
             extension_modules()) for i in subjects]
    log.debug("%s (seed %d): subjects %d..%d, modes %s, %d process(es), into %s", name, seed, subjects.start,
              subjects.stop - 1, ", ".join(cfg.modes), jobs, out)
    bar = Progress(len(subjects), f"{name}: subjects", enabled=progress)
    results: list[SubjectResult] = []
    start = time.monotonic()
    status, reason = "failed", ""

    def finished(result: SubjectResult) -> None:
        results.append(result)
        _finished(results, len(subjects))
        _write(out, name, seed, cfg, results, complete=False, final=False, subjects=subjects)
        bar.advance()

    try:
        with interrupt_on_signals():
            _simulate(args, jobs, finished)
        status = "complete"
    except BaseException as err:
        status, reason = stop_reason(err)
        raise
    finally:
        bar.close()
        with interrupt_on_signals():  # a second Ctrl-C while writing still leaves whole files
            if results:
                summary = _write(out, name, seed, cfg, results, complete=status == "complete", final=True,
                                 status=status, plot_subjects=plot_subjects, subjects=subjects)
                if summary["status"] == "abandoned":
                    status = "abandoned"
                    reason = f"{summary['repetitions_abandoned']} repetition(s) abandoned"
                folder.finish(status, reason)
            elif status == "interrupted":
                summary = _write(out, name, seed, cfg, results, complete=False, final=True, status=status,
                                 subjects=subjects)
                folder.finish(status, reason)
            else:
                summary = {}
                folder.discard()  # an early error leaves no empty output folder behind
    log.debug("%s: %s, %d subject(s) written to %s", name, status, len(results), out)
    results.sort(key=lambda r: r.subject)
    chosen = [r for r in results if r.subject == record_subject]
    if record_mode is not None and chosen:
        _record(recorder, scenario, seed, chosen[0], record_mode)
    filmed = None
    chosen = [r for r in results if video is not None and r.subject == video.subject]
    if chosen:
        from ergosim.experiment.film import film_subject  # noqa: PLC0415 - only videos need the renderer

        with interrupt_on_signals():  # SIGTERM too leaves no half-written video
            filmed = film_subject(scenario, seed, chosen[0], video, progress=progress)
    return ScenarioResult(results, summary, out, time.monotonic() - start, status, filmed)


def _simulate(args: list, jobs: int, finished: Callable[[SubjectResult], None]) -> None:
    """Run every subject's ``_job``: in this process (``jobs`` 1) or on a pool of ``jobs`` spawned workers
    (which log as this process does), calling ``finished`` with each result as it comes. An error or a
    signal stops the pool's workers before it propagates."""
    if jobs == 1:
        for a in args:
            finished(_job(a))
        return
    ctx = multiprocessing.get_context("spawn")
    with signals_ignored():
        pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=quiet_worker,
                                      initargs=(configured_level(),))
        futures = [pool.submit(_job, a) for a in args]
    try:
        for fut in cf.as_completed(futures):
            finished(fut.result())
    except BaseException:
        stop_pool(pool)
        raise
    pool.shutdown()


def _record(recorder, scenario: Scenario, seed: int, result: SubjectResult, mode: str) -> None:
    """Log ``result``'s run in ``mode`` to the rerun ``recorder``, in the cell the subject ran in."""
    cell = subject_cell(scenario, scenario_subject(scenario, result.subject, seed))
    view = cell.config.view()
    record_run(recorder, cell.model, result.runs[mode], scenario.protocol.cost.v_th, cell.parts,
               view=(view.azimuth, view.elevation))

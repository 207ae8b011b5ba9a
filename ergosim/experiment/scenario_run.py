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
import contextlib
import dataclasses
import logging
import multiprocessing
import os
import signal
import time
from collections.abc import Callable, Mapping
from pathlib import Path

from ergosim.errors import ConfigError
from ergosim.experiment.interrupt import (
    interrupt_on_signals,
    quiet_worker,
    signals_ignored,
    stop_pool,
    stop_reason,
)
from ergosim.experiment.outputs import Products, output, write_outputs
from ergosim.experiment.protocol import ScenarioConfig
from ergosim.experiment.report import write_report
from ergosim.experiment.report.still import run_still
from ergosim.experiment.run_folder import RunFolder
from ergosim.experiment.runner import run_subject
from ergosim.experiment.scenario import Scenario
from ergosim.experiment.spawn_guard import check_main_guard
from ergosim.experiment.subject import SubjectResult, scenario_subject, subject_cell
from ergosim.experiment.subject_records import SubjectRecord
from ergosim.experiment.summary import summary_of
from ergosim.experiment.team_metrics import team_document, team_in_summary
from ergosim.logs import configured_level
from ergosim.plugins import extension_modules, import_extensions
from ergosim.progress import Progress

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


def run_config(cfg: ScenarioConfig, overrides: Mapping[str, str] | None) -> dict:
    """The run's ``config`` as run.json, summary.json and the subject records keep it: the protocol and,
    when any were given, every override as given (``overrides``: ``--set`` key -> value)."""
    return {**cfg.record(), **({"overrides": dict(overrides)} if overrides else {})}


def _products(name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult], complete: bool,
              status: str, plot_subjects=None, subjects: range | None = None,
              overrides: Mapping[str, str] | None = None, plots: bool = True) -> Products:
    """What the outputs are written from. The summary is computed from the subject records, as ``ergosim
    merge`` computes it for shards."""
    results = sorted(results, key=lambda r: r.subject)
    records = tuple(SubjectRecord.of(r) for r in results)
    span = (subjects.start, subjects.stop) if subjects is not None else (0, cfg.population.subjects)
    config = run_config(cfg, overrides)
    summary = summary_of(name, seed, config, records, subject_range=span, complete=complete, status=status)
    modes = {m: [r.runs[m] for r in results if m in r.runs] for m in cfg.modes}
    team = None
    if team_in_summary(cfg, modes):  # a team setting is not the paper's: team.json, and in summary.json
        team = summary["team"] = team_document(cfg, modes)
    return Products(name, seed, config, records, span, summary, team, tuple(results), plot_subjects, plots)


def _with_status(p: Products, status: str) -> Products:
    """``p`` with its summary computed again for the run's final ``status``."""
    summary = summary_of(p.scenario, p.seed, p.config, p.records, subject_range=p.subject_range,
                         complete=status == "complete", status=status)
    if p.team is not None:
        summary["team"] = p.team
    return dataclasses.replace(p, summary=summary)


def _write(out: Path, name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult],
           complete: bool, final: bool, status: str = "running", plot_subjects=None,
           subjects: range | None = None, overrides: Mapping[str, str] | None = None) -> dict:
    """Write the run's outputs (:data:`~ergosim.experiment.outputs.OUTPUTS`): after a subject those rewritten
    each time, with ``final`` all of them."""
    products = _products(name, seed, cfg, results, complete, status, plot_subjects, subjects, overrides)
    write_outputs(out, products, final=final)
    return products.summary


def _finish(folder: RunFolder, stop, out: Path, products: Products | None, status: str,
            reason: str) -> tuple[dict, str]:
    """The final write, with the signals held (``stop``): every output but summary.json, then summary.json
    and run.json with the run's status. A signal held meanwhile makes a run that had ended
    ``interrupted``; if it came while those two were written, both are written again. Returns the summary
    and the status. Without ``products`` (an early error) the folder is given back empty."""
    if products is None:
        folder.discard()  # an early error leaves no empty output folder behind
        return {}, status
    try:
        write_outputs(out, products, final=True, skip=("summary", "report"))
    except OSError as err:  # a full disk, a folder made read-only meanwhile: one line, and run.json says so
        why = err.strerror or str(err)
        with contextlib.suppress(OSError):
            output("summary").write(out, _with_status(products, "failed"))
        with contextlib.suppress(OSError):
            folder.finish("failed", f"the results could not be written: {why}")
        folder.release()
        raise ConfigError(f"cannot write the results into {out}: {why}", where="--out") from None
    while True:
        if stop.held is not None and status in ("complete", "abandoned"):
            status, reason = "interrupted", f"stopped by {signal.Signals(stop.held).name} while the " \
                                            "results were written"
        final = _with_status(products, status)
        output("summary").write(out, final)
        output("report").write(out, final)
        if final.summary["status"] == "abandoned":
            status = "abandoned"
            reason = f"{final.summary['repetitions_abandoned']} repetition(s) abandoned"
        folder.finish(status, reason, release=False)
        if stop.held is None or status not in ("complete", "abandoned"):
            break
    folder.release()
    return final.summary, status


def run_scenario(scenario: Scenario, *, seed: int, out: Path, jobs: int | None = None, progress: bool = True,
                 recorder=None, record_subject: int = 0, record_mode: str | None = None,
                 video=None, plot_subjects: tuple[int, ...] | None = None,
                 subjects: range | None = None, plots: bool = True) -> ScenarioResult:
    """Run ``scenario`` for its subjects and write summary.json, allocations.csv, failures.csv, ticks.csv,
    the KWear state files and PNGs into ``out``, which the run owns (run.json).

    ``recorder`` (an enabled :class:`~ergosim.viz.TwinRecorder`): subject ``record_subject``'s run in mode
    ``record_mode`` (default: the first mode) is logged to it (3-D workcell, joint angles, RULA, KWear,
    decisions, failures) once the run is over. ``video`` (a :class:`~ergosim.video.VideoRequest`): that
    subject's run in that mode is rendered to an MP4 after every result is written. ``plot_subjects``: the
    subjects the timelines and the per-action figure show (default: every subject); ``plots``: False draws
    no figures (``ergosim plot`` draws them later from the folder's files). ``subjects``: run only
    these subjects of the population (a shard, ``ergosim run --subject-range``; default all), each seeded
    as in the whole run. SIGINT and SIGTERM stop the run the same way: the finished subjects are written,
    then :class:`~ergosim.experiment.interrupt.Interrupted` propagates. A signal that comes while the results
    are written is held until they are whole; the run is then ``interrupted`` too, and says so.
    """
    name, cfg = scenario.name, scenario.protocol
    out = Path(out)
    recording = recorder is not None and recorder.enabled
    record_mode = (record_mode or cfg.modes[0]) if recording else None
    folder = RunFolder(out, scenario=name, seed=seed)
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
    results: list[SubjectResult] = []
    start = time.monotonic()
    status, reason = "failed", ""
    bar = None

    def finished(result: SubjectResult) -> None:
        results.append(result)
        _finished(results, len(subjects))
        _write(out, name, seed, cfg, results, complete=False, final=False, subjects=subjects,
               overrides=scenario.overrides)
        bar.advance()

    # signals are held while the folder is claimed and while the results are written: an exit by a signal
    # always leaves outputs that say "interrupted" (ergosim.experiment.interrupt)
    with interrupt_on_signals(holding=True) as stop:
        folder.claim(run_config(cfg, scenario.overrides))
        try:
            stop.release()  # a signal during the claim stops the run here, with the folder ours
            bar = Progress(len(subjects), f"{name}: subjects", enabled=progress)
            _simulate(args, jobs, finished)
            stop.holding = True  # from here a signal waits until the results are written
            status = "complete"
        except BaseException as err:
            stop.holding = True
            status, reason = stop_reason(err)
            raise
        finally:
            if bar is not None:
                bar.close()
            products = _products(name, seed, cfg, results, False, status, plot_subjects, subjects,
                                 scenario.overrides, plots) if results or status == "interrupted" else None
            if products is not None and plots:
                products = dataclasses.replace(products, still=run_still(scenario))
            summary, status = _finish(folder, stop, out, products, status, reason)
        if status == "interrupted":
            stop.release()  # a signal held while a whole run was written (its outputs say interrupted)
    log.debug("%s: %s, %d subject(s) written to %s", name, status, len(results), out)
    results.sort(key=lambda r: r.subject)
    chosen = [r for r in results if r.subject == record_subject]
    if record_mode is not None and chosen:
        _record(recorder, scenario, seed, chosen[0], record_mode)
    filmed = _film(scenario, seed, results, video, progress)
    if filmed is not None:
        write_report(out, video=video.path)  # the page again, with the video
    return ScenarioResult(results, summary, out, time.monotonic() - start, status, filmed)


def _film(scenario: Scenario, seed: int, results: list[SubjectResult], video, progress: bool):
    """The video ``video`` asks for, of its subject's result (None: no video, or that subject has none)."""
    chosen = [r for r in results if video is not None and r.subject == video.subject]
    if not chosen:
        return None
    from ergosim.experiment.film import film_subject  # noqa: PLC0415 - only videos need the renderer

    with interrupt_on_signals():  # SIGTERM too leaves no half-written video
        return film_subject(scenario, seed, chosen[0], video, progress=progress)


def _simulate(args: list, jobs: int, finished: Callable[[SubjectResult], None]) -> None:
    """Run every subject's ``_job``: in this process (``jobs`` 1) or on a pool of ``jobs`` spawned workers
    (which log as this process does), calling ``finished`` with each result as it comes. An error or a
    signal stops the pool's workers before it propagates."""
    if jobs == 1:
        for a in args:
            finished(_job(a))
        return
    check_main_guard(where="jobs")
    ctx = multiprocessing.get_context("spawn")
    pool = None
    try:
        with signals_ignored():  # the workers start here and inherit SIG_IGN
            pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=quiet_worker,
                                          initargs=(configured_level(),))
            futures = [pool.submit(_job, a) for a in args]
        for fut in cf.as_completed(futures):
            finished(fut.result())
    except BaseException:
        if pool is not None:
            stop_pool(pool)
        raise
    pool.shutdown()


def _record(recorder, scenario: Scenario, seed: int, result: SubjectResult, mode: str) -> None:
    """Log ``result``'s run in ``mode`` to the rerun ``recorder``, in the cell the subject ran in."""
    from ergosim.experiment.recording import record_run  # noqa: PLC0415 - rerun only for a run recorded

    cell = subject_cell(scenario, scenario_subject(scenario, result.subject, seed))
    view = cell.config.view()
    record_run(recorder, cell.model, result.runs[mode], scenario.protocol.cost.v_th, cell.parts,
               view=(view.azimuth, view.elevation))

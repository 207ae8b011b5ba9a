"""Run a whole scenario: subjects in parallel processes, results written atomically as they arrive.

Every subject is an independent job seeded by ``(seed, subject)``, so ``--jobs`` changes the wall time,
never the results. The run owns its folder (:mod:`ergosim.twin.run_folder`): ``run.json`` is written before
the first tick. After each finished subject ``summary.json``, ``allocations.csv`` and ``failures.csv`` are
rewritten (atomically); ``ticks.csv``, the KWear state files and the plots are written at the end. If the
run is interrupted (Ctrl-C or SIGTERM) or fails, everything finished so far is written with
``"complete": false``; a run in which a repetition was abandoned is ``"complete": false`` too.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import dataclasses
import multiprocessing
import os
import signal
import time
from collections.abc import Mapping
from pathlib import Path

from ergosim.atomic import write_json
from ergosim.errors import ConfigError
from ergosim.plugins import extension_modules, import_extensions
from ergosim.twin.interrupt import (
    interrupt_on_signals,
    quiet_worker,
    signals_ignored,
    stop_pool,
    stop_reason,
)
from ergosim.twin.kwear_state import state_document
from ergosim.twin.plots import write_plots
from ergosim.twin.progress import Progress
from ergosim.twin.recording import record_run
from ergosim.twin.report import write_action_traces, write_subjects, write_summary, write_ticks
from ergosim.twin.run_folder import RunFolder
from ergosim.twin.run_summary import summary_of, write_record_files
from ergosim.twin.runner import SubjectResult, run_subject, scenario_subject, subject_cell
from ergosim.twin.scenario import ScenarioConfig
from ergosim.twin.scenariofile import Scenario
from ergosim.twin.spawn_guard import check_main_guard
from ergosim.twin.subject_records import SubjectRecord
from ergosim.twin.team_metrics import team_document, team_in_summary

__all__ = ["run_scenario", "ScenarioResult", "EXIT_ABANDONED"]

EXIT_ABANDONED = 3
"""Exit status of ``ergosim run`` when every subject finished but a repetition was abandoned."""


class ScenarioResult:
    """Subject results in subject order, the summary dict, and where the files are.

    ``status``: ``complete`` or ``abandoned`` (see :mod:`ergosim.twin.run_folder`)."""

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


def run_config(cfg: ScenarioConfig, overrides: Mapping[str, str] | None) -> dict:
    """The run's ``config`` as run.json, summary.json and the subject records keep it: the protocol and,
    when any were given, every override as given (``overrides``: ``--set`` key -> value)."""
    return {**cfg.record(), **({"overrides": dict(overrides)} if overrides else {})}


def _write(out: Path, name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult],
           complete: bool, final: bool, status: str = "running", plot_subjects=None,
           subjects: range | None = None, overrides: Mapping[str, str] | None = None) -> dict:
    team = _write_results(out, name, seed, cfg, results, final, plot_subjects, subjects, overrides)
    return _write_summary(out, name, seed, cfg, results, complete, status, subjects, overrides, team)


def _write_results(out: Path, name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult],
                   final: bool, plot_subjects=None, subjects: range | None = None,
                   overrides: Mapping[str, str] | None = None) -> dict | None:
    """Every output but summary.json; returns team.json's document (None when the run has no team)."""
    results = sorted(results, key=lambda r: r.subject)
    # computed from the subject records (subject_records.json), as `ergosim merge` does for shards
    write_record_files(out, name, seed, run_config(cfg, overrides), [SubjectRecord.of(r) for r in results],
                       subject_range=_span(cfg, subjects))
    modes = {m: [r.runs[m] for r in results if m in r.runs] for m in cfg.modes}
    team = None
    if team_in_summary(cfg, modes):  # a team setting is not the paper's: team.json, and in summary.json
        team = team_document(cfg, modes)
        write_json(out / "team.json", team)
    if final:
        write_ticks(out / "ticks.csv", [run for r in results for run in r.runs.values()])
        _write_states(out, name, seed, cfg, results)
        write_subjects(out / "subjects.csv", [(r.name, r.runs[m]) for m in cfg.modes for r in results
                                              if m in r.runs])
        write_action_traces(out / "kwear_actions.csv", [(r.subject, a, t, v) for r in results
                                                        for a, (t, v) in sorted(r.traces.items())])
        write_plots(out, subjects=plot_subjects)
    return team


def _write_summary(out: Path, name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult],
                   complete: bool, status: str, subjects: range | None, overrides: Mapping[str, str] | None,
                   team: dict | None) -> dict:
    """summary.json, written last: the file that says whether the others are the whole run."""
    records = [SubjectRecord.of(r) for r in sorted(results, key=lambda r: r.subject)]
    summary = summary_of(name, seed, run_config(cfg, overrides), records, subject_range=_span(cfg, subjects),
                         complete=complete, status=status)
    if team is not None:
        summary["team"] = team
    write_summary(out / "summary.json", summary)
    return summary


def _span(cfg: ScenarioConfig, subjects: range | None) -> tuple[int, int]:
    return (subjects.start, subjects.stop) if subjects is not None else (0, cfg.subjects)


def _finish(folder: RunFolder, stop, out: Path, name: str, seed: int, cfg: ScenarioConfig,
            results: list[SubjectResult], status: str, reason: str, plot_subjects, subjects: range,
            overrides: Mapping[str, str] | None) -> tuple[dict, str]:
    """The final write, with the signals held (``stop``): every file, then summary.json and run.json with
    the run's status. A signal held meanwhile makes a run that had ended ``interrupted``; if it came while
    those two were written, both are written again. Returns the summary and the status."""
    if not results and status != "interrupted":
        folder.discard()  # an early error leaves no empty output folder behind
        return {}, status
    try:
        team = _write_results(out, name, seed, cfg, results, True, plot_subjects, subjects, overrides)
    except OSError as err:  # a full disk, a folder made read-only meanwhile: one line, and run.json says so
        why = err.strerror or str(err)
        with contextlib.suppress(OSError):
            _write_summary(out, name, seed, cfg, results, False, "failed", subjects, overrides, None)
        with contextlib.suppress(OSError):
            folder.finish("failed", f"the results could not be written: {why}")
        folder.release()
        raise ConfigError(f"cannot write the results into {out}: {why}", where="--out") from None
    while True:
        if stop.held is not None and status in ("complete", "abandoned"):
            status, reason = "interrupted", f"stopped by {signal.Signals(stop.held).name} while the " \
                                            "results were written"
        summary = _write_summary(out, name, seed, cfg, results, status == "complete", status, subjects,
                                 overrides, team)
        if summary["status"] == "abandoned":
            status = "abandoned"
            reason = f"{summary['repetitions_abandoned']} repetition(s) abandoned"
        folder.finish(status, reason, release=False)
        if stop.held is None or status not in ("complete", "abandoned"):
            break
    folder.release()
    return summary, status


def _run_subjects(scenario: Scenario, seed: int, out: Path, jobs: int, subjects: range,
                  kept: set[tuple[int, str]], results: list[SubjectResult], bar: Progress) -> None:
    """Run ``subjects`` in ``jobs`` processes; each result is appended to ``results`` and the running
    outputs are rewritten as it arrives."""
    name, cfg = scenario.name, scenario.protocol
    args = [(scenario, i, seed, tuple(cfg.modes), tuple(sorted(m for s, m in kept if s == i)),
             extension_modules()) for i in subjects]

    def arrived(result: SubjectResult) -> None:
        results.append(result)
        _write(out, name, seed, cfg, results, complete=False, final=False, subjects=subjects,
               overrides=scenario.overrides)
        bar.advance()

    if jobs == 1:
        for a in args:
            arrived(_job(a))
        return
    check_main_guard(where="jobs")
    ctx = multiprocessing.get_context("spawn")
    pool = None
    try:
        with signals_ignored():  # the workers start here and inherit SIG_IGN
            pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=quiet_worker)
            futures = [pool.submit(_job, a) for a in args]
        for fut in cf.as_completed(futures):
            arrived(fut.result())
    except BaseException:
        if pool is not None:
            stop_pool(pool)
        raise
    pool.shutdown()


def _write_states(out: Path, name: str, seed: int, cfg: ScenarioConfig, results: list[SubjectResult]) -> None:
    """kwear_state_s<subject>_<mode>.json: the KWear state each run ended with (ergosim.twin.kwear_state)."""
    for r in results:
        params = r.kwear_params
        for mode, run in r.runs.items():
            rows = run.ticks.rows
            doc = state_document(
                scenario=name, task=cfg.task, seed=seed, subject=r.subject, worker=r.name, mode=mode,
                time_s=float(rows[-1, 1]) if len(rows) else 0.0,
                v=run.ticks.kwear[-1] if len(rows) else [0.0] * run.ticks.kwear.shape[1],
                alpha=r.alphas, kwear_params=params, gamma=cfg.gamma, v_th=cfg.v_th,
                robot_cost=cfg.robot_cost)
            write_json(out / f"kwear_state_s{r.subject}_{mode}.json", doc)


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
    then :class:`~ergosim.twin.interrupt.Interrupted` propagates. A signal that comes while the results
    are written is held until they are whole; the run is then ``interrupted`` too, and says so.
    """
    name, cfg = scenario.name, scenario.protocol
    out = Path(out)
    recording = recorder is not None and recorder.enabled
    record_mode = (record_mode or cfg.modes[0]) if recording else None
    folder = RunFolder(out, scenario=name, seed=seed)
    subjects = subjects if subjects is not None else range(cfg.subjects)
    jobs = max(1, min(jobs or os.cpu_count() or 1, len(subjects)))
    kept = {(record_subject, record_mode)} if record_mode is not None else set()
    if video is not None:
        video = dataclasses.replace(video, mode=video.mode or cfg.modes[0])
        kept.add((video.subject, video.mode))
    results: list[SubjectResult] = []
    start = time.monotonic()
    status, reason = "failed", ""
    # signals are held while the folder is claimed and while the results are written: an exit by a signal
    # always leaves outputs that say "interrupted" (ergosim.twin.interrupt)
    with interrupt_on_signals(holding=True) as stop:
        folder.claim(run_config(cfg, scenario.overrides))
        bar = None
        try:
            stop.release()  # a signal during the claim stops the run here, with the folder ours
            bar = Progress(len(subjects), f"{name}: subjects", enabled=progress)
            _run_subjects(scenario, seed, out, jobs, subjects, kept, results, bar)
            stop.holding = True  # from here a signal waits until the results are written
            status = "complete"
        except BaseException as err:
            stop.holding = True
            status, reason = stop_reason(err)
            raise
        finally:
            if bar is not None:
                bar.close()
            summary, status = _finish(folder, stop, out, name, seed, cfg, results, status, reason,
                                      plot_subjects, subjects, scenario.overrides)
        if status == "interrupted":
            stop.release()  # a signal held while a whole run was written (its outputs say interrupted)
    results.sort(key=lambda r: r.subject)
    chosen = [r for r in results if r.subject == record_subject]
    if record_mode is not None and chosen:
        subject = scenario_subject(scenario, record_subject, seed)
        cell = subject_cell(scenario, subject)
        view = cell.config.view()
        record_run(recorder, cell.model, chosen[0].runs[record_mode], cfg.v_th, cell.parts,
                   view=(view.azimuth, view.elevation))
    filmed = None
    chosen = [r for r in results if video is not None and r.subject == video.subject]
    if chosen:
        from ergosim.video.film import film_subject  # noqa: PLC0415 - only videos need the renderer

        with interrupt_on_signals():  # SIGTERM too leaves no half-written video
            filmed = film_subject(scenario, seed, chosen[0], video, progress=progress)
    return ScenarioResult(results, summary, out, time.monotonic() - start, status, filmed)

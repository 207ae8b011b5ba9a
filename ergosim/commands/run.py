"""``ergosim run SCENARIO``: the paper's experiments end to end in the twin (Fig. 1, §7).

Exit status: 0 every repetition completed; 2 bad input (one line on stderr, nothing simulated); 3 every
subject ran but at least one repetition was abandoned (no agent left able to finish the assembly; the
summary, the printed text and ``run.json`` say which and why); 130 / 143 interrupted by SIGINT / SIGTERM
(the finished subjects are written, marked incomplete).
"""

from __future__ import annotations

import argparse
import logging
import os
from pathlib import Path

from ergosim.commands.plot import add_plot_subject_argument, parse_subjects
from ergosim.commands.video_options import add_video_arguments, check_can_render, video_line, video_request
from ergosim.errors import ConfigError, ErgosimError
from ergosim.overrides import parse_assignments

__all__ = ["add_parser", "run", "subject_range"]

log = logging.getLogger(__name__)


def add_parser(sub) -> argparse.ArgumentParser:
    from ergosim.experiment.scenario import scenario_names  # noqa: PLC0415
    from ergosim.twin.modes import mode_names  # noqa: PLC0415 - keep `ergosim --help` fast

    p = sub.add_parser(
        "run", help="run a scenario (a bundled one by name, or a scenario file) headless",
        description="Run a scenario in the twin and write summary.json, allocations.csv, ticks.csv and plots "
                    "to --out. Bundled scenarios are listed by `ergosim scenarios`.",
    )
    p.add_argument("scenario", help=f"a scenario file (.toml) or one of: {', '.join(scenario_names())}")
    p.add_argument("--subjects", type=int, help="number of synthetic subjects (default: the scenario's)")
    p.add_argument("--reps", type=int, help="repetitions per subject and mode")
    p.add_argument("--mode", choices=mode_names(), help="run only this mode (default: the scenario's modes)")
    p.add_argument("--subject-range", metavar="A:B",
                   help="run only subjects A..B-1 of the population (0-based, end exclusive: 0:6 and 6:12 "
                        "split 12 subjects), seeded as in the whole run; `ergosim merge` joins the shards")
    p.add_argument("--seed", type=int, default=0,
                   help="random seed, an integer >= 0 (default 0); same seed, same results")
    p.add_argument("--jobs", type=int, help="parallel processes (default: all cores)")
    p.add_argument("--out", default=None, help="output directory (default results/<scenario>)")
    p.add_argument("--rrd", metavar="FILE", help="save a rerun recording of one subject's run in one mode "
                                                 "(--rrd-subject, --rrd-mode)")
    p.add_argument("--rrd-subject", type=int, metavar="N",
                   help="subject recorded by --rrd/--spawn/--connect, 0-based as in the CSVs (default 0)")
    p.add_argument("--rrd-mode", choices=mode_names(), metavar="MODE",
                   help="mode recorded by --rrd/--spawn/--connect (default: the first mode run)")
    p.add_argument("--spawn", action="store_true", help="open a rerun viewer and stream to it")
    p.add_argument("--connect", nargs="?", const="default", metavar="URL",
                   help="stream to a running rerun viewer (default URL if none given)")
    p.add_argument("--set", dest="assign", action="append", default=[], metavar="KEY=VALUE",
                   help="override any field by its dotted path: the protocol (takt=40), the workcell "
                        "(scene.shelf_height=1.6, scene.parts.L.xy=0.2,0.8), the task "
                        "(task.agents.robot.cost=3), or the task or workcell itself (workcell=FILE); "
                        "docs/workcell_format.md")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar; log warnings only")
    add_plot_subject_argument(p)
    p.add_argument("--no-plots", dest="plots", action="store_false",
                   help="write no figures (PNG): the run is faster; `ergosim plot OUT` draws them later from "
                        "the folder's files")
    add_video_arguments(p, mode_names())
    return p


def _scenario(args):
    from ergosim.experiment.scenario import load_scenario  # noqa: PLC0415

    own = parse_assignments(args.assign)
    if args.seed < 0:
        raise ConfigError(f"must be an integer >= 0, got {args.seed}", where="--seed")
    counts = (("--subjects", "subjects", args.subjects), ("--reps", "repetitions", args.reps),
              ("--mode", "modes", args.mode))
    flags = {}  # the protocol fields given by an option, not by --set
    for flag, field, value in counts:
        if value is not None:
            flags[field] = flag
            if field in own:  # two answers to one question: refuse rather than pick one silently
                raise ConfigError(f"{flag} {value} and --set {field}={own[field]} both set {field}; give one",
                                  where=flag)
            if isinstance(value, int) and value < 1:
                raise ConfigError(f"must be >= 1, got {value}", where=flag)
            own[field] = str(value)
    if args.jobs is not None and args.jobs < 1:
        raise ConfigError(f"must be >= 1, got {args.jobs}", where="--jobs")
    try:
        scenario = load_scenario(args.scenario, own)
    except ConfigError as err:  # a bound on --subjects or --reps names that option, not --set
        flag = next((f for field, f in flags.items() if err.where == "--set" and err.what.startswith(field)),
                    None)
        if flag is None:
            raise
        raise ConfigError(err.what, where=flag) from None
    cfg = scenario.protocol
    recording = args.rrd is not None or args.spawn or args.connect is not None
    if (args.rrd_subject is not None or args.rrd_mode is not None) and not recording:
        raise ConfigError("--rrd-subject/--rrd-mode choose what to record: give --rrd FILE, --spawn or "
                          "--connect as well", where="--rrd-subject" if args.rrd_subject is not None
                          else "--rrd-mode")
    subjects = subject_range(args.subject_range, cfg.population.subjects)
    if args.rrd_subject is not None and args.rrd_subject not in subjects:
        raise ConfigError(f"must be a subject index in {subjects.start}..{subjects.stop - 1}, got "
                          f"{args.rrd_subject}", where="--rrd-subject")
    if args.rrd_mode is not None and args.rrd_mode not in cfg.modes:
        raise ConfigError(f"mode {args.rrd_mode!r} is not run; modes run: {', '.join(cfg.modes)}",
                          where="--rrd-mode")
    return scenario, subjects


def subject_range(text: str | None, n: int) -> range:
    """``--subject-range A:B`` (either end may be left out) as a range of subject indices in 0..n-1."""
    if text is None:
        return range(n)
    first, sep, end = text.partition(":")
    try:
        a = int(first) if first.strip() else 0
        b = int(end) if end.strip() else n
    except ValueError:
        a = b = -1
    if not sep or not 0 <= a < b <= n:
        raise ConfigError(f"expected A:B with 0 <= A < B <= {n} (the number of subjects), got {text!r}",
                          where="--subject-range")
    return range(a, b)


def _in_shard(subjects: range, n: int, **chosen) -> None:
    """``--plot-subject`` and ``--video-subject`` name subjects of the shard ``--subject-range`` runs."""
    if len(subjects) == n:
        return
    for option, value in chosen.items():
        wanted = [value] if isinstance(value, int) else list(value or ())
        outside = [s for s in wanted if s not in subjects]
        if outside:
            raise ConfigError(f"subject {outside[0]} is not in the shard {subjects.start}:{subjects.stop} "
                              "(--subject-range)", where=f"--{option.replace('_', '-')}")


def _precheck(scenario) -> None:
    """Refuse a run certain to fail before any subject starts (reachability of every action); say which
    actions a robot cannot do (taken from it for the run), one line each."""
    from ergosim.experiment.scenario_check import precheck  # noqa: PLC0415

    for line in precheck(scenario):
        print(line)


def run(args) -> int:
    from ergosim.experiment.scenario_run import EXIT_ABANDONED, run_scenario  # noqa: PLC0415
    from ergosim.experiment.summary_text import summary_text  # noqa: PLC0415

    scenario, subjects = _scenario(args)
    cfg = scenario.protocol
    out = Path(args.out) if args.out else Path("results") / scenario.name
    if out.exists() and not out.is_dir():  # before a viewer is spawned; run_scenario checks the rest
        raise ConfigError(f"{out} exists and is not a directory", where="--out")
    video = video_request(args, scenario)
    plot_subjects = parse_subjects(args.plot_subject)
    if plot_subjects and max(plot_subjects) >= cfg.population.subjects:
        raise ConfigError(f"must be subject indices in 0..{cfg.population.subjects - 1}, got "
                          f"{args.plot_subject}", where="--plot-subject")
    _in_shard(subjects, cfg.population.subjects, plot_subjects=plot_subjects,
              video=None if video is None else video.subject)
    _precheck(scenario)
    if video is not None:
        check_can_render()
    recorder = None  # rerun is imported only for a run that records (a second of start-up otherwise)
    if args.rrd is not None or args.spawn or args.connect is not None:
        from ergosim.viz import open_recording  # noqa: PLC0415

        recorder = open_recording(rrd=args.rrd, spawn=args.spawn, connect=args.connect,
                                  recording_name=f"ergosim {args.scenario} seed {args.seed}")
    committed = False
    try:
        result = run_scenario(scenario, seed=args.seed, out=out, jobs=args.jobs or os.cpu_count(),
                              progress=not args.quiet, recorder=recorder,
                              record_subject=args.rrd_subject if args.rrd_subject is not None
                              else subjects.start, record_mode=args.rrd_mode, video=video,
                              plot_subjects=plot_subjects, subjects=subjects, plots=args.plots)
        committed = True
    finally:
        try:
            if recorder is not None:
                recorder.close(commit=committed)
        except ErgosimError as err:
            if committed:  # the results are written: show them, then say what went wrong with the viewer
                print(summary_text(result.summary, cfg))
                print(f"\nresults: {out.resolve()}")
            raise err from None
    print(summary_text(result.summary, cfg))
    team = "team.json, " if (out / "team.json").is_file() else ""
    print(f"\nresults: {out.resolve()} (run.json, summary.json, {team}allocations.csv, decisions.csv, "
          f"failures.csv, ticks.csv, subjects.csv, kwear_actions.csv, kwear_state_*.json"
          f"{', *.png' if args.plots else ''})")
    print(f"report: {(out / 'report.html').resolve()}  (one page to open in a browser or hand on)")
    if args.rrd:
        print(f"recording: {Path(args.rrd).resolve()}  (open it with: rerun {args.rrd})")
    if result.video is not None:
        print(video_line(result.video, video))
    log.info("wall time %.1f s", result.wall)
    if result.status == "abandoned":
        n = result.summary.get("repetitions_abandoned", 0)
        log.warning("ergosim: %d repetition(s) abandoned: the run is incomplete (exit status 3)", n)
        return EXIT_ABANDONED
    return 0


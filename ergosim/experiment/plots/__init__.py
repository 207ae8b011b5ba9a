"""The scenario's PNG figures (matplotlib, headless Agg), each drawn from the CSV files beside it.

:func:`write_plots` reads ``run.json``, ``ticks.csv``, ``allocations.csv``, ``subjects.csv`` and
``kwear_actions.csv`` back from the run's folder (never the run's memory) and writes:

- ``kwear_timeline_<mode>.png``: KWear per joint over the run, a panel per subject, with V_th, repetition
  starts, robot-acting spans and every attempt labelled (:mod:`~ergosim.experiment.plots.timeline`);
- ``kwear_modes.png``: the KWear integral and the time above V_th per subject, mode against mode, paired
  lines and the Wilcoxon p (:mod:`~ergosim.experiment.plots.modes`; when two or more modes ran);
- ``kwear_actions.png``: the paper's KWear figure, every action from zero wear side by side, and
  ``kwear_<action>.png`` each alone (:mod:`~ergosim.experiment.plots.actions`);
- ``allocation_histogram.png``: the robot's share of each action per mode, with counts
  (:mod:`~ergosim.experiment.plots.allocations`).

``ergosim plot DIR`` redraws them for an existing folder, e.g. for other subjects (``--plot-subject``).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ergosim.errors import ConfigError
from ergosim.experiment.plots.actions import action_figure, actions_figure
from ergosim.experiment.plots.allocations import allocation_figure, robot_counts
from ergosim.experiment.plots.modes import modes_figure, paired_tests
from ergosim.experiment.plots.style import COLOURS, save_figure
from ergosim.experiment.plots.tables import (
    Attempt,
    RunInfo,
    SubjectRow,
    TickTable,
    read_action_traces,
    read_attempts,
    read_run_info,
    read_subjects,
    read_ticks,
)
from ergosim.experiment.plots.timeline import timeline_figure

__all__ = [
    "COLOURS",
    "Attempt",
    "RunInfo",
    "SubjectRow",
    "TickTable",
    "action_figure",
    "actions_figure",
    "allocation_figure",
    "kwear_timeline",
    "modes_figure",
    "paired_tests",
    "read_action_traces",
    "read_attempts",
    "read_run_info",
    "read_subjects",
    "read_ticks",
    "robot_counts",
    "save_figure",
    "timeline_figure",
    "write_plots",
]


def write_plots(out: str | Path, subjects: Sequence[int] | None = None) -> list[str]:
    """Draw every figure of the run in ``out`` from its files; ``subjects``: the subjects the timelines show
    (default: all) and whose per-action figure is drawn (the first given; default: the first subject).
    Returns the names written."""
    out = Path(out)
    info = read_run_info(out)
    rows = read_subjects(out)
    known = sorted({r.subject for r in rows})
    chosen = tuple(dict.fromkeys(subjects)) if subjects else None
    if chosen:
        missing = [s for s in chosen if s not in known]
        if missing:
            raise ConfigError(f"no subject {', '.join(map(str, missing))} in {out}; subjects: "
                              f"{', '.join(map(str, known)) or 'none'}", where="--plot-subject")
    attempts = read_attempts(out)
    workers = {r.subject: r.worker for r in rows}
    written: list[str] = []

    def save(fig, name: str) -> None:
        save_figure(fig, out / name)
        written.append(name)

    ticks = read_ticks(out, chosen)
    for mode in info.modes:
        if ticks.get(mode):
            title = f"{info.scenario}: KWear per joint, mode {mode}"
            save(timeline_figure(ticks[mode], [a for a in attempts if a.mode == mode], v_th=info.v_th,
                                 title=title), f"kwear_timeline_{mode}.png")
    ran = [m for m in info.modes if any(r.mode == m for r in rows)]
    if len(ran) >= 2:
        save(modes_figure(rows, ran, scenario=info.scenario), "kwear_modes.png")
    traces = read_action_traces(out)
    shown = chosen[0] if chosen else (min(s for s, _ in traces) if traces else None)
    mine = {a: tv for (s, a), tv in traces.items() if s == shown}
    if mine:
        save(actions_figure(mine, subject=shown, worker=workers.get(shown, ""), scenario=info.scenario),
             "kwear_actions.png")
        for action, (t, v) in mine.items():
            save(action_figure(action, t, v, subject=shown, worker=workers.get(shown, "")),
                 f"kwear_{action}.png")
    if any(a.done and a.allocatable for a in attempts):
        save(allocation_figure(attempts, info.modes, scenario=info.scenario), "allocation_histogram.png")
    return written


def kwear_timeline(path: Path, t: np.ndarray, v: np.ndarray, v_th: float, title: str) -> None:
    """KWear per joint over time with the V_th line, one panel, for a replayed recording: ``t`` (n,) [s],
    ``v`` (n, 5) in KWEAR_JOINTS order."""
    table = TickTable(t=np.asarray(t, float), repetition=np.zeros(len(t), int), kwear=np.asarray(v, float))
    fig = timeline_figure({0: table}, None, v_th=v_th, title=title, xlabel="time [s]")
    fig.axes[0].set_ylabel("KWear V", fontsize=8)
    save_figure(fig, Path(path))

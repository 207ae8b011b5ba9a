"""Two allocation modes compared over sweeps of the bundled scenarios: the table and the figure of
docs/allocation_modes.md (``scripts/compare_allocation_modes.py``).

Each sweep folder holds one cell run in two modes (a baseline and a challenger) for the same subjects and
seeds; ``cells.parquet`` already has the paired statistics (:mod:`ergosim.sweep.stats`: the mean paired
difference with its 95 % t interval and the two-sided Wilcoxon signed-rank test over the pairs). This module
reads them into rows, and draws, per scenario, the pairs of the load proxies and the time (a line per
subject from one mode to the other) and the robot's share of each action in both modes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq

__all__ = ["ModeRow", "mode_rows", "format_mode_table", "plot_mode_study", "PAIRED_PANELS"]

PAIRED_PANELS = (("kwear_integral", "KWear integral ∫ΣV dt [s]"), ("repetition_time", "repetition time [s]"),
                 ("takt_overruns", "takt overruns (repetitions)"))
"""The paired metrics drawn per scenario (a line per subject), with their axis labels."""


class ModeRow(dict):
    """One metric of one sweep: ``metric``, ``baseline``/``challenger`` means, ``diff`` (challenger −
    baseline, paired) with ``ci_low``/``ci_high``, ``p`` (Wilcoxon), ``pairs``."""


def _cells(folder: Path) -> list[dict]:
    table = pq.read_table(Path(folder) / "cells.parquet").to_pylist()
    if not table:
        raise ValueError(f"{folder}: cells.parquet is empty")
    return table


def _results(folder: Path) -> list[dict]:
    return [r for r in pq.read_table(Path(folder) / "results.parquet").to_pylist() if r["status"] != "failed"]


def mode_rows(folder: str | Path, metrics: Sequence[str]) -> tuple[str, str, list[ModeRow]]:
    """(baseline mode, challenger mode, one :class:`ModeRow` per metric) of the sweep in ``folder``."""
    cells = _cells(Path(folder))
    base, other = cells[0], cells[1]
    rows = []
    for m in metrics:
        rows.append(ModeRow(metric=m, baseline=base.get(f"{m}.mean"), challenger=other.get(f"{m}.mean"),
                            diff=other.get(f"{m}.diff"), ci_low=other.get(f"{m}.diff_ci_low"),
                            ci_high=other.get(f"{m}.diff_ci_high"), p=other.get(f"{m}.wilcoxon_p"),
                            pairs=other.get(f"{m}.pairs")))
    return base["mode"], other["mode"], rows


def _num(x, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "–"
    return f"{x:.{digits}g}"


def format_mode_table(studies: Mapping[str, tuple[str, str, list[ModeRow]]]) -> str:
    """A Markdown table: per scenario and metric, both means, the paired difference with its interval and
    the Wilcoxon p."""
    lines = ["| scenario | metric | {0} | {1} | {1} − {0} [95 % CI] | Wilcoxon p (pairs) |",
             "|---|---|---|---|---|---|"]
    modes = None
    for scenario, (base, other, rows) in studies.items():
        modes = modes or (base, other)
        for r in rows:
            ci = "–" if r["diff"] is None else (f"{_num(r['diff'])} [{_num(r['ci_low'])}, "
                                                 f"{_num(r['ci_high'])}]")
            p = f"{_num(r['p'], 2)} ({r['pairs']})" if r["pairs"] else "–"
            lines.append(f"| {scenario} | {r['metric']} | {_num(r['baseline'])} | {_num(r['challenger'])} | "
                         f"{ci} | {p} |")
    lines[0] = lines[0].format(*(modes or ("a", "b")))
    return "\n".join(lines)


def plot_mode_study(folders: Mapping[str, str | Path], out: str | Path) -> Path:
    """Per scenario (a row): the paired metrics of :data:`PAIRED_PANELS` (a line per subject and seed, from
    the baseline mode to the challenger, the means as coloured bars) and the robot's share of each action in
    both modes (the mean over subjects). Written to ``out`` (PNG)."""
    import matplotlib  # noqa: PLC0415 - plotting only

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415

    n = len(folders)
    fig, axes = plt.subplots(n, len(PAIRED_PANELS) + 1, figsize=(4.2 * (len(PAIRED_PANELS) + 1), 3.4 * n),
                             squeeze=False)
    colours = ("#4c72b0", "#dd8452")
    for row, (scenario, folder) in enumerate(folders.items()):
        results = _results(Path(folder))
        modes = list(dict.fromkeys(r["mode"] for r in results))
        by_mode = {m: {(r["subject"], r["seed"]): r for r in results if r["mode"] == m} for m in modes}
        keys = sorted(set(by_mode[modes[0]]) & set(by_mode[modes[-1]]))
        for col, (metric, label) in enumerate(PAIRED_PANELS):
            ax = axes[row, col]
            a = np.array([by_mode[modes[0]][k][metric] for k in keys], dtype=float)
            b = np.array([by_mode[modes[-1]][k][metric] for k in keys], dtype=float)
            for x0, x1 in zip(a, b, strict=True):
                ax.plot([0, 1], [x0, x1], color="0.6", lw=0.9, marker="o", ms=3.5)
            for x, values, c in ((0, a, colours[0]), (1, b, colours[1])):
                ax.plot([x - 0.18, x + 0.18], [np.nanmean(values)] * 2, color=c, lw=3)
            if not np.any(np.nan_to_num(np.r_[a, b])):
                ax.text(0.5, 0.8, "0 in every run", transform=ax.transAxes, ha="center", color="0.4")
            ax.set_xticks([0, 1], modes[:1] + modes[-1:])
            ax.set_xlim(-0.4, 1.4)
            ax.set_ylabel(label)
            ax.set_title(f"{scenario}: {label.split(' [')[0]}", fontsize=10)
            ax.grid(axis="y", alpha=0.3)
        ax = axes[row, -1]
        actions = [c.split(".", 1)[1] for c in results[0] if c.startswith("robot_share.")]
        actions = [x for x in actions if any(r.get(f"robot_share.{x}") is not None for r in results)]
        width = 0.38
        for i, m in enumerate((modes[0], modes[-1])):
            shares = [np.nanmean([r[f"robot_share.{x}"] if r[f"robot_share.{x}"] is not None else np.nan
                                  for r in by_mode[m].values()]) for x in actions]
            pos = np.arange(len(actions)) + (i - 0.5) * width
            ax.bar(pos, shares, width, color=colours[i], label=m)
            for p, s in zip(pos, shares, strict=True):
                ax.text(p, s + 0.02, f"{s:.0%}", ha="center", fontsize=7)
        ax.set_xticks(np.arange(len(actions)), actions)
        ax.set_ylim(0, 1.3)
        ax.set_ylabel("robot share, mean over subjects")
        ax.set_title(f"{scenario}: the robot's share of each action", fontsize=10)
        ax.legend(fontsize=8, loc="upper left", ncol=2)
    fig.tight_layout()
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out

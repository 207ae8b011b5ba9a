"""``kwear_modes.png``: the physical-load proxy per subject, mode against mode (paper §7.2, HRC vs H only).

Each subject is a line joining its values in the modes, so the paired design shows: a line that rises
from hrc to h-only is a subject whose load HRC lowered. Panels: the KWear integral ∫ΣV dt over the
production schedule (repetitions × takt, the same window in every mode); the highest V any joint reached
(from ``ticks.csv``), against V_th; and the time with a joint at or above V_th. Where no joint of any
subject reached V_th that time is 0 for everyone: its panel is left out and the peak panel says so (the
peaks show how far below V_th the subjects stayed). The Wilcoxon signed-rank test of the first mode
against each other one (two-sided, paired by subject) is computed with the same function as
``summary.json``'s.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ergosim.experiment.plots.style import mode_colour, plt
from ergosim.experiment.plots.tables import SubjectRow
from ergosim.experiment.summary import too_few_pairs, wilcoxon_between
from ergosim.experiment.summary_text import too_few_words

__all__ = ["modes_figure", "paired_tests"]

_METRICS = (("kwear_integral", "KWear integral ∫ΣV dt [s]\n(repetitions × takt)"),
            ("time_above_vth", "time with a joint ≥ V_th [s]"))


def _order(modes: Sequence[str]) -> list[str]:
    """hrc first when it ran (the framework against its baselines), then the others in run order."""
    return sorted(modes, key=lambda m: (m != "hrc", list(modes).index(m)))


def paired_tests(rows: Sequence[SubjectRow], modes: Sequence[str],
                 metric: str) -> list[tuple[str, str, dict]]:
    """(first mode, other mode, wilcoxon_between result) for each other mode, paired by subject."""
    return _paired(_order(modes), {(r.mode, r.subject): getattr(r, metric) for r in rows}, metric)


def _paired(order: Sequence[str], by: Mapping[tuple[str, int], float], metric: str
            ) -> list[tuple[str, str, dict]]:
    subjects = sorted({s for _, s in by})
    tests = []
    for other in order[1:]:
        common = [s for s in subjects if (order[0], s) in by and (other, s) in by]
        tests.append((order[0], other, wilcoxon_between([by[(order[0], s)] for s in common],
                                                        [by[(other, s)] for s in common], metric)))
    return tests


def _p_text(a: str, b: str, test: dict) -> str:
    if too_few_pairs(test["n"]):
        return f"{a} vs {b}: no test,\n{too_few_words(test['n'])}"
    if test["p"] is None:
        return f"{a} vs {b}: no test (n = {test['n']})"
    return f"{a} vs {b}: Wilcoxon W = {test['statistic']:g}, p = {test['p']:.2g}, n = {test['n']}"


def modes_figure(rows: Sequence[SubjectRow], modes: Sequence[str], *, scenario: str = "",
                 peaks: Mapping[tuple[str, int], float] | None = None, v_th: float | None = None):
    """The figure (not saved); lines carry gids ``<metric>/<subject>``, the test texts
    ``p/<metric>/<mode>``. ``peaks``: (mode, subject) -> the highest V any joint reached, drawn against
    ``v_th`` as ``peak_v``."""
    order = _order([m for m in modes if any(r.mode == m for r in rows)])
    x = np.arange(len(order))
    subjects = sorted({r.subject for r in rows})
    values = {m: {(r.mode, r.subject): getattr(r, m) for r in rows} for m, _ in _METRICS}
    reached = any(v > 0 for v in values["time_above_vth"].values())
    panels = [_METRICS[0]]
    if peaks:
        values["peak_v"] = dict(peaks)
        panels.append(("peak_v", "highest V of any joint"))
    if reached or not peaks:
        panels.append(_METRICS[1])
    fig, axes = plt.subplots(1, len(panels), figsize=(4.4 * len(panels), 4.3))
    for ax, (metric, label) in zip(axes, panels, strict=True):
        by = values[metric]
        for s in subjects:
            y = [by.get((m, s), np.nan) for m in order]
            ax.plot(x, y, color="0.55", lw=0.9, marker="o", ms=3.5, mfc="0.3", mec="none", zorder=2,
                    gid=f"{metric}/{s}")
        for k, m in enumerate(order):
            mine = [by[(m, s)] for s in subjects if (m, s) in by]
            if mine:
                ax.hlines(np.mean(mine), k - 0.18, k + 0.18, color=mode_colour(m, k), lw=3, zorder=1,
                          gid=f"mean/{metric}/{m}")
        ax.set_xticks(x, order)
        ax.set_xlim(-0.4, len(order) - 0.6)
        ax.set_ylabel(label, fontsize=9)
        ax.grid(alpha=0.3, axis="y")
        texts = [(f"p/{metric}/{b}", _p_text(a, b, t)) for a, b, t in _paired(order, by, metric)]
        if metric == "peak_v" and v_th is not None:
            ax.axhline(v_th, color="k", ls="--", lw=1, gid="v_th")
            why = "" if reached else (": no joint reached it in any mode,\nso the time above V_th is 0 for "
                                      "everyone")
            texts.append(("note/peak_v", f"V_th = {v_th:g} (dashed){why}"))
        if metric == "time_above_vth" and not reached:
            texts.append(("note/time_above_vth", "0 for every subject: no joint reached V_th"))
        k = 0
        for gid, text in texts:
            ax.text(0.02, 0.98 - 0.06 * k, text, transform=ax.transAxes, fontsize=7.5, va="top", gid=gid,
                    bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.85, "pad": 1.5})
            k += 1 + text.count("\n")
        lines = range(k)
        top = max((v for v in by.values() if np.isfinite(v)), default=0.0) or 1.0
        if metric == "peak_v" and v_th is not None:
            top = max(top, v_th)
        ax.set_ylim(0, top * (1.08 + 0.09 * len(lines)))  # room above the lines for the texts
    fig.suptitle(f"{scenario + ': ' if scenario else ''}physical load per subject by mode "
                 f"({len(subjects)} subject{'s' if len(subjects) != 1 else ''}; lines join a subject's "
                 "values, bars are the means)", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    return fig

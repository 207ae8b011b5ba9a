"""A sweep's figures (matplotlib, Agg), drawn from the units of the cells whose every unit finished.

- ``response_<factor>.png``: each metric of the sweep against a factor's level (a grid or sample axis, or
  a zip's named levels), one line per mode: the mean over the completed units at that level (the other
  factors' cells pooled, a main-effects plot: each worker's cells averaged first, so n counts workers)
  with its 95 % interval as a band and bars (a share's Wilson interval, a mean's clipped t interval:
  :mod:`ergosim.sweep.stats`). Small n is said in the title, n beside the points where it varies, and a
  level with no completed unit is marked;
- ``heatmap_<factor a>__<factor b>.png``, for every pair of factors: the mean of each metric (columns) per
  mode (rows) over a × b; factors with many distinct values (a sampled design) are drawn as a scatter
  coloured by the cell mean instead.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ergosim.experiment.plots import save_figure  # noqa: E402
from ergosim.sweep.metrics import metric_label, share_trials  # noqa: E402
from ergosim.sweep.stats import SMALL_N, counted, metric_ci  # noqa: E402

__all__ = ["write_sweep_plots", "MAX_HEATMAP_LEVELS", "MAX_PAIRS"]

MAX_HEATMAP_LEVELS = 24
"""Factors with more distinct values than this are scattered rather than binned into a heat map."""
MAX_PAIRS = 10
"""At most this many factor pairs get a heat map (the first ones in the file's order)."""

_MODE_COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd")


def _safe(key: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", key)


def _numeric(values: Sequence[Any]) -> bool:
    return all(isinstance(v, int | float) and not isinstance(v, bool) for v in values)


def _label(value: Any) -> str:
    if isinstance(value, list | tuple):
        return ",".join(f"{x:g}" if isinstance(x, float) else str(x) for x in value)
    return f"{value:g}" if isinstance(value, float) else str(value)


def _key(value: Any) -> Any:
    return tuple(value) if isinstance(value, list) else value


def _grid(n: int) -> tuple[int, int]:
    cols = min(n, 2 if n <= 4 else 3)
    return (n + cols - 1) // cols, cols


def _levels(rows, factor) -> list:
    if factor.block == "zip":
        return list(factor.levels)
    return sorted({_key(r[factor.column]) for r in rows}, key=lambda v: (v if _numeric([v]) else str(v)))


def _per_person(rows, metric: str) -> list[dict]:
    """One row per synthetic worker (subject, seed) of the units that count: the mean of ``metric`` over
    that worker's cells (and the sum of a share's trials). A level pooled over other factors holds each
    worker several times; the interval is over workers, not over their repeated cells."""
    trials = share_trials(metric)
    people: dict[tuple, list] = {}
    for r in counted(rows, metric):
        if r.get(metric) is not None:
            people.setdefault((r["subject"], r["seed"]), []).append(r)
    out = []
    for group in people.values():
        row = {metric: float(np.mean([r[metric] for r in group]))}
        if trials is not None:
            row[trials] = sum(r.get(trials) or 0 for r in group) or None
        out.append(row)
    return out


def _stats(rows, metric: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[int]]:
    """(mean, low, high, n) arrays of ``metric`` over each group of rows, per worker (:func:`_per_person`)."""
    out = [metric_ci(_per_person(group, metric), metric) for group in rows]
    nan = lambda v: np.nan if v is None else v  # noqa: E731
    return (np.array([nan(s["mean"]) for s in out], float), np.array([nan(s["ci_low"]) for s in out], float),
            np.array([nan(s["ci_high"]) for s in out], float), [s["n"] for s in out])


def write_sweep_plots(out: Path, sweep, rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """Write the figures of ``rows`` (results rows of complete cells) into ``out``; return their names.
    Levels with no completed unit (every unit failed or was abandoned) are drawn as such (a grey × on the
    response plots, a grey cell marked "failed" or "abandoned" in the heat maps), so the design's
    infeasible part stays visible."""
    if not any(r["status"] != "failed" for r in rows) or not sweep.factors:
        return []
    names = []
    for factor in sweep.factors:
        names.append(_response(out, sweep, factor, rows))
    for a, b in list(itertools.combinations(sweep.factors, 2))[:MAX_PAIRS]:
        names.append(_heatmap(out, sweep, a, b, rows))
    return names


def _response(out: Path, sweep, factor, rows) -> str:
    levels = _levels(rows, factor)
    numeric = factor.block != "zip" and _numeric(levels)
    x = np.asarray(levels, float) if numeric else np.arange(len(levels), dtype=float)
    at = {lv: [r for r in rows if _key(r[factor.column]) == lv] for lv in levels}
    dead = [i for i, lv in enumerate(levels) if not counted(at[lv])]
    nr, nc = _grid(len(sweep.metrics))
    fig, axes = plt.subplots(nr, nc, figsize=(4.6 * nc, 3.3 * nr), squeeze=False)
    sizes = {len({(r["subject"], r["seed"]) for r in counted(rows) if r["mode"] == m}) for rows in at.values()
             for m in sweep.modes}
    uniform = len(sizes) == 1
    for k, metric in enumerate(sweep.metrics):
        ax = axes[k // nc][k % nc]
        for j, mode in enumerate(sweep.modes):
            mean, lo, hi, n = _stats([[r for r in at[lv] if r["mode"] == mode] for lv in levels], metric)
            colour = _MODE_COLOURS[j % len(_MODE_COLOURS)]
            if numeric:  # a line and a band along a numeric axis
                xs = x
                ax.plot(xs, mean, "o-", color=colour, label=mode, ms=4, lw=1.4)
                ax.fill_between(xs, lo, hi, color=colour, alpha=0.18, lw=0)
            else:  # named levels: points with bars, the modes side by side
                xs = x + (j - (len(sweep.modes) - 1) / 2) * 0.12
                ax.plot(xs, mean, "o", color=colour, label=mode, ms=5)
            bars = [np.clip(np.nan_to_num(mean - lo), 0, None), np.clip(np.nan_to_num(hi - mean), 0, None)]
            ax.errorbar(xs, mean, yerr=bars, fmt="none",
                        ecolor=colour, elinewidth=0.9, capsize=3)
            if not uniform:  # else the title says n
                for xi, yi, ni in zip(xs, mean, n, strict=True):
                    if ni and np.isfinite(yi):
                        ax.annotate(f"n={ni}", (xi, yi), xytext=(4, 3), textcoords="offset points",
                                    fontsize=6.5, color=colour)
        if dead:
            ax.plot(x[dead], np.full(len(dead), 0.04), "x", color="0.45", ms=7, mew=1.6,
                    transform=ax.get_xaxis_transform(), label="no unit completed", clip_on=False)
        if not numeric:
            ax.set_xticks(x, [_label(v) for v in levels], rotation=30 if len(levels) > 4 else 0, fontsize=8)
            ax.set_xlim(x[0] - 0.5, x[-1] + 0.5)
        ax.set_xlabel(_factor_label(factor))
        ax.set_ylabel(_wrap(metric_label(metric)), fontsize=8)
        ax.set_title(metric, fontsize=9)
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7, title="mode", title_fontsize=7)
    for k in range(len(sweep.metrics), nr * nc):
        axes[k // nc][k % nc].set_visible(False)
    sizes.discard(0)
    per = f"{min(sizes)}–{max(sizes)}" if len(sizes) > 1 else f"{min(sizes, default=0)}"
    title = _wrap(f"{sweep.name}: response to {factor.name} (mean and 95 % CI over {per} workers per level "
                  "and mode, their completed units averaged)", int(13 * 4.6 * nc))
    if min(sizes, default=0) < SMALL_N:
        title += f"\nsmall n (< {SMALL_N}): the intervals are wide and no paired test can reach p < 0.05"
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    name = f"response_{_safe(factor.name)}.png"
    save_figure(fig, out / name)
    return name


def _factor_label(factor) -> str:
    if factor.block == "zip" and factor.keys != (factor.name,):
        return f"{factor.name} ({' + '.join(factor.keys)})"
    return factor.name


def _heatmap(out: Path, sweep, a, b, rows) -> str:
    la, lb = _levels(rows, a), _levels(rows, b)
    binned = a.block == "zip" or b.block == "zip" or (len(la) <= MAX_HEATMAP_LEVELS
                                                       and len(lb) <= MAX_HEATMAP_LEVELS)
    panels = [(mode, metric) for mode in sweep.modes for metric in sweep.metrics]
    if len(sweep.modes) == 1:
        nr, nc = _grid(len(panels))
    else:
        nr, nc = len(sweep.modes), len(sweep.metrics)
    fig, axes = plt.subplots(nr, nc, figsize=(4.3 * nc, 3.4 * nr), squeeze=False)
    sizes: set[int] = set()
    for k, (mode, metric) in enumerate(panels):
        ax = axes[k // nc][k % nc]
        of = [r for r in rows if r["mode"] == mode]
        if binned:
            groups = [[[r for r in of if _key(r[a.column]) == va and _key(r[b.column]) == vb] for va in la]
                      for vb in lb]
            grid = np.array([_stats(row, metric)[0] for row in groups]).reshape(len(lb), len(la))
            sizes.update(len(counted(c)) for row in groups for c in row if c)
            ax.set_facecolor("0.88")
            im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
            ax.set_xticks(range(len(la)), [_label(v) for v in la], fontsize=7,
                          rotation=30 if len(la) > 5 else 0)
            ax.set_yticks(range(len(lb)), [_label(v) for v in lb], fontsize=7)
            if grid.size <= 64:
                mid = np.nanmean(grid) if np.isfinite(grid).any() else 0.0
                for q, p in itertools.product(range(len(lb)), range(len(la))):
                    cell = groups[q][p]
                    if np.isfinite(grid[q, p]):
                        ax.text(p, q, f"{grid[q, p]:.3g}", ha="center", va="center", fontsize=7,
                                color="white" if grid[q, p] < mid else "black")
                    elif cell and not counted(cell):
                        gone = "failed" if all(r["status"] == "failed" for r in cell) else "abandoned"
                        ax.text(p, q, gone, ha="center", va="center", fontsize=6.5, color="0.35")
        else:
            cells: dict[tuple, list] = {}
            for r in counted(of):
                cells.setdefault((_key(r[a.column]), _key(r[b.column])), []).append(r)
            pts = [(va, vb, metric_ci(v, metric)["mean"]) for (va, vb), v in cells.items()]
            pts = [p for p in pts if p[2] is not None and _numeric(p[:2])]
            sizes.update(len(v) for v in cells.values())
            im = ax.scatter([p[0] for p in pts], [p[1] for p in pts], c=[p[2] for p in pts],
                            cmap="viridis", s=40, edgecolors="k", linewidths=0.4)
        bar = fig.colorbar(im, ax=ax, shrink=0.85)
        bar.ax.tick_params(labelsize=7)
        ax.set_xlabel(_factor_label(a), fontsize=8)
        ax.set_ylabel(_factor_label(b), fontsize=8)
        ax.set_title(f"{metric} ({mode})", fontsize=9)
    for k in range(len(panels), nr * nc):
        axes[k // nc][k % nc].set_visible(False)
    sizes.discard(0)
    per = "" if not sizes else (f" of {min(sizes)}" if len(sizes) == 1 else f" of {min(sizes)}–{max(sizes)}")
    title = f"{sweep.name}: mean per cell{per} completed units over {a.name} × {b.name}"
    if sizes and min(sizes) < SMALL_N:
        title += f" (small n: < {SMALL_N})"
    fig.suptitle(_wrap(title, int(13 * 4.3 * nc)), fontsize=10)
    fig.tight_layout()
    name = f"heatmap_{_safe(a.name)}__{_safe(b.name)}.png"
    save_figure(fig, out / name)
    return name


def _wrap(text: str, width: int = 38) -> str:
    words, lines, line = text.split(), [], ""
    for w in words:
        if line and len(line) + len(w) + 1 > width:
            lines.append(line)
            line = w
        else:
            line = f"{line} {w}".strip()
    return "\n".join([*lines, line])

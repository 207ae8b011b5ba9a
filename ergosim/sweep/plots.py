"""A sweep's figures (matplotlib, Agg), drawn from the units of the cells whose every unit finished.

- ``response_<axis>.png``: each metric of the sweep against the axis value, one line per mode: the mean
  over every unit at that value (the other axes' cells pooled, a main-effects plot) with its 95 % t
  interval as a band and bars;
- ``heatmap_<axis a>__<axis b>.png``, for every pair of axes: the mean of each metric (columns) per mode
  (rows) over a × b; axes with many distinct values (a sampled design) are drawn as a scatter coloured by
  the cell mean instead.
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
from ergosim.sweep.metrics import metric_label  # noqa: E402
from ergosim.sweep.stats import mean_ci  # noqa: E402

__all__ = ["write_sweep_plots", "MAX_HEATMAP_LEVELS", "MAX_PAIRS"]

MAX_HEATMAP_LEVELS = 24
"""Axes with more distinct values than this are scattered rather than binned into a heat map."""
MAX_PAIRS = 10
"""At most this many axis pairs get a heat map (the first ones in the file's order)."""

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


def _levels(rows, column: str) -> list:
    return sorted({_key(r[column]) for r in rows}, key=lambda v: (v if _numeric([v]) else str(v)))


def write_sweep_plots(out: Path, sweep, rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """Write the figures of ``rows`` (results rows of complete cells) into ``out``; return their names.
    Values whose every unit failed are drawn as such (a grey × on the response plots, a grey cell marked
    "failed" in the heat maps), so the design's infeasible part stays visible."""
    if not any(r["status"] != "failed" for r in rows) or not sweep.axes:
        return []
    names = []
    for axis in sweep.axes:
        names.append(_response(out, sweep, axis, rows))
    for a, b in list(itertools.combinations(sweep.axes, 2))[:MAX_PAIRS]:
        names.append(_heatmap(out, sweep, a, b, rows))
    return names


def _response(out: Path, sweep, axis, rows) -> str:
    levels = _levels(rows, axis.column)
    numeric = _numeric(levels)
    x = np.asarray(levels, float) if numeric else np.arange(len(levels), dtype=float)
    at = {lv: [r for r in rows if _key(r[axis.column]) == lv] for lv in levels}
    dead = [i for i, lv in enumerate(levels) if all(r["status"] == "failed" for r in at[lv])]
    nr, nc = _grid(len(sweep.metrics))
    fig, axes = plt.subplots(nr, nc, figsize=(4.6 * nc, 3.3 * nr), squeeze=False)
    for k, metric in enumerate(sweep.metrics):
        ax = axes[k // nc][k % nc]
        for j, mode in enumerate(sweep.modes):
            stats = [mean_ci([r[metric] for r in at[lv] if r["mode"] == mode and r["status"] != "failed"])
                     for lv in levels]
            mean = np.array([s["mean"] if s["mean"] is not None else np.nan for s in stats])
            lo = np.array([s["ci_low"] if s["ci_low"] is not None else np.nan for s in stats])
            hi = np.array([s["ci_high"] if s["ci_high"] is not None else np.nan for s in stats])
            colour = _MODE_COLOURS[j % len(_MODE_COLOURS)]
            ax.plot(x, mean, "o-", color=colour, label=mode, ms=4, lw=1.4)
            ax.fill_between(x, lo, hi, color=colour, alpha=0.18, lw=0)
            ax.errorbar(x, mean, yerr=[np.nan_to_num(mean - lo), np.nan_to_num(hi - mean)], fmt="none",
                        ecolor=colour, elinewidth=0.8, capsize=2.5)
        if dead:
            ax.plot(x[dead], np.full(len(dead), 0.04), "x", color="0.45", ms=7, mew=1.6,
                    transform=ax.get_xaxis_transform(), label="every unit failed", clip_on=False)
        if not numeric:
            ax.set_xticks(x, [_label(v) for v in levels], rotation=30 if len(levels) > 4 else 0, fontsize=8)
        ax.set_xlabel(axis.key)
        ax.set_ylabel(_wrap(metric_label(metric)), fontsize=8)
        ax.set_title(metric, fontsize=9)
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7, title="mode", title_fontsize=7)
    for k in range(len(sweep.metrics), nr * nc):
        axes[k // nc][k % nc].set_visible(False)
    n = {sum(r["status"] != "failed" for r in at[lv]) for i, lv in enumerate(levels) if i not in dead}
    per = f"{min(n)}–{max(n)}" if len(n) > 1 else f"{min(n)}"
    fig.suptitle(f"{sweep.name}: response to {axis.key} (mean and 95 % CI over {per} units per value)",
                 fontsize=10)
    fig.tight_layout()
    name = f"response_{_safe(axis.key)}.png"
    save_figure(fig, out / name)
    return name


def _heatmap(out: Path, sweep, a, b, rows) -> str:
    la, lb = _levels(rows, a.column), _levels(rows, b.column)
    binned = len(la) <= MAX_HEATMAP_LEVELS and len(lb) <= MAX_HEATMAP_LEVELS
    panels = [(mode, metric) for mode in sweep.modes for metric in sweep.metrics]
    if len(sweep.modes) == 1:
        nr, nc = _grid(len(panels))
    else:
        nr, nc = len(sweep.modes), len(sweep.metrics)
    fig, axes = plt.subplots(nr, nc, figsize=(4.3 * nc, 3.4 * nr), squeeze=False)
    for k, (mode, metric) in enumerate(panels):
        ax = axes[k // nc][k % nc]
        of = [r for r in rows if r["mode"] == mode]
        if binned:
            grid = np.full((len(lb), len(la)), np.nan)
            failed = np.zeros(grid.shape, bool)
            for p, va in enumerate(la):
                for q, vb in enumerate(lb):
                    cell = [r for r in of if _key(r[a.column]) == va and _key(r[b.column]) == vb]
                    failed[q, p] = bool(cell) and all(r["status"] == "failed" for r in cell)
                    s = mean_ci([r[metric] for r in cell if r["status"] != "failed"])
                    grid[q, p] = s["mean"] if s["mean"] is not None else np.nan
            ax.set_facecolor("0.88")
            im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
            ax.set_xticks(range(len(la)), [_label(v) for v in la], fontsize=7,
                          rotation=30 if len(la) > 5 else 0)
            ax.set_yticks(range(len(lb)), [_label(v) for v in lb], fontsize=7)
            if grid.size <= 64:
                mid = np.nanmean(grid) if np.isfinite(grid).any() else 0.0
                for q, p in itertools.product(range(len(lb)), range(len(la))):
                    if np.isfinite(grid[q, p]):
                        ax.text(p, q, f"{grid[q, p]:.3g}", ha="center", va="center", fontsize=7,
                                color="white" if grid[q, p] < mid else "black")
                    elif failed[q, p]:
                        ax.text(p, q, "failed", ha="center", va="center", fontsize=6.5, color="0.35")
        else:
            cells: dict[tuple, list] = {}
            for r in of:
                if r["status"] != "failed":
                    cells.setdefault((_key(r[a.column]), _key(r[b.column])), []).append(r[metric])
            pts = [(va, vb, mean_ci(v)["mean"]) for (va, vb), v in cells.items()]
            pts = [p for p in pts if p[2] is not None and _numeric(p[:2])]
            im = ax.scatter([p[0] for p in pts], [p[1] for p in pts], c=[p[2] for p in pts],
                            cmap="viridis", s=40, edgecolors="k", linewidths=0.4)
        bar = fig.colorbar(im, ax=ax, shrink=0.85)
        bar.ax.tick_params(labelsize=7)
        ax.set_xlabel(a.key, fontsize=8)
        ax.set_ylabel(b.key, fontsize=8)
        ax.set_title(f"{metric} ({mode})", fontsize=9)
    for k in range(len(panels), nr * nc):
        axes[k // nc][k % nc].set_visible(False)
    fig.suptitle(f"{sweep.name}: mean per cell over {a.key} × {b.key}", fontsize=10)
    fig.tight_layout()
    name = f"heatmap_{_safe(a.key)}__{_safe(b.key)}.png"
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

"""Statistics of a sweep: means with 95 % confidence intervals, paired and unpaired differences, and the
per-cell table ``cells.parquet``.

Means: Student's t interval, mean ± t_{0.975, n-1} s / √n (n ≥ 2; one value has no interval). Paired
differences (the same subject and seed in both, e.g. two modes of one cell): the t interval of the
differences and the two-sided Wilcoxon signed-rank test, as the paper's §7.2 compares hrc with h-only
(:func:`~ergosim.experiment.summary.wilcoxon_between`). Unpaired differences: Welch's t interval and the
two-sided Mann-Whitney U test. A cell's statistics are computed only once every unit of the cell has
finished; failed units (no metrics) are left out and counted, abandoned ones are kept.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pyarrow as pa
from scipy import stats

from ergosim.experiment.summary import wilcoxon_between
from ergosim.sweep.tables import param_type, param_value

__all__ = ["mean_ci", "paired_difference", "unpaired_difference", "cell_statistics", "group_values",
           "CONFIDENCE", "STAT_SUFFIXES", "DIFF_SUFFIXES"]

CONFIDENCE = 0.95
STAT_SUFFIXES = ("mean", "ci_low", "ci_high", "std", "n")
DIFF_SUFFIXES = ("diff", "diff_ci_low", "diff_ci_high", "pairs", "wilcoxon_statistic", "wilcoxon_p")


def _t_interval(mean: float, se: float, dof: float) -> tuple[float | None, float | None]:
    if not (dof > 0 and math.isfinite(se)):
        return None, None
    half = float(stats.t.ppf(0.5 + CONFIDENCE / 2, dof)) * se
    return mean - half, mean + half


def mean_ci(values: Sequence[float]) -> dict[str, Any]:
    """{mean, ci_low, ci_high, std, n} of ``values`` (None entries left out)."""
    x = np.asarray([v for v in values if v is not None], float)
    n = int(x.size)
    if n == 0:
        return {"mean": None, "ci_low": None, "ci_high": None, "std": None, "n": 0}
    mean = float(x.mean())
    std = float(x.std(ddof=1)) if n > 1 else None
    lo, hi = _t_interval(mean, std / math.sqrt(n), n - 1) if std is not None else (None, None)
    return {"mean": mean, "ci_low": lo, "ci_high": hi, "std": std, "n": n}


def paired_difference(a: Sequence[float], b: Sequence[float]) -> dict[str, Any]:
    """b − a over pairs (None pairs left out): mean difference, its t interval, the Wilcoxon test."""
    pairs = [(x, y) for x, y in zip(a, b, strict=True) if x is not None and y is not None]
    if not pairs:
        return {**dict.fromkeys(DIFF_SUFFIXES), "pairs": 0}
    x, y = (np.asarray(v, float) for v in zip(*pairs, strict=True))
    d = y - x
    ci = mean_ci(list(d))
    w = wilcoxon_between(list(y), list(x), "")
    return {"diff": ci["mean"], "diff_ci_low": ci["ci_low"], "diff_ci_high": ci["ci_high"], "pairs": len(d),
            "wilcoxon_statistic": w["statistic"], "wilcoxon_p": w["p"]}


def unpaired_difference(a: Sequence[float], b: Sequence[float]) -> dict[str, Any]:
    """mean(b) − mean(a): Welch's t interval and the two-sided Mann-Whitney U test."""
    x = np.asarray([v for v in a if v is not None], float)
    y = np.asarray([v for v in b if v is not None], float)
    out: dict[str, Any] = {"diff": None, "diff_ci_low": None, "diff_ci_high": None, "n_a": int(x.size),
                           "n_b": int(y.size), "mannwhitney_u": None, "mannwhitney_p": None}
    if x.size == 0 or y.size == 0:
        return out
    diff = float(y.mean() - x.mean())
    out["diff"] = diff
    if x.size > 1 and y.size > 1:
        va, vb = x.var(ddof=1) / x.size, y.var(ddof=1) / y.size
        se = math.sqrt(va + vb)
        if se > 0:
            dof = (va + vb) ** 2 / (va**2 / (x.size - 1) + vb**2 / (y.size - 1))
            out["diff_ci_low"], out["diff_ci_high"] = _t_interval(diff, se, dof)
        else:
            out["diff_ci_low"] = out["diff_ci_high"] = diff
    if np.all(x == x[0]) and np.all(y == x[0]):
        out["mannwhitney_u"], out["mannwhitney_p"] = float(x.size * y.size / 2), 1.0
    else:
        res = stats.mannwhitneyu(y, x, alternative="two-sided")
        out["mannwhitney_u"], out["mannwhitney_p"] = float(res.statistic), float(res.pvalue)
    return out


def group_values(rows: Sequence[Mapping[str, Any]], metric: str) -> dict[tuple, float | None]:
    """(subject, seed) -> the metric, of rows that did not fail."""
    return {(r["subject"], r["seed"]): r[metric] for r in rows if r["status"] != "failed"}


def cell_statistics(sweep, rows: Sequence[Mapping[str, Any]], complete_cells: set[int]) -> pa.Table:
    """``cells.parquet``: one row per (complete cell, mode) with unit counts, the mean and 95 % CI of every
    metric of the sweep and, for each mode after the first (the baseline), the paired difference from the
    baseline (same subject and seed) with its CI and the Wilcoxon signed-rank test."""
    baseline = sweep.modes[0]
    fields = [pa.field("cell", pa.int32()), pa.field("label", pa.string())]
    fields += [pa.field(a.column, param_type(a.values)) for a in sweep.axes]
    fields += [pa.field(k, pa.int64()) for k in ("units", "units_failed", "units_abandoned")]
    fields += [pa.field("mode", pa.string()), pa.field("baseline", pa.string())]
    for m in sweep.metrics:
        fields += [pa.field(f"{m}.{s}", pa.int64() if s == "n" else pa.float64()) for s in STAT_SUFFIXES]
        fields += [pa.field(f"{m}.{s}", pa.int64() if s == "pairs" else pa.float64()) for s in DIFF_SUFFIXES]
    data: dict[str, list] = {f.name: [] for f in fields}
    by_cell: dict[int, dict[str, list]] = {}
    for r in rows:
        by_cell.setdefault(r["cell"], {}).setdefault(r["mode"], []).append(r)
    for cell in sweep.cells:
        if cell.index not in complete_cells:
            continue
        modes = by_cell.get(cell.index, {})
        base_rows = modes.get(baseline, [])
        for mode in sweep.modes:
            mode_rows = modes.get(mode, [])
            data["cell"].append(cell.index)
            data["label"].append(cell.label())
            for a in sweep.axes:
                data[a.column].append(param_value(cell.params[a.key], param_type(a.values)))
            data["units"].append(len(mode_rows))
            data["units_failed"].append(sum(r["status"] == "failed" for r in mode_rows))
            data["units_abandoned"].append(sum(r["status"] == "abandoned" for r in mode_rows))
            data["mode"].append(mode)
            data["baseline"].append(baseline if mode != baseline else None)
            for m in sweep.metrics:
                s = mean_ci([v for v in group_values(mode_rows, m).values()])
                for k in STAT_SUFFIXES:
                    data[f"{m}.{k}"].append(s[k])
                if mode == baseline:
                    d = dict.fromkeys(DIFF_SUFFIXES)
                else:
                    base, this = group_values(base_rows, m), group_values(mode_rows, m)
                    keys = sorted(set(base) & set(this))
                    d = paired_difference([base[k] for k in keys], [this[k] for k in keys])
                for k in DIFF_SUFFIXES:
                    data[f"{m}.{k}"].append(d[k])
    return pa.table(data, schema=pa.schema(fields))


"""Statistics of a sweep: means and shares with 95 % confidence intervals that stay inside what the metric
can be, paired and unpaired differences, and the per-cell table ``cells.parquet``.

- **Shares** (``robot_share``, ``robot_share.<a>``, ``robot_share_chosen``; each unit's k robot actions
  out of m): the Wilson score interval (Wilson 1927) at the units' effective number of trials. A unit is
  one synthetic worker, and its actions are not independent trials, so the trials are discounted by the
  design effect the units show (Kish 1965): n* = p̄(1 − p̄) / (s² / n), at most the pooled trials Σm, and
  Σm when the units agree exactly. Korn & Graubard's (1998) degrees-of-freedom factor (z / t_{n−1})²
  then widens it for few units. The interval lies in [0, 1] by construction.
- **Means** of every other metric: Student's t interval, mean ± t_{0.975, n−1} s / √n, clipped to the
  metric's range (:func:`~ergosim.sweep.metrics.metric_range`: no negative time or wear).
- One unit has no interval. Fewer than :data:`SMALL_N` units are *small n*: the tables, the plots and
  ``ergosim compare`` say so.
- **Which units count**: only ``complete`` ones. A ``failed`` unit has no metrics; an ``abandoned`` one
  has the metrics of a run cut short (a partial KWear integral, fewer actions), which would pull a mean
  down and fake a paired difference. Both are counted apart (``units_failed``, ``units_abandoned``) and
  left out of every mean, interval and difference; a pair counts only when both its units completed.
  G(a_k) (``rula_g.<a>``) comes from the calibration before the run, whole in an abandoned unit too,
  which counts for it: leaving it out would drop the workers a cell is hardest for.
- **Paired differences** (the same subject and seed in both, e.g. two modes of one cell): the t interval
  of the differences and the two-sided Wilcoxon signed-rank test, as the paper's §7.2 compares hrc with
  h-only (:func:`~ergosim.experiment.summary.wilcoxon_between`). With n non-zero differences the test's
  smallest p is 2 / 2ⁿ (``wilcoxon_min_p``): 0.25 at n = 3, 0.0625 at n = 5, so below six pairs it
  cannot show a difference at 0.05 whatever the data. **Unpaired differences**: Welch's t interval and
  the two-sided Mann-Whitney U test. Differences are clipped to what a difference of the metric can be.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pyarrow as pa
from scipy import stats

from ergosim.experiment.summary import wilcoxon_between, wilcoxon_min_p
from ergosim.sweep.metrics import from_calibration, metric_range, share_trials
from ergosim.sweep.tables import param_type, param_value

__all__ = ["interval_text", "round_off", "mean_ci", "share_ci", "metric_ci", "wilson_interval",
           "wilcoxon_min_p", "paired_difference", "unpaired_difference", "cell_statistics", "counted",
           "CONFIDENCE", "SMALL_N", "STAT_SUFFIXES", "DIFF_SUFFIXES"]

CONFIDENCE = 0.95
SMALL_N = 6
"""Fewer units (or pairs) than this are "small n": a paired Wilcoxon test cannot reach p < 0.05."""
STAT_SUFFIXES = ("mean", "ci_low", "ci_high", "std", "n", "interval")
DIFF_SUFFIXES = ("diff", "diff_ci_low", "diff_ci_high", "pairs", "wilcoxon_statistic", "wilcoxon_p",
                 "wilcoxon_min_p")
_Z = float(stats.norm.ppf(0.5 + CONFIDENCE / 2))


def _t(dof: float) -> float:
    return float(stats.t.ppf(0.5 + CONFIDENCE / 2, dof))


def _clip(lo: float | None, hi: float | None, bounds: tuple[float | None, float | None]):
    low, high = bounds
    if lo is not None and low is not None:
        lo = max(lo, low)
    if hi is not None and high is not None:
        hi = min(hi, high)
    return lo, hi


def _none(kind: str, n: int = 0, mean: float | None = None, std: float | None = None) -> dict[str, Any]:
    return {"mean": mean, "ci_low": None, "ci_high": None, "std": std, "n": n, "interval": kind}


def mean_ci(values: Sequence[float | None], bounds: tuple[float | None, float | None] = (None, None)
            ) -> dict[str, Any]:
    """{mean, ci_low, ci_high, std, n, interval} of ``values`` (None left out): the Student t interval,
    clipped to ``bounds`` (low, high; None: unbounded)."""
    x = np.asarray([v for v in values if v is not None], float)
    n = int(x.size)
    if n == 0:
        return _none("t")
    mean = float(x.mean())
    if n == 1:
        return _none("t", 1, mean)
    std = float(x.std(ddof=1))
    half = _t(n - 1) * std / math.sqrt(n)
    lo, hi = _clip(mean - half, mean + half, bounds)
    return {"mean": mean, "ci_low": lo, "ci_high": hi, "std": std, "n": n, "interval": "t"}


def wilson_interval(p: float, n: float) -> tuple[float, float]:
    """The 95 % Wilson score interval of a proportion ``p`` observed in ``n`` trials (n may be an
    effective, non-integer number of trials)."""
    z2 = _Z * _Z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = _Z / (1 + z2 / n) * math.sqrt(max(p * (1 - p), 0.0) / n + z2 / (4 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def share_ci(values: Sequence[float | None], trials: Sequence[float | None] | None = None) -> dict[str, Any]:
    """{mean, ci_low, ci_high, std, n, interval, n_eff} of the units' shares ``values`` (None left out),
    each of ``trials[i]`` trials (None or no ``trials``: one trial per unit): the Wilson interval at the
    effective number of trials, with Korn & Graubard's degrees-of-freedom factor (module docstring)."""
    m = [1.0] * len(values) if trials is None else [1.0 if t is None else float(t) for t in trials]
    kept = [(float(v), t) for v, t in zip(values, m, strict=True) if v is not None]
    n = len(kept)
    if n == 0:
        return {**_none("wilson"), "n_eff": None}
    x = np.asarray([v for v, _ in kept])
    mean = float(x.mean())
    if n == 1:
        return {**_none("wilson", 1, mean), "n_eff": None}
    std = float(x.std(ddof=1))
    pooled = max(sum(t for _, t in kept), float(n))
    var = std * std / n
    n_eff = pooled if var == 0 or mean in (0.0, 1.0) else min(mean * (1 - mean) / var, pooled)
    n_eff *= (_Z / _t(n - 1)) ** 2
    lo, hi = wilson_interval(mean, n_eff)
    return {"mean": mean, "ci_low": lo, "ci_high": hi, "std": std, "n": n, "interval": "wilson",
            "n_eff": n_eff}


def metric_ci(rows: Sequence[Mapping[str, Any]], metric: str) -> dict[str, Any]:
    """The mean of ``metric`` over ``rows`` (results rows, already the units that count) with the interval
    its kind takes: a share's Wilson interval (its trials from the row's trials column), else the t
    interval clipped to the metric's range."""
    values = [r.get(metric) for r in rows]
    trials = share_trials(metric)
    if trials is not None:
        return share_ci(values, [r.get(trials) for r in rows])
    return mean_ci(values, metric_range(metric))


def _difference_bounds(metric: str | None) -> tuple[float | None, float | None]:
    if metric is None:
        return None, None
    low, high = metric_range(metric)
    return (None, None) if high is None else (low - high, high - low)


def paired_difference(a: Sequence[float | None], b: Sequence[float | None], metric: str | None = None
                      ) -> dict[str, Any]:
    """b − a over pairs (None pairs left out): mean difference, its t interval (clipped to what a
    difference of ``metric`` can be), the Wilcoxon test and the smallest p it could give."""
    pairs = [(x, y) for x, y in zip(a, b, strict=True) if x is not None and y is not None]
    if not pairs:
        return {**dict.fromkeys(DIFF_SUFFIXES), "pairs": 0}
    x, y = (np.asarray(v, float) for v in zip(*pairs, strict=True))
    d = y - x
    ci = mean_ci(list(d), _difference_bounds(metric))
    w = wilcoxon_between(list(y), list(x), "")
    return {"diff": ci["mean"], "diff_ci_low": ci["ci_low"], "diff_ci_high": ci["ci_high"], "pairs": len(d),
            "wilcoxon_statistic": w["statistic"], "wilcoxon_p": w["p"],
            "wilcoxon_min_p": wilcoxon_min_p(int(np.count_nonzero(d)))}


def unpaired_difference(a: Sequence[float | None], b: Sequence[float | None], metric: str | None = None
                        ) -> dict[str, Any]:
    """mean(b) − mean(a): Welch's t interval (clipped like :func:`paired_difference`) and the two-sided
    Mann-Whitney U test."""
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
            half = _t(dof) * se
            out["diff_ci_low"], out["diff_ci_high"] = _clip(diff - half, diff + half,
                                                            _difference_bounds(metric))
        else:
            out["diff_ci_low"] = out["diff_ci_high"] = diff
    if np.all(x == x[0]) and np.all(y == x[0]):
        out["mannwhitney_u"], out["mannwhitney_p"] = float(x.size * y.size / 2), 1.0
    else:
        res = stats.mannwhitneyu(y, x, alternative="two-sided")
        out["mannwhitney_u"], out["mannwhitney_p"] = float(res.statistic), float(res.pvalue)
    return out


def counted(rows: Sequence[Mapping[str, Any]], metric: str | None = None) -> list[Mapping[str, Any]]:
    """The rows whose units enter the statistics of ``metric``: the complete ones (failed and abandoned
    units are reported apart; module docstring), and the abandoned ones too for a metric the calibration
    set before the run (G(a_k): leaving them out would drop the workers the cell is hardest for)."""
    keep = ("complete", "abandoned") if metric is not None and from_calibration(metric) else ("complete",)
    return [r for r in rows if r["status"] in keep]


def _by_person(rows: Sequence[Mapping[str, Any]], metric: str) -> dict[tuple, Mapping[str, Any]]:
    """(subject, seed) -> the row, of the units that count for ``metric``."""
    return {(r["subject"], r["seed"]): r for r in counted(rows, metric)}


def cell_statistics(sweep, rows: Sequence[Mapping[str, Any]], complete_cells: set[int]) -> pa.Table:
    """``cells.parquet``: one row per (complete cell, mode) with unit counts, the mean and 95 % CI of every
    metric of the sweep and, for each mode after the first (the baseline), the paired difference from the
    baseline (same subject and seed) with its CI and the Wilcoxon signed-rank test."""
    baseline = sweep.modes[0]
    fields = [pa.field("cell", pa.int32()), pa.field("label", pa.string())]
    fields += [pa.field(f.column, pa.string()) for f in sweep.factors if f.block == "zip"]
    fields += [pa.field(a.column, param_type(a.values)) for a in sweep.axes]
    fields += [pa.field(k, pa.int64()) for k in ("units", "units_failed", "units_abandoned", "units_counted")]
    fields += [pa.field("small_n", pa.bool_()), pa.field("mode", pa.string()),
               pa.field("baseline", pa.string())]
    kinds = {"n": pa.int64(), "interval": pa.string(), "pairs": pa.int64()}
    for m in sweep.metrics:
        fields += [pa.field(f"{m}.{s}", kinds.get(s, pa.float64())) for s in (*STAT_SUFFIXES, *DIFF_SUFFIXES)]
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
            used = counted(mode_rows)
            data["cell"].append(cell.index)
            data["label"].append(cell.label())
            for f in sweep.factors:
                if f.block == "zip":
                    data[f.column].append(cell.levels[f.name])
            for a in sweep.axes:
                data[a.column].append(param_value(cell.params[a.key], param_type(a.values)))
            data["units"].append(len(mode_rows))
            data["units_failed"].append(sum(r["status"] == "failed" for r in mode_rows))
            data["units_abandoned"].append(sum(r["status"] == "abandoned" for r in mode_rows))
            data["units_counted"].append(len(used))
            data["small_n"].append(len(used) < SMALL_N)
            data["mode"].append(mode)
            data["baseline"].append(baseline if mode != baseline else None)
            for m in sweep.metrics:
                s = metric_ci(counted(mode_rows, m), m)
                for k in STAT_SUFFIXES:
                    data[f"{m}.{k}"].append(s[k])
                if mode == baseline:
                    d = dict.fromkeys(DIFF_SUFFIXES)
                else:
                    base, this = _by_person(base_rows, m), _by_person(mode_rows, m)
                    keys = sorted(set(base) & set(this))
                    d = paired_difference([base[k].get(m) for k in keys], [this[k].get(m) for k in keys], m)
                for k in DIFF_SUFFIXES:
                    data[f"{m}.{k}"].append(d[k])
    return pa.table(data, schema=pa.schema(fields))


ROUND_OFF = 1e-9
"""A figure smaller than this fraction of the largest it is printed with (or than 1e-12 itself) is float
round-off, printed as 0 (assumed: the metrics carry far fewer significant digits, a t interval bound of
5.55e-17 is an exact 0 that lost its last bits)."""


def round_off(x: float, scale: float) -> float:
    """``x``, or 0.0 when it is round-off (:data:`ROUND_OFF`) among figures of magnitude ``scale``."""
    return 0.0 if abs(x) <= max(ROUND_OFF * abs(scale), 1e-12) else x


def interval_text(lo: float | None, hi: float | None, mean: float | None = None, digits: int = 3) -> str:
    """``"lo, hi"`` to ``digits`` significant digits, round-off as 0 (:func:`round_off`); ``mean`` only
    sets the scale with them."""
    if lo is None or hi is None:
        return "-"
    scale = max(abs(lo), abs(hi), abs(mean or 0.0))
    return ", ".join(f"{round_off(x, scale):.{digits}g}" for x in (lo, hi))

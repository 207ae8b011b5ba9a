"""Compare two run or sweep folders (``ergosim compare DIR_A DIR_B``): metric differences B − A with 95 %
confidence intervals, paired where the subjects match.

A run folder (``ergosim run``) gives one row per subject and mode from its ``subject_records.json``, with
the metrics of a sweep unit (:func:`~ergosim.sweep.metrics.unit_metrics`); a sweep folder gives the rows
of its ``results.parquet``. Cells are matched by their axis values (two folders of one cell each are
compared as they are, e.g. a run against a one-cell sweep). Within a matched cell and mode, the units of
the same subject of the same population seed are the same synthetic worker: with at least two such pairs
the comparison is paired (t interval of the differences, Wilcoxon signed-rank test); otherwise unpaired
(Welch's interval, Mann-Whitney U test). Failed units are left out.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ergosim.errors import ConfigError
from ergosim.experiment.subject_records import RECORDS_FILE, read_records
from ergosim.sweep.metrics import DEFAULT_METRICS, check_metric, unit_metrics
from ergosim.sweep.stats import mean_ci, paired_difference, unpaired_difference

__all__ = ["Folder", "read_folder", "compare_folders", "comparison_text"]


@dataclasses.dataclass(frozen=True)
class Folder:
    """A run or sweep folder as rows: ``cell`` (a key of the axis values), ``label``, ``subject``,
    ``seed``, ``mode``, ``status`` and the metrics."""

    path: Path
    kind: str
    rows: tuple[dict, ...]
    actions: tuple[str, ...]
    metrics: tuple[str, ...]

    @property
    def cells(self) -> dict[str, str]:
        return {r["cell"]: r["label"] for r in self.rows}

    def describe(self) -> str:
        cells, units = len(self.cells), len(self.rows)
        subjects = len({(r["subject"], r["seed"]) for r in self.rows})
        return f"{self.path} ({self.kind}: {cells} cell(s), {subjects} subject(s), {units} rows)"


def _cell_key(params: dict[str, Any]) -> str:
    return json.dumps(params, sort_keys=True)


def read_folder(path: str | Path) -> Folder:
    """The rows of the run folder or sweep folder at ``path``."""
    path = Path(path)
    if not path.is_dir():
        raise ConfigError("not a directory", where=str(path))
    if (path / "results.parquet").is_file() and (path / "sweep.json").is_file():
        return _sweep_folder(path)
    if (path / RECORDS_FILE).is_file():
        return _run_folder(path)
    raise ConfigError("neither a run folder (subject_records.json) nor a sweep folder (results.parquet, "
                      "sweep.json)", where=str(path))


def _run_folder(path: Path) -> Folder:
    header, records = read_records(path / RECORDS_FILE)
    actions = tuple(sorted(records[0].alphas)) if records else ()
    rows = []
    for rec in records:
        for mode in header["config"]["modes"]:
            run = rec.runs.get(mode)
            if run is None:
                continue
            abandoned = any(o.outcome == "abandoned" for o in run.outcomes)
            rows.append({"cell": _cell_key({}), "label": header["scenario"], "subject": rec.subject,
                         "seed": header["seed"], "mode": mode,
                         "status": "abandoned" if abandoned else "complete",
                         **unit_metrics(run, rec.rula_g, actions)})
    return Folder(path, "run", tuple(rows), actions, DEFAULT_METRICS)


def _sweep_folder(path: Path) -> Folder:
    from ergosim.sweep.tables import read_parquet  # noqa: PLC0415

    try:
        manifest = json.loads((path / "sweep.json").read_text(encoding="utf-8"))
        keys = [a["key"] for a in manifest["axes"]]
        table = read_parquet(path / "results.parquet")
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise ConfigError(f"cannot read the sweep folder: {err}", where=str(path)) from None
    rows = []
    for r in table.to_pylist():
        params = {k: r[f"param.{k}"] for k in keys}
        label = ", ".join(f"{k}={_fmt_param(v)}" for k, v in params.items()) or "base"
        rows.append({**r, "cell": _cell_key(params), "label": label})
    return Folder(path, "sweep", tuple(rows), tuple(manifest.get("actions", ())),
                  tuple(manifest.get("metrics", DEFAULT_METRICS)))


def _fmt_param(v: Any) -> str:
    if isinstance(v, list):
        return ",".join(f"{x:g}" for x in v)
    return f"{v:g}" if isinstance(v, float) else str(v)


def _matched_cells(a: Folder, b: Folder) -> list[tuple[str, str, str]]:
    """(cell of a, cell of b, label) pairs to compare."""
    ca, cb = a.cells, b.cells
    if len(ca) == 1 and len(cb) == 1:
        (ka, la), (kb, lb) = next(iter(ca.items())), next(iter(cb.items()))
        return [(ka, kb, la if la == lb else f"{la} vs {lb}")]
    common = [k for k in ca if k in cb]
    if not common:
        raise ConfigError(f"the folders share no cell (no equal axis values); {a.path} has {len(ca)} "
                          f"cell(s), {b.path} {len(cb)}", where="ergosim compare")
    return [(k, k, ca[k]) for k in common]


def compare_folders(a: Folder, b: Folder, metrics: Sequence[str] | None = None) -> list[dict[str, Any]]:
    """One row per (matched cell, mode in both, metric): the means of A and B with their CIs and the
    difference B − A with its CI and test."""
    actions = tuple(dict.fromkeys((*a.actions, *b.actions)))
    metrics = tuple(metrics or dict.fromkeys((*a.metrics, *b.metrics)))
    for m in metrics:
        check_metric(m, actions, where="--metric")
    out = []
    for ka, kb, label in _matched_cells(a, b):
        ra = [r for r in a.rows if r["cell"] == ka and r["status"] != "failed"]
        rb = [r for r in b.rows if r["cell"] == kb and r["status"] != "failed"]
        for mode in [m for m in dict.fromkeys(r["mode"] for r in ra) if any(r["mode"] == m for r in rb)]:
            xa = {(r["subject"], r["seed"]): r for r in ra if r["mode"] == mode}
            xb = {(r["subject"], r["seed"]): r for r in rb if r["mode"] == mode}
            common = sorted(set(xa) & set(xb))
            for m in metrics:
                va, vb = [r.get(m) for r in xa.values()], [r.get(m) for r in xb.values()]
                row = {"cell": label, "mode": mode, "metric": m, "a": mean_ci(va), "b": mean_ci(vb)}
                if len(common) >= 2:
                    d = paired_difference([xa[k].get(m) for k in common], [xb[k].get(m) for k in common])
                    row.update(test="wilcoxon", n=d["pairs"], diff=d["diff"], ci_low=d["diff_ci_low"],
                               ci_high=d["diff_ci_high"], statistic=d["wilcoxon_statistic"],
                               p=d["wilcoxon_p"])
                else:
                    d = unpaired_difference(va, vb)
                    row.update(test="mann-whitney", n=d["n_a"] + d["n_b"], diff=d["diff"],
                               ci_low=d["diff_ci_low"], ci_high=d["diff_ci_high"],
                               statistic=d["mannwhitney_u"], p=d["mannwhitney_p"])
                out.append(row)
    if not out:
        raise ConfigError("the folders share no mode in their matched cells", where="ergosim compare")
    return out


def _num(x: float | None, width: int = 9) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-".rjust(width)
    return f"{x:.4g}".rjust(width)


def _ci(lo: float | None, hi: float | None) -> str:
    return "[" + (f"{lo:.3g}, {hi:.3g}" if lo is not None and hi is not None else "-") + "]"


def comparison_text(a: Folder, b: Folder, rows: Sequence[dict[str, Any]]) -> str:
    lines = [f"A: {a.describe()}", f"B: {b.describe()}",
             "difference B − A with its 95 % CI; paired (Wilcoxon signed-rank) where the same subjects and "
             "seeds are in both, else Welch / Mann-Whitney U"]
    cell = None
    for r in rows:
        if r["cell"] != cell:
            cell = r["cell"]
            lines.append(f"\n{cell}")
            lines.append(f"  {'mode':<8} {'metric':<22} {'A mean':>9} {'B mean':>9} {'B − A':>9} "
                         f"{'95 % CI':>22} {'test':>12} {'n':>4} {'p':>9}")
        lines.append(f"  {r['mode']:<8} {r['metric']:<22} {_num(r['a']['mean'])} {_num(r['b']['mean'])} "
                     f"{_num(r['diff'])} {_ci(r['ci_low'], r['ci_high']):>22} {r['test']:>12} {r['n']:>4} "
                     f"{_num(r['p'])}")
    return "\n".join(lines)

"""Compare two run or sweep folders, or two cells of one sweep (``ergosim compare``): which settings
differ, and the metric differences B − A with 95 % confidence intervals, paired where the subjects match.

A run folder (``ergosim run``) gives one row per subject and mode from its ``subject_records.json``, with
the metrics of a sweep unit (:func:`~ergosim.sweep.metrics.unit_metrics`); a sweep folder gives the rows
of its ``results.parquet``. :func:`select` keeps the cells of a folder whose factors have given levels
(``layout=B``, ``takt=45``, ``cell=3``), so two cells of one sweep, or a sweep's cell and a run, can be
compared. Cells are then matched: two single cells as they are; one cell against each cell of the
other side; otherwise by the values of the factors neither side selected. Within a matched cell and mode,
the units of the same subject of the same population seed are the same synthetic worker: with at least
two such pairs the comparison is paired (t interval of the differences, Wilcoxon signed-rank test, and
the smallest p the test could give at that n); otherwise unpaired (Welch's interval, Mann-Whitney U).
Only complete units count (:func:`~ergosim.sweep.stats.counted`); a folder whose run or sweep did not
finish (interrupted, crashed, still running) is compared with a warning.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ergosim.errors import ConfigError
from ergosim.experiment.subject_records import RECORDS_FILE, read_records
from ergosim.sweep.metrics import DEFAULT_METRICS, check_metric, unit_metrics
from ergosim.sweep.stats import (
    SMALL_N,
    counted,
    interval_text,
    metric_ci,
    paired_difference,
    unpaired_difference,
)

__all__ = ["Folder", "read_folder", "select", "compare_folders", "comparison_text", "settings_difference"]

_NOT_SETTINGS = ("subjects", "modes", "scene", "task")
"""Config entries that are not settings of a cell: the population (said by the folder's description) and
the labels of the workcell and the task (said by the settings that chose them)."""


@dataclasses.dataclass(frozen=True)
class Folder:
    """A run or sweep folder as rows: ``cell`` (a key of the axis values), ``label``, ``subject``,
    ``seed``, ``mode``, ``status`` and the metrics. ``settings``: per cell key, each setting's value as a
    string (the protocol, the scenario, every override); ``status``: how the run or sweep ended;
    ``factors``: a sweep's factors (name, block, keys, levels)."""

    path: Path
    kind: str
    rows: tuple[dict, ...]
    actions: tuple[str, ...]
    metrics: tuple[str, ...]
    status: str = "complete"
    settings: Mapping[str, Mapping[str, str]] = dataclasses.field(default_factory=dict)
    factors: tuple[Mapping[str, Any], ...] = ()
    selected: tuple[str, ...] = ()

    @property
    def cells(self) -> dict[str, str]:
        return {r["cell"]: r["label"] for r in self.rows}

    def describe(self) -> str:
        cells, units = len(self.cells), len(self.rows)
        subjects = len({(r["subject"], r["seed"]) for r in self.rows})
        left = sum(r["status"] != "complete" for r in self.rows)
        out = f"{self.path} ({self.kind}: {cells} cell(s), {subjects} subject(s), {units} rows"
        out += f", {left} abandoned or failed and left out" if left else ""
        out += f"; {', '.join(self.selected)}" if self.selected else ""
        return out + ")"

    def warning(self) -> str | None:
        """What to warn about before comparing: a run or sweep that did not finish."""
        if self.status in ("complete", "abandoned", "incomplete"):
            return None
        what = {"running": "still running, or was killed (it never wrote its end)",
                "interrupted": "was interrupted (Ctrl-C or SIGTERM)", "failed": "stopped on an error"}
        said = what.get(self.status, f"has status {self.status!r}")
        return f"{self.path}: the {self.kind} {said}; only the units it finished are compared"


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


def _manifest(path: Path) -> dict[str, Any]:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return {}
    return doc if isinstance(doc, dict) else {}


def _settings(scenario: str, config: Mapping[str, Any], overrides: Mapping[str, Any]) -> dict[str, str]:
    """Each setting's value as a string: the scenario, the protocol (with protocol overrides applied), and
    every other override (workcell, task)."""
    out = {"scenario": str(scenario)}
    out.update({k: _text(v) for k, v in config.items() if k not in (*_NOT_SETTINGS, "overrides")})
    for key, value in overrides.items():
        bare = key.removeprefix("protocol.")
        if bare in _NOT_SETTINGS:
            continue
        out[bare if bare in config else key] = _text(value)
    return out


def _text(value: Any) -> str:
    """A setting's value as one canonical string: numbers by value (``60`` and ``60.0`` are one)."""
    if isinstance(value, list | tuple):
        return ",".join(_text(v) for v in value)
    if isinstance(value, bool):
        return "true" if value else "false"
    text = str(value).strip()
    if "," in text:
        return ",".join(_text(v) for v in text.split(","))
    try:
        number = float(text)
    except ValueError:
        return text
    return f"{number:.12g}" if math.isfinite(number) else text


def _run_folder(path: Path) -> Folder:
    header, records = read_records(path / RECORDS_FILE)
    actions = tuple(sorted(records[0].alphas)) if records else ()
    config = header["config"]
    rows = []
    for rec in records:
        for mode in config["modes"]:
            run = rec.runs.get(mode)
            if run is None:
                continue
            abandoned = any(o.outcome == "abandoned" for o in run.outcomes)
            rows.append({"cell": _cell_key({}), "label": header["scenario"], "subject": rec.subject,
                         "seed": header["seed"], "mode": mode, "cell_index": 0,
                         "status": "abandoned" if abandoned else "complete",
                         **unit_metrics(run, rec.rula_g, actions)})
    status = str(_manifest(path / "run.json").get("status", "unknown (no readable run.json)"))
    settings = {_cell_key({}): _settings(header["scenario"], config, config.get("overrides", {}))}
    return Folder(path, "run", tuple(rows), actions, DEFAULT_METRICS, status, settings)


def _sweep_folder(path: Path) -> Folder:
    from ergosim.sweep.tables import read_parquet  # noqa: PLC0415

    try:
        manifest = json.loads((path / "sweep.json").read_text(encoding="utf-8"))
        keys = [a["key"] for a in manifest["axes"]]
        table = read_parquet(path / "results.parquet")
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise ConfigError(f"cannot read the sweep folder: {err}", where=str(path)) from None
    factors = tuple(manifest.get("factors") or [{"name": k, "block": "grid", "keys": [k]} for k in keys])
    config = manifest.get("config") or {}
    fixed = manifest.get("fixed") or {}
    rows, settings = [], {}
    for r in table.to_pylist():
        params = {k: r[f"param.{k}"] for k in keys}
        label = ", ".join(f"{f['name']}={_fmt_param(r.get('param.' + f['name']))}" for f in factors) or "base"
        key = _cell_key(params)
        if key not in settings:
            settings[key] = _settings(manifest.get("scenario", "?"), config,
                                      {**fixed, **{k: _fmt_param(v) for k, v in params.items()}})
        rows.append({**r, "cell_index": r["cell"], "cell": key, "label": label})
    return Folder(path, "sweep", tuple(rows), tuple(manifest.get("actions", ())),
                  tuple(manifest.get("metrics", DEFAULT_METRICS)), str(manifest.get("status", "unknown")),
                  settings, factors)


def _fmt_param(v: Any) -> str:
    if isinstance(v, list | tuple):
        return ",".join(f"{x:g}" for x in v)
    return f"{v:g}" if isinstance(v, float) else str(v)


def select(folder: Folder, conditions: Sequence[str], where: str) -> Folder:
    """The cells of ``folder`` whose factors have the given levels: ``NAME=LEVEL`` (a factor: a zip's name
    or an axis key, its level as the tables show it), or ``cell=N`` (the cell's index); all must hold."""
    if not conditions:
        return folder
    rows = list(folder.rows)
    for cond in conditions:
        name, sep, value = cond.partition("=")
        name, value = name.strip(), value.strip()
        if not sep or not name:
            raise ConfigError(f"expected NAME=LEVEL (e.g. layout=B, takt=45, cell=3), got {cond!r}",
                              where=where)
        if name == "cell":
            rows = [r for r in rows if str(r["cell_index"]) == value]
        else:
            column = f"param.{name}"
            if folder.kind != "sweep" or not any(column in r for r in folder.rows):
                raise ConfigError(f"{folder.path} has no factor {name!r}; {_levels_text(folder)}",
                                  where=where)
            rows = [r for r in rows if _text(_fmt_param(r[column])) == _text(value)]
    if not rows:
        raise ConfigError(f"no cell of {folder.path} has {', '.join(conditions)}; {_levels_text(folder)}",
                          where=where)
    return dataclasses.replace(folder, rows=tuple(rows), selected=tuple(conditions))


def _levels_text(folder: Folder) -> str:
    if folder.kind != "sweep" or not folder.factors:
        return "a run folder is one cell"
    shown = []
    for f in folder.factors:
        levels = list(dict.fromkeys(_fmt_param(r.get(f"param.{f['name']}")) for r in folder.rows))
        shown.append(f"{f['name']}: {' | '.join(levels[:8])}" + (" | ..." if len(levels) > 8 else ""))
    return "its factors: " + "; ".join(shown)


def _selected_keys(folder: Folder) -> set[str]:
    """The axis keys a selection fixed (a zip's name fixes every key of the zip)."""
    keys = set()
    for cond in folder.selected:
        name = cond.partition("=")[0].strip()
        if name == "cell":
            return {k for f in folder.factors for k in f["keys"]}
        factor = next((f for f in folder.factors if f["name"] == name), None)
        keys.update(factor["keys"] if factor else [name])
    return keys


def _matched_cells(a: Folder, b: Folder) -> list[tuple[str, str, str]]:
    """(cell of a, cell of b, label) pairs to compare."""
    ca, cb = a.cells, b.cells
    if len(ca) == 1 or len(cb) == 1:  # one cell against one, or against each cell of the other side
        return [(ka, kb, la if la == lb else f"A {la}  vs  B {lb}")
                for ka, la in ca.items() for kb, lb in cb.items()]
    fixed = _selected_keys(a) | _selected_keys(b)

    def free(key: str) -> str:
        if not fixed:
            return key
        return _cell_key({k: v for k, v in json.loads(key).items() if k not in fixed})

    pairs = [(ka, kb, ca[ka] if ca[ka] == cb[kb] else f"A {ca[ka]}  vs  B {cb[kb]}")
             for ka in ca for kb in cb if free(ka) == free(kb)]
    if not pairs:
        raise ConfigError(f"the folders share no cell (no equal axis values); {a.path} has {len(ca)} "
                          f"cell(s), {b.path} {len(cb)}: choose cells with --a-cell / --b-cell NAME=LEVEL "
                          f"({_levels_text(a)})", where="ergosim compare")
    return pairs


def settings_difference(a: Folder, ka: str, b: Folder, kb: str) -> list[tuple[str, str, str]]:
    """(setting, value in A, value in B) of every setting that differs between cell ``ka`` of ``a`` and
    cell ``kb`` of ``b``. A workcell field overridden on one side only is read from the other side's
    workcell file; where that cannot be read it says "(the scenario's)"."""
    sa, sb = a.settings.get(ka, {}), b.settings.get(kb, {})
    out = []
    for key in sorted(set(sa) | set(sb), key=_setting_order):
        va, vb = _setting(sa, key), _setting(sb, key)
        if va != vb:
            out.append((key, va, vb))
    return out


def _setting(settings: Mapping[str, str], key: str) -> str:
    if key in settings:
        return settings[key]
    if "workcell" not in settings and key.startswith(("scene.", "workcell.")):
        value = _workcell_value(settings.get("scenario", ""), key.partition(".")[2])
        if value is not None:
            return value
    return "(the scenario's)"


@functools.lru_cache(maxsize=16)
def _workcell_value(scenario: str, path: str) -> str | None:
    """The value of the workcell field ``path`` (a dotted path or an alias) in ``scenario``'s own workcell
    file, as a setting string; None where it cannot be read."""
    from ergosim.errors import ErgosimError  # noqa: PLC0415
    from ergosim.experiment.scenario import load_scenario  # noqa: PLC0415

    try:
        doc = load_scenario(scenario).cell_doc
    except (ErgosimError, OSError):
        return None
    target = (doc.get("aliases") or {}).get(path, path)
    node: Any = doc
    for part in (target if isinstance(target, str) else target[0]).split("."):
        if isinstance(node, dict) and part in node:
            node = node[part]
        elif isinstance(node, list):  # [[parts.P.slots]]: a slot by its name
            node = next((x for x in node if isinstance(x, dict) and x.get("name") == part), None)
        else:
            return None
    return None if node is None or isinstance(node, dict | list) and not _flat_list(node) else _text(node)


def _flat_list(value: Any) -> bool:
    return isinstance(value, list) and all(isinstance(v, int | float) for v in value)


def _setting_order(key: str) -> tuple[int, str]:
    return ("." in key or key in ("task", "workcell"), key)


def compare_folders(a: Folder, b: Folder, metrics: Sequence[str] | None = None) -> list[dict[str, Any]]:
    """One row per (matched cell, mode in both, metric): the means of A and B with their CIs, the
    difference B − A with its CI and test, and the settings that differ between the two cells."""
    actions = tuple(dict.fromkeys((*a.actions, *b.actions)))
    metrics = tuple(metrics or dict.fromkeys((*a.metrics, *b.metrics)))
    for m in metrics:
        check_metric(m, actions, where="--metric")
    out = []
    for ka, kb, label in _matched_cells(a, b):
        ra = [r for r in a.rows if r["cell"] == ka]
        rb = [r for r in b.rows if r["cell"] == kb]
        differ = settings_difference(a, ka, b, kb)
        for mode in [m for m in dict.fromkeys(r["mode"] for r in ra) if any(r["mode"] == m for r in rb)]:
            for m in metrics:
                xa = {(r["subject"], r["seed"]): r for r in counted(ra, m) if r["mode"] == mode}
                xb = {(r["subject"], r["seed"]): r for r in counted(rb, m) if r["mode"] == mode}
                common = sorted(set(xa) & set(xb))
                va, vb = [r.get(m) for r in xa.values()], [r.get(m) for r in xb.values()]
                row = {"cell": label, "mode": mode, "metric": m, "a": metric_ci(list(xa.values()), m),
                       "b": metric_ci(list(xb.values()), m), "settings": differ}
                if len(common) >= 2:
                    d = paired_difference([xa[k].get(m) for k in common], [xb[k].get(m) for k in common], m)
                    row.update(test="wilcoxon", n=d["pairs"], diff=d["diff"], ci_low=d["diff_ci_low"],
                               ci_high=d["diff_ci_high"], statistic=d["wilcoxon_statistic"],
                               p=d["wilcoxon_p"], min_p=d["wilcoxon_min_p"])
                else:
                    d = unpaired_difference(va, vb, m)
                    row.update(test="mann-whitney", n=d["n_a"] + d["n_b"], diff=d["diff"],
                               ci_low=d["diff_ci_low"], ci_high=d["diff_ci_high"],
                               statistic=d["mannwhitney_u"], p=d["mannwhitney_p"], min_p=None)
                out.append(row)
    if not out:
        raise ConfigError("the folders share no mode in their matched cells", where="ergosim compare")
    return out


def _num(x: float | None, width: int = 9) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-".rjust(width)
    return f"{x:.4g}".rjust(width)


def _ci(lo: float | None, hi: float | None) -> str:
    return f"[{interval_text(lo, hi)}]"


def comparison_text(a: Folder, b: Folder, rows: Sequence[dict[str, Any]]) -> str:
    lines = [f"A: {a.describe()}", f"B: {b.describe()}",
             "difference B − A with its 95 % CI; paired (Wilcoxon signed-rank) where the same subjects and "
             "seeds are in both, else Welch / Mann-Whitney U; only completed units count"]
    cell, floors = None, []
    for r in rows:
        if r["cell"] != cell:
            cell = r["cell"]
            lines.append(f"\n{cell}")
            if r["settings"]:
                lines.append("  settings that differ (A -> B): " + "; ".join(
                    f"{k} {va} -> {vb}" for k, va, vb in r["settings"]))
            else:
                lines.append("  settings that differ: none (the same settings: any difference is the seeds' "
                             "or the code's)")
            lines.append(f"  {'mode':<8} {'metric':<22} {'A mean':>9} {'B mean':>9} {'B − A':>9} "
                         f"{'95 % CI':>22} {'test':>12} {'n':>4} {'p':>9}")
        floor = r.get("min_p")
        note = ""
        if r["test"] == "wilcoxon" and floor is not None and 0.05 <= floor < 1:
            note = f"  (p ≥ {floor:.2g} at n={r['n']})"
            floors.append(r["n"])
        lines.append(f"  {r['mode']:<8} {r['metric']:<22} {_num(r['a']['mean'])} {_num(r['b']['mean'])} "
                     f"{_num(r['diff'])} {_ci(r['ci_low'], r['ci_high']):>22} {r['test']:>12} {r['n']:>4} "
                     f"{_num(r['p'])}{note}")
    if floors:
        n = max(floors)
        lines.append(f"\n(p ≥ ...): with n={n} paired differences a Wilcoxon signed-rank test cannot give p "
                     f"below 2/2^n = {2 / 2**n:.3g}: it cannot show a difference at 0.05 whatever the data; "
                     f"{SMALL_N} or more subjects can")
    return "\n".join(lines)

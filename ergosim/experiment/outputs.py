"""The files of a run folder, listed once: what ``ergosim run`` writes, ``ergosim merge`` joins and a sweep
gathers per unit.

Each :class:`Output` names a file (or a family of files), the function that writes it from what the run
produced (:class:`Products`), whether it is rewritten after every finished subject (``each``) or once at the
end, and how a merge makes it from shards when it cannot be computed again from the subject records
(``merge``: the lines of the shards' files joined, or the files copied). An output whose rows describe one
subject's run in one mode may give a ``unit_table``: a sweep keeps those rows in every unit's document and
gathers them into ``<name>.parquet`` (:mod:`ergosim.sweep.tables`). A new output format is one entry of
:data:`OUTPUTS`; the run folder's list of names it owns (:data:`~ergosim.experiment.run_folder.
OUTPUT_PATTERNS`) follows from it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ergosim.atomic import atomic_open, write_bytes, write_json
from ergosim.errors import ConfigError
from ergosim.experiment.csv_files import (
    write_action_traces,
    write_allocations,
    write_decisions,
    write_failures,
    write_subjects,
    write_ticks,
)
from ergosim.experiment.kwear_state import state_document
from ergosim.experiment.report import REPORT_FILE, STILL_FILE, write_report
from ergosim.experiment.subject_records import RECORDS_FILE, RunRecord, SubjectRecord, write_records

__all__ = ["Output", "UnitTable", "Products", "OUTPUTS", "output", "write_outputs", "merge_outputs"]


@dataclasses.dataclass(frozen=True)
class Products:
    """What a run folder's files are written from. ``config``: the protocol as recorded
    (:meth:`~ergosim.experiment.protocol.ScenarioConfig.record`); ``records``: the subject records, in subject
    order; ``summary``: the summary.json document; ``team``: team.json's, or None; ``results``: the
    subjects' full results (per-tick logs, KWear traces), empty in a merge; ``plot_subjects``: the subjects
    the figures show (None: all); ``plots``: False writes no figures (``ergosim run --no-plots``);
    ``still``: the workcell's still as PNG bytes (cell.png; b"": none)."""

    scenario: str
    seed: int
    config: Mapping[str, Any]
    records: tuple[SubjectRecord, ...]
    subject_range: tuple[int, int]
    summary: dict
    team: dict | None = None
    results: tuple = ()
    plot_subjects: tuple[int, ...] | None = None
    plots: bool = True
    still: bytes = b""

    def runs_by_mode(self) -> list[tuple[str, RunRecord]]:
        """(worker name, run record) of every run: mode by mode in the protocol's order, then subject."""
        return [(r.name, r.runs[m]) for m in self.config["modes"] for r in self.records if m in r.runs]

    def runs_by_subject(self) -> list[RunRecord]:
        """Every run record: subject by subject, then mode in the protocol's order."""
        return [r.runs[m] for r in self.records for m in self.config["modes"] if m in r.runs]


Writer = Callable[[Path, Products], None]
Merger = Callable[[Path, Products, Sequence[Path]], None]
"""(the merged folder, the merged products, the shards' folders in subject order) -> None."""


@dataclasses.dataclass(frozen=True)
class UnitTable:
    """An output's rows for one sweep unit (one subject in one mode): ``columns`` (name, Arrow type alias:
    ``int32``, ``float64``, ``string``) and ``rows(run)`` of a :class:`RunRecord`, values JSON-ready."""

    columns: tuple[tuple[str, str], ...]
    rows: Callable[[RunRecord], list[list[Any]]]


@dataclasses.dataclass(frozen=True)
class Output:
    """One file of a run folder. ``files``: its name, or glob patterns for a family of files; ``write``
    writes it from :class:`Products`; ``each``: rewritten after every finished subject, not only at the
    end; ``merge``: how a merge makes it from the shards (None: ``write`` from the joined records);
    ``unit_table``: its rows in a sweep unit, or None."""

    name: str
    files: tuple[str, ...]
    write: Writer
    each: bool = False
    merge: Merger | None = None
    unit_table: UnitTable | None = None


# -- writers -----------------------------------------------------------------------------------------------
def _allocations(out: Path, p: Products) -> None:
    write_allocations(out / "allocations.csv", [a for run in p.runs_by_subject() for a in run.allocations])


def _decisions(out: Path, p: Products) -> None:
    modes = p.config["modes"]
    write_decisions(out / "decisions.csv", [r.runs[m] for r in p.results for m in modes if m in r.runs])


def _failures(out: Path, p: Products) -> None:
    write_failures(out / "failures.csv", [f for run in p.runs_by_subject() for f in run.failures])


def _records(out: Path, p: Products) -> None:
    write_records(out / RECORDS_FILE, scenario=p.scenario, seed=p.seed, config=p.config,
                  subject_range=p.subject_range, records=p.records)


def _team(out: Path, p: Products) -> None:
    if p.team is not None:
        write_json(out / "team.json", p.team)


def _ticks(out: Path, p: Products) -> None:
    write_ticks(out / "ticks.csv", [run for r in p.results for run in r.runs.values()])


def _states(out: Path, p: Products) -> None:
    """kwear_state_s<subject>_<mode>.json: the KWear state each run ended with
    (:mod:`ergosim.experiment.kwear_state`)."""
    cfg = p.config
    for r in p.results:
        for mode, run in r.runs.items():
            rows = run.ticks.rows
            doc = state_document(
                scenario=p.scenario, task=cfg["task"], seed=p.seed, subject=r.subject, worker=r.name,
                mode=mode,
                time_s=float(rows[-1, 1]) if len(rows) else 0.0,
                v=run.ticks.kwear[-1] if len(rows) else [0.0] * run.ticks.kwear.shape[1],
                alpha=r.alphas, kwear_params=r.kwear_params, gamma=cfg["gamma"], v_th=cfg["v_th"],
                robot_cost=cfg["robot_cost"])
            write_json(out / f"kwear_state_s{r.subject}_{mode}.json", doc)


def _subjects(out: Path, p: Products) -> None:
    write_subjects(out / "subjects.csv", p.runs_by_mode())


def _action_traces(out: Path, p: Products) -> None:
    write_action_traces(out / "kwear_actions.csv", [(r.subject, a, t, v) for r in p.results
                                                    for a, (t, v) in sorted(r.traces.items())])


def _plots(out: Path, p: Products) -> None:
    # drawn from the folder's own files (`ergosim plot` draws them again, or later after --no-plots)
    if p.plots and (out / "ticks.csv").is_file():
        from ergosim.experiment.plots import write_plots  # noqa: PLC0415 - matplotlib only where it draws

        write_plots(out, subjects=p.plot_subjects)


def _still(out: Path, p: Products) -> None:
    if p.still:
        write_bytes(out / STILL_FILE, p.still)


def _summary(out: Path, p: Products) -> None:
    write_json(out / "summary.json", p.summary)


def _report(out: Path, p: Products) -> None:
    write_report(out)  # from the folder's files, summary.json among them (``ergosim report DIR`` the same)


# -- how a merge makes what the records cannot give ----------------------------------------------------------
def _joined(name: str, by_mode: bool = False) -> Merger:
    """Join ``name`` of the shards (in subject order): every shard's lines, or with ``by_mode`` the lines of
    each mode (the second column) in turn, as ticks.csv orders mode, then subject."""

    def merge(out: Path, p: Products, shards: Sequence[Path]) -> None:
        paths = [s / name for s in shards]
        if not all(f.is_file() for f in paths):
            return
        header = _header(paths, name)
        with atomic_open(out / name, "w") as dst:
            dst.write(header)
            for group in sorted(p.config["modes"]) if by_mode else [None]:
                for f in paths:
                    with f.open(encoding="utf-8", newline="") as src:
                        next(src)
                        for line in src:
                            if group is None or line.split(",", 2)[1] == group:
                                dst.write(line)

    return merge


def _header(paths: Sequence[Path], name: str) -> str:
    headers = []
    for f in paths:
        with f.open(encoding="utf-8") as src:
            headers.append(src.readline())
    if len(set(headers)) != 1:
        raise ConfigError(f"{name} columns differ between shards", where=str(paths[0].parent))
    return headers[0]


def _copied(pattern: str) -> Merger:
    """Copy every file matching ``pattern`` of every shard."""

    def merge(out: Path, p: Products, shards: Sequence[Path]) -> None:
        for shard in shards:
            for f in sorted(shard.glob(pattern)):
                write_bytes(out / f.name, f.read_bytes())

    return merge


# -- the list ----------------------------------------------------------------------------------------------
_ATTEMPT_COLUMNS = (("repetition", "int32"), ("order", "int32"), ("action", "string"), ("agent", "string"),
                    ("status", "string"), ("attempt", "int32"), ("forced", "string"), ("t_start", "float64"),
                    ("t_end", "float64"), ("human_cost", "float64"), ("robot_cost", "float64"))
"""A sweep unit's attempts (allocations.parquet after the unit's own columns)."""

_FAILURE_COLUMNS = (("time", "float64"), ("repetition", "int32"), ("action", "string"), ("agent", "string"),
                    ("status", "string"), ("message", "string"))
"""A sweep unit's failed attempts and abandoned repetitions, each with its message (failures.parquet)."""

OUTPUTS: tuple[Output, ...] = (
    Output("allocations", ("allocations.csv",), _allocations, each=True,
           unit_table=UnitTable(_ATTEMPT_COLUMNS, lambda run: [[getattr(a, c) for c, _ in _ATTEMPT_COLUMNS]
                                                               for a in run.allocations])),
    Output("failures", ("failures.csv",), _failures, each=True,
           unit_table=UnitTable(_FAILURE_COLUMNS, lambda run: [[getattr(f, c) for c, _ in _FAILURE_COLUMNS]
                                                               for f in run.failures])),
    Output("subject_records", (RECORDS_FILE,), _records, each=True),
    Output("team", ("team.json",), _team, each=True),
    Output("ticks", ("ticks.csv",), _ticks, merge=_joined("ticks.csv", by_mode=True)),
    Output("kwear_state", ("kwear_state_*.json",), _states, merge=_copied("kwear_state_s*_*.json")),
    Output("subjects", ("subjects.csv",), _subjects),
    Output("kwear_actions", ("kwear_actions.csv",), _action_traces, merge=_joined("kwear_actions.csv")),
    Output("decisions", ("decisions.csv",), _decisions, merge=_joined("decisions.csv")),
    Output("plots", ("kwear_*.png", "kwear_timeline_*.png", "allocation_histogram.png"), _plots),
    Output("still", (STILL_FILE,), _still, merge=_copied(STILL_FILE)),
    Output("summary", ("summary.json",), _summary, each=True),
    Output("report", (REPORT_FILE,), _report),
)
"""Every file of a run folder, in the order written (summary.json next to last: a reader that finds it finds
the rest of that state of the run; report.html, last, is drawn from them all)."""


def output(name: str) -> Output:
    """The entry of :data:`OUTPUTS` called ``name``."""
    try:
        return next(o for o in OUTPUTS if o.name == name)
    except StopIteration:
        raise KeyError(f"no output {name!r}; outputs: {', '.join(o.name for o in OUTPUTS)}") from None


def write_outputs(out: Path, products: Products, *, final: bool, skip: tuple[str, ...] = ()) -> None:
    """Write the outputs of a run into ``out``: those rewritten after every subject, and with ``final`` every
    one; but those named in ``skip`` (a run writes its summary apart, once its status is final)."""
    for o in OUTPUTS:
        if (final or o.each) and o.name not in skip:
            o.write(out, products)


def merge_outputs(out: Path, products: Products, shards: Sequence[Path]) -> None:
    """Write every output of the merged run into ``out``: from the joined records, or from the shards'
    files (``shards`` in subject order) where an output has a ``merge``."""
    for o in OUTPUTS:
        if o.merge is not None:
            o.merge(out, products, shards)
        else:
            o.write(out, products)

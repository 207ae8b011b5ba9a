"""Run a sweep: plan its units, skip the finished ones, run the rest on an executor, keep every result.

Each finished unit is written to its own file the moment it arrives (:mod:`ergosim.sweep.folder`); the
tables, statistics and figures are consolidated from those files at the end, and also at least every
:data:`CONSOLIDATE_EVERY` seconds while the sweep runs, so ``results.parquet`` can be read mid-sweep.
Ctrl-C or SIGTERM stop the sweep as they stop a run: the tables of the units finished so far are
written, the manifest says ``interrupted`` and a re-run resumes. A failed unit is recorded with its
error and the sweep goes on.
"""

from __future__ import annotations

import dataclasses
import logging
import os
import sys
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from tqdm import tqdm

from ergosim.experiment.interrupt import interrupt_on_signals, stop_reason
from ergosim.sweep.executors import make_executor
from ergosim.sweep.folder import SweepFolder
from ergosim.sweep.plots import write_sweep_plots
from ergosim.sweep.stats import cell_statistics
from ergosim.sweep.tables import results_table, unit_rows_table, write_parquet
from ergosim.sweep.units import UNIT_OUTPUTS, Unit, plan_units

__all__ = ["SweepResult", "run_sweep", "CONSOLIDATE_EVERY", "EXIT_INCOMPLETE"]

log = logging.getLogger(__name__)

CONSOLIDATE_EVERY = 60.0
"""Seconds between consolidations of results.parquet while the sweep runs."""
EXIT_INCOMPLETE = 3
"""Exit status of ``ergosim sweep`` when every unit finished but some failed or were abandoned."""


@dataclasses.dataclass(frozen=True)
class SweepResult:
    """What a sweep did. ``skipped``: units found finished in the folder; ``ran``: units run now."""

    out: Path
    status: str
    units: int
    finished: int
    skipped: int
    ran: int
    failed: int
    abandoned: int
    cells_complete: int
    wall: float
    plots: tuple[str, ...]
    executor: Mapping[str, Any]


def _complete_cells(units: Sequence[Unit], docs: Mapping[str, dict]) -> set[int]:
    cells: dict[int, bool] = {}
    for u in units:
        cells[u.cell] = cells.get(u.cell, True) and u.id in docs
    return {c for c, done in cells.items() if done}


def _consolidate(sweep, folder: SweepFolder, units: Sequence[Unit], docs: Mapping[str, dict],
                 plots: bool) -> tuple[set[int], list[str]]:
    table = results_table(sweep, units, docs)
    write_parquet(folder.path / "results.parquet", table)
    for o in UNIT_OUTPUTS:
        write_parquet(folder.path / f"{o.name}.parquet", unit_rows_table(o, units, docs))
    complete = _complete_cells(units, docs)
    rows = table.to_pylist()
    write_parquet(folder.path / "cells.parquet", cell_statistics(sweep, rows, complete))
    names: list[str] = []
    if plots:
        names = write_sweep_plots(folder.path, sweep, [r for r in rows if r["cell"] in complete])
    return complete, names


def _manifest(sweep, status: str, reason: str, units, docs, skipped: int, ran: int, complete: set[int],
              executor: Mapping[str, Any], wall: float, plots: Sequence[str]) -> dict:
    done = [docs[u.id] for u in units if u.id in docs]
    return {
        "name": sweep.name, "source": sweep.source, "description": sweep.description,
        "scenario": sweep.scenario, "status": status, "reason": reason,
        "units": len(units), "units_finished": len(done),
        "units_failed": sum(d["status"] == "failed" for d in done),
        "units_abandoned": sum(d["status"] == "abandoned" for d in done),
        "units_skipped_at_start": skipped, "units_run": ran,
        "cells": len(sweep.cells), "cells_complete": len(complete),
        "axes": [{"key": a.key, "block": a.block, "values": list(a.values)} for a in sweep.axes],
        "fixed": dict(sweep.fixed), "subjects": list(sweep.subjects), "seeds": list(sweep.seeds),
        "modes": list(sweep.modes), "mode_slots": dict(sweep.slots), "metrics": list(sweep.metrics),
        "actions": list(sweep.actions),
        "sampling": dataclasses.asdict(sweep.sampling) if sweep.sampling else None,
        "executor": dict(executor), "wall_s": wall, "plots": list(plots),
    }


def run_sweep(sweep, out: str | Path, *, executor: str = "local", jobs: int | None = None,
              ray_address: str | None = None, progress: bool = True, retry_failed: bool = False,
              sweep_text: str | None = None) -> SweepResult:
    """Run ``sweep`` (a :class:`~ergosim.sweep.design.Sweep`) into the folder ``out``, resuming whatever
    is finished there. ``retry_failed``: run failed units again (e.g. after a crashed worker)."""
    folder = SweepFolder(out)
    folder.claim()
    start = time.monotonic()
    try:
        units = plan_units(sweep)
        docs = folder.finished(u.id for u in units)
        if retry_failed:
            docs = {k: d for k, d in docs.items() if d["status"] != "failed"}
        skipped = len(docs)
        # a unit shared by two cells (the same resolved scenario) runs once
        todo = list({u.id: u for u in units if u.id not in docs}.values())
        log.debug("%s: %d unit(s), %d finished in %s, %d to run", sweep.name, len(units), skipped, out,
                  len(todo))
        if sweep_text is not None:
            folder.write_sweep_file(sweep_text)
        described: dict[str, Any] = {"executor": executor}
        folder.write_manifest(_manifest(sweep, "running", "", units, docs, skipped, 0, set(), described, 0.0,
                                        []))
        status, reason, ran, plots, complete = "failed", "", 0, [], set()
        try:
            with interrupt_on_signals():
                if todo:
                    workers = min(jobs or os.cpu_count() or 1, len(todo)) if executor == "local" else jobs
                    with make_executor(executor, workers, ray_address) as ex:
                        described = ex.describe()
                        bar = tqdm(total=len(units), initial=skipped, desc=sweep.name, unit="unit",
                                   disable=not progress, file=sys.stderr, dynamic_ncols=True, smoothing=0.05,
                                   mininterval=0.5 if sys.stderr.isatty() else 15.0)
                        last = time.monotonic()
                        try:
                            tasks = ((sweep.scenarios[u.cell], u) for u in todo)
                            for doc in ex.imap(tasks, sweep.actions):
                                folder.write_unit(doc)
                                log.debug("unit %s (cell %d, subject %d, seed %d, %s): %s in %.1f s%s",
                                          doc["id"], doc["cell"], doc["subject"], doc["seed"], doc["mode"],
                                          doc["status"], doc["wall_s"], f": {doc['error']}" if doc["error"]
                                          else "")
                                docs[doc["id"]] = doc
                                ran += 1
                                bar.update(1)
                                if doc["status"] != "complete":
                                    bar.set_postfix_str(f"{_not_complete(docs)} failed or abandoned",
                                                        refresh=False)
                                if time.monotonic() - last > CONSOLIDATE_EVERY:
                                    _consolidate(sweep, folder, units, docs, plots=False)
                                    last = time.monotonic()
                        finally:
                            bar.close()
            status = "incomplete" if _not_complete(docs) else "complete"
        except BaseException as err:
            status, reason = stop_reason(err)
            raise
        finally:
            with interrupt_on_signals():  # a second Ctrl-C while writing still leaves whole files
                ended = status in ("complete", "incomplete")
                complete, plots = _consolidate(sweep, folder, units, docs, plots=ended)
                folder.write_manifest(_manifest(sweep, status, reason, units, docs, skipped, ran, complete,
                                                described, time.monotonic() - start, plots))
    finally:
        folder.close()
    done = [docs[u.id] for u in units if u.id in docs]
    return SweepResult(out=Path(out), status=status, units=len(units), finished=len(done), skipped=skipped,
                       ran=ran, failed=sum(d["status"] == "failed" for d in done),
                       abandoned=sum(d["status"] == "abandoned" for d in done), cells_complete=len(complete),
                       wall=time.monotonic() - start, plots=tuple(plots), executor=described)


def _not_complete(docs: Mapping[str, dict]) -> int:
    return sum(d["status"] != "complete" for d in docs.values())

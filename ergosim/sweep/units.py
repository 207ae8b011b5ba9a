"""Work units of a sweep: one (cell, subject, mode, seed) simulation each, identified by what determines it.

A unit runs :func:`~ergosim.experiment.runner.run_subject` for one subject and one mode, with the mode's
random stream of the whole run (its slot), so a unit equals that subject and mode in ``ergosim run`` of the
same cell. Its id is a hash of everything its result depends on (the resolved scenario: protocol, task,
workcell and overrides; subject, seed, mode, slot; the ergosim version and the code's fingerprint), so a
re-run over the same folder finds the units already done even after the sweep file grew, and never takes
a unit of another study, or of other code, for one of this. :func:`run_unit` never raises for a failed
simulation: the unit is returned with status ``failed`` and the error, and the sweep goes on.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import socket
import time
import traceback
from collections.abc import Sequence
from typing import Any

from ergosim import __version__
from ergosim.errors import ErgosimError
from ergosim.experiment.outputs import OUTPUTS
from ergosim.experiment.scenario import Scenario
from ergosim.experiment.subject_records import RunRecord
from ergosim.overrides import flat_values
from ergosim.plugins import import_extensions
from ergosim.sweep.fingerprint import code_fingerprint
from ergosim.sweep.metrics import unit_metrics

__all__ = ["Unit", "UNIT_FORMAT", "UNIT_STATUSES", "UNIT_OUTPUTS", "unit_scenario", "unit_id",
           "plan_units", "run_unit", "failed_document"]

UNIT_FORMAT = "ergosim-sweep-unit/1"
UNIT_STATUSES = ("complete", "abandoned", "failed")
"""``complete``: every repetition completed; ``abandoned``: the run ended but a repetition was abandoned
(no agent left able to finish it; the metrics are those of the run); ``failed``: the unit raised (a cell
certain to fail, a crash), its metrics are empty and ``error`` says why."""
UNIT_OUTPUTS = tuple(o for o in OUTPUTS if o.unit_table is not None)
"""The run outputs whose rows every unit's document keeps under the output's name, gathered into
``<name>.parquet`` (:mod:`ergosim.sweep.tables`)."""


@dataclasses.dataclass(frozen=True)
class Unit:
    """One work unit: cell index, subject index, population seed, mode, the mode's random stream and the
    fingerprint of the code that planned it (:func:`~ergosim.sweep.fingerprint.code_fingerprint`)."""

    id: str
    cell: int
    subject: int
    seed: int
    mode: str
    slot: int
    code: str = ""


def unit_scenario(scenario: Scenario, mode: str) -> Scenario:
    """``scenario`` as one unit runs it: one subject, one mode (neither changes the simulation)."""
    return dataclasses.replace(scenario, protocol=scenario.protocol.replace(subjects=1, modes=(mode,)))


def unit_id(scenario: Scenario, subject: int, seed: int, mode: str, slot: int) -> str:
    """16 hex digits of the SHA-256 of everything the unit's result depends on, the code included."""
    key = {
        "ergosim": __version__,
        "code": code_fingerprint(),
        "protocol": flat_values(unit_scenario(scenario, mode).protocol),
        "task": scenario.task_doc,
        "workcell": scenario.cell_doc,
        "overrides": dict(scenario.cell_overrides),
        "subject": subject, "seed": seed, "mode": mode, "slot": slot,
    }
    text = json.dumps(key, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def plan_units(sweep) -> list[Unit]:
    """Every unit of ``sweep`` in the order of its results: cell, seed, subject, mode."""
    units = []
    for cell, scenario in zip(sweep.cells, sweep.scenarios, strict=True):
        for seed in sweep.seeds:
            for subject in sweep.subjects:
                for mode in sweep.modes:
                    slot = sweep.slots[mode]
                    units.append(Unit(unit_id(scenario, subject, seed, mode, slot), cell.index, subject, seed,
                                      mode, slot, code_fingerprint()))
    return units


def run_unit(scenario: Scenario, unit: Unit, actions: Sequence[str],
             extensions: tuple[str, ...] = ()) -> dict[str, Any]:
    """Simulate ``unit`` of the cell ``scenario``; the unit's document (JSON-ready), failed or not.
    ``extensions``: the modules that registered modes, indices or kinds in the driver
    (:func:`ergosim.plugins.extension_modules`), imported first in a worker process."""
    from ergosim.experiment.runner import run_subject  # noqa: PLC0415
    from ergosim.experiment.scenario_check import check_reachability  # noqa: PLC0415
    from ergosim.scenes import build_cell  # noqa: PLC0415 - heavy imports stay in the worker

    start = time.perf_counter()
    doc = failed_document(unit, "")
    try:
        if unit.code and unit.code != code_fingerprint():
            raise ErgosimError(f"this worker runs other code (fingerprint {code_fingerprint()}) than the "
                               f"driver that planned the unit ({unit.code}); install the same ergosim and "
                               f"libraries on every node", where=socket.gethostname())
        import_extensions(extensions)
        sc = unit_scenario(scenario, unit.mode)
        check_reachability(sc, sc.task(), build_cell(sc.cell()))  # a cell certain to fail does not start
        result = run_subject(sc, unit.subject, unit.seed, (unit.mode,), slots=(unit.slot,))
        run = RunRecord.of(result.runs[unit.mode])
        doc["metrics"] = {k: _plain(v) for k, v in unit_metrics(run, result.rula_g, actions).items()}
        for o in UNIT_OUTPUTS:  # the rows of each output a unit keeps (allocations.csv's attempts, ...)
            doc[o.name] = [[_plain(v) for v in row] for row in o.unit_table.rows(run)]
        doc["status"] = "abandoned" if any(o.outcome == "abandoned" for o in run.outcomes) else "complete"
        if doc["status"] == "abandoned":
            doc["error"] = "; ".join(sorted({o.reason for o in run.outcomes if o.outcome == "abandoned"}))
    except ErgosimError as err:
        doc["error"] = str(err)
    except ImportError as err:  # an extension module this worker cannot import
        doc["error"] = f"{type(err).__name__}: {err} (install the module on every node that runs units)"
    except Exception as err:  # noqa: BLE001 - a crash in one unit is recorded, the sweep goes on
        where = traceback.extract_tb(err.__traceback__)[-1]
        doc["error"] = f"{type(err).__name__}: {err} ({os.path.basename(where.filename)}:{where.lineno})"
    doc["wall_s"] = time.perf_counter() - start
    doc["finished_at"] = time.time()  # wall clock [s since the epoch], for throughput; not in the tables
    doc["host"] = socket.gethostname()
    return doc


def failed_document(unit: Unit, error: str) -> dict[str, Any]:
    """The document of ``unit`` failed with ``error`` (also the start of every unit's document)."""
    return {"format": UNIT_FORMAT, **dataclasses.asdict(unit), "status": "failed", "error": error,
            "metrics": {}, **{o.name: [] for o in UNIT_OUTPUTS}, "wall_s": 0.0, "host": ""}


def _plain(value: Any) -> Any:
    """A JSON value: numpy scalars as Python ones, NaN and ±inf as None (a pruned row's costs)."""
    if hasattr(value, "item") and not isinstance(value, str):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value

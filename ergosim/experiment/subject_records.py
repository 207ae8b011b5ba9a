"""What a summary is computed from, kept exactly: per subject and mode, the attempts, failures, repetition
outcomes and load figures, without the per-tick arrays.

A run writes them to ``subject_records.json`` beside ``summary.json``; ``ergosim merge`` reads the records
of several shards (``ergosim run --subject-range A:B``) and recomputes the summary from them, so a merged
summary is the unsharded one byte for byte. A :class:`RunRecord` has the attributes of a
:class:`~ergosim.twin.records.SubjectRun` that :func:`~ergosim.experiment.summary.summarise` reads, so the
summary of a finished run and of its records is one computation. Floats are stored as JSON numbers, which
round-trip float64 exactly; NaN and ±inf (the costs of a pruned row) as the strings ``"nan"``, ``"inf"``
and ``"-inf"``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ergosim.atomic import write_json
from ergosim.errors import ConfigError
from ergosim.twin.records import Allocation, Failure, RepetitionOutcome, SubjectRun

__all__ = ["RunRecord", "SubjectRecord", "RECORDS_FILE", "RECORDS_FORMAT", "write_records", "read_records"]

RECORDS_FILE = "subject_records.json"
RECORDS_FORMAT = "ergosim-subject-records/1"
_TABLES = (("allocations", Allocation), ("failures", Failure), ("outcomes", RepetitionOutcome))
_FLOATS = ("kwear_integral", "kwear_integral_run", "kwear_mean", "time_above_threshold", "duration")


@dataclasses.dataclass(frozen=True)
class RunRecord:
    """One subject's run in one mode, as the summary sees it. Times [s]; KWear integrals [s]."""

    subject: int
    mode: str
    allocations: tuple[Allocation, ...]
    failures: tuple[Failure, ...]
    outcomes: tuple[RepetitionOutcome, ...]
    repetitions_completed: int
    takt_overruns: int
    kwear_integral: float
    kwear_integral_run: float
    kwear_mean: float
    time_above_threshold: float
    duration: float
    human: str = "human"
    """The task's name for the worker; every other agent of the records is a robot."""

    def by_robot(self, agent: str) -> bool:
        """``agent`` (of an allocation or a failure) is one of the robots (not the worker, not empty)."""
        return agent not in (self.human, "")

    @classmethod
    def of(cls, run: SubjectRun) -> RunRecord:
        return cls(subject=run.subject, mode=run.mode, allocations=tuple(run.allocations),
                   failures=tuple(run.failures), outcomes=tuple(run.outcomes),
                   repetitions_completed=run.repetitions_completed, takt_overruns=run.takt_overruns,
                   kwear_integral=run.kwear_integral, kwear_integral_run=run.kwear_integral_run,
                   kwear_mean=run.kwear_mean, time_above_threshold=run.time_above_threshold,
                   duration=run.duration, human=run.human)

    def to_dict(self) -> dict[str, Any]:
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        for key, kind in _TABLES:
            names = [f.name for f in dataclasses.fields(kind)]
            out[key] = {"columns": names, "rows": [[_enc(getattr(x, n)) for n in names] for x in out[key]]}
        for key in _FLOATS:
            out[key] = _enc(out[key])
        return out

    @classmethod
    def from_dict(cls, doc: Mapping[str, Any]) -> RunRecord:
        fields = dict(doc)
        for key, kind in _TABLES:
            table = fields[key]
            fields[key] = tuple(kind(**{n: _dec(v) for n, v in zip(table["columns"], row, strict=True)})
                                for row in table["rows"])
        for key in _FLOATS:
            fields[key] = float(_dec(fields[key]))
        return cls(**fields)


@dataclasses.dataclass(frozen=True)
class SubjectRecord:
    """One subject: its name, calibration figures (η, max error, G(a_k), α per action, the MTM-1 analysis of
    each action's first execution) and runs per mode."""

    subject: int
    name: str
    eta: Mapping[str, int]
    calibration_errors: Mapping[str, float]
    alphas: Mapping[str, list[float]]
    rula_g: Mapping[str, float]
    runs: Mapping[str, RunRecord]
    mtm: Mapping[str, str] = dataclasses.field(default_factory=dict)
    reba_g: Mapping[str, float] | None = None
    """G(a_k) on REBA per action, when a mode of the run reads REBA (recorded only then)."""

    @classmethod
    def of(cls, result) -> SubjectRecord:
        """The record of a :class:`~ergosim.experiment.subject.SubjectResult`."""
        return cls(subject=result.subject, name=result.name, eta=dict(result.eta),
                   calibration_errors=dict(result.calibration_errors), alphas=dict(result.alphas),
                   rula_g=dict(result.rula_g), runs={m: RunRecord.of(r) for m, r in result.runs.items()},
                   mtm=dict(result.mtm), reba_g=None if result.reba_g is None else dict(result.reba_g))

    def to_dict(self) -> dict[str, Any]:
        return {"subject": self.subject, "name": self.name, "eta": dict(self.eta),
                "calibration_errors": {k: _enc(v) for k, v in self.calibration_errors.items()},
                "alphas": {k: [_enc(x) for x in v] for k, v in self.alphas.items()},
                "rula_g": {k: _enc(v) for k, v in self.rula_g.items()},
                "runs": {m: r.to_dict() for m, r in self.runs.items()}, "mtm": dict(self.mtm),
                **({} if self.reba_g is None else {"reba_g": {k: _enc(v) for k, v in self.reba_g.items()}})}

    @classmethod
    def from_dict(cls, doc: Mapping[str, Any]) -> SubjectRecord:
        return cls(subject=int(doc["subject"]), name=str(doc["name"]), eta=dict(doc["eta"]),
                   calibration_errors={k: float(_dec(v)) for k, v in doc["calibration_errors"].items()},
                   alphas={k: [float(_dec(x)) for x in v] for k, v in doc["alphas"].items()},
                   rula_g={k: float(_dec(v)) for k, v in doc["rula_g"].items()},
                   runs={m: RunRecord.from_dict(r) for m, r in doc["runs"].items()},
                   mtm=dict(doc.get("mtm", {})),
                   reba_g={k: float(_dec(v)) for k, v in doc["reba_g"].items()} if "reba_g" in doc else None)


def _enc(value: Any) -> Any:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def _dec(value: Any) -> Any:
    if isinstance(value, str) and value in ("nan", "inf", "-inf"):
        return float(value)
    return value


def write_records(path: str | os.PathLike[str], *, scenario: str, seed: int, config: Mapping[str, Any],
                  subject_range: tuple[int, int], records: Sequence[SubjectRecord]) -> None:
    """``subject_records.json``: the run's identity (scenario, seed, protocol, the subjects it was asked to
    run, ``[first, end)``) and one record per finished subject, in subject order, atomically."""
    write_json(path, {
        "format": RECORDS_FORMAT,
        "scenario": scenario,
        "seed": seed,
        "config": dict(config),
        "subject_range": list(subject_range),
        "subjects": [r.to_dict() for r in sorted(records, key=lambda r: r.subject)],
    })


def read_records(path: str | os.PathLike[str]) -> tuple[dict[str, Any], list[SubjectRecord]]:
    """(the header: scenario, seed, config, subject_range; the subject records) of a records file."""
    path = Path(path)
    where = str(path)
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(f"no {RECORDS_FILE}: not a run folder written by ergosim run",
                          where=str(path.parent)) from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise ConfigError(f"cannot read the subject records: {err}", where=where) from None
    if not isinstance(doc, dict) or doc.get("format") != RECORDS_FORMAT:
        raise ConfigError(f"not a subject records file (expected format {RECORDS_FORMAT!r})", where=where)
    try:
        records = [SubjectRecord.from_dict(s) for s in doc["subjects"]]
        header = {k: doc[k] for k in ("scenario", "seed", "config", "subject_range")}
    except (KeyError, TypeError, ValueError) as err:
        raise ConfigError(f"damaged subject records ({type(err).__name__}: {err})", where=where) from None
    return header, records

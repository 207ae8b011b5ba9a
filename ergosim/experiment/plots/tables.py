"""The run's CSV files read back for the figures: every plot is drawn from the files it sits beside.

``ticks.csv`` (KWear per tick), ``allocations.csv`` (every attempt), ``subjects.csv`` (per subject and mode)
and ``kwear_actions.csv`` (each action from zero wear), plus the protocol in ``run.json`` (V_th, the modes).
"""

from __future__ import annotations

import csv
import dataclasses
import json
from collections import defaultdict
from pathlib import Path

import numpy as np

from ergosim.errors import ConfigError
from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.records import Allocation

__all__ = ["RunInfo", "TickTable", "Attempt", "SubjectRow", "read_run_info", "read_ticks", "read_attempts",
           "read_subjects", "read_action_traces"]

_KWEAR = tuple(f"kwear_{j}" for j in KWEAR_JOINTS)


@dataclasses.dataclass(frozen=True)
class RunInfo:
    """From ``run.json``: the scenario's name, the modes run (in order), V_th, takt [s], repetitions."""

    scenario: str
    modes: tuple[str, ...]
    v_th: float
    takt: float
    repetitions: int


@dataclasses.dataclass(frozen=True)
class TickTable:
    """One subject's run in one mode: ``t`` (n,) [s], ``repetition`` (n,), ``kwear`` (n, 5) in KWEAR_JOINTS
    order."""

    t: np.ndarray
    repetition: np.ndarray
    kwear: np.ndarray


_ATTEMPT_FIELDS = ("subject", "mode", "repetition", "order", "action", "agent", "t_start", "t_end", "status",
                   "allocatable")

Attempt = dataclasses.make_dataclass(
    "Attempt", [(f.name, f.type) for f in dataclasses.fields(Allocation) if f.name in _ATTEMPT_FIELDS]
    + [("robot", bool, dataclasses.field(default=False))],
    frozen=True, namespace={"done": property(lambda self: self.status == "done"), "__module__": __name__})
Attempt.__doc__ = """A row of ``allocations.csv`` read back: the columns the figures use, named and typed as
in :class:`~ergosim.twin.records.Allocation` (times [s]); ``done`` as there; ``robot``: a robot made the
attempt (its agent is neither the subject's worker, named in ``subjects.csv``, nor empty)."""


@dataclasses.dataclass(frozen=True)
class SubjectRow:
    """A row of ``subjects.csv`` (the figures the mode comparison draws)."""

    subject: int
    worker: str
    mode: str
    kwear_integral: float
    time_above_vth: float


def _open(path: Path):
    try:
        return path.open(encoding="utf-8", newline="")
    except FileNotFoundError:
        raise ConfigError(f"no {path.name} in {path.parent}: not the folder of a finished `ergosim run`",
                          where=str(path.parent)) from None


def read_run_info(out: Path) -> RunInfo:
    with _open(Path(out) / "run.json") as f:
        doc = json.load(f)
    cfg = doc.get("config", {})
    return RunInfo(scenario=str(doc.get("scenario", "")), modes=tuple(cfg.get("modes", ())),
                   v_th=float(cfg.get("v_th", np.nan)), takt=float(cfg.get("takt", np.nan)),
                   repetitions=int(cfg.get("repetitions", 0)))


def read_ticks(out: Path, subjects: tuple[int, ...] | None = None) -> dict[str, dict[int, TickTable]]:
    """Mode -> subject -> its ticks (only ``subjects``, when given), subjects in order; one pass over the
    file."""
    groups: dict[tuple[str, int], list[str]] = defaultdict(list)
    with _open(Path(out) / "ticks.csv") as f:
        header = f.readline().rstrip("\n").split(",")
        cols = [header.index(c) - 2 for c in ("repetition", "t", *_KWEAR)]
        for line in f:
            s, m, rest = line.split(",", 2)
            if subjects is None or int(s) in subjects:
                groups[(m, int(s))].append(rest)
    tables: dict[str, dict[int, TickTable]] = defaultdict(dict)
    for (m, s) in sorted(groups, key=lambda k: (k[0], k[1])):
        a = np.loadtxt(groups[(m, s)], delimiter=",", usecols=cols, ndmin=2)
        tables[m][s] = TickTable(t=a[:, 1], repetition=a[:, 0].astype(int), kwear=a[:, 2:])
    return dict(tables)


def read_attempts(out: Path) -> list[Attempt]:
    with _open(Path(out) / "subjects.csv") as f:
        worker = {(int(r["subject"]), r["mode"]): r.get("worker_agent") or "human" for r in csv.DictReader(f)}
    with _open(Path(out) / "allocations.csv") as f:
        return [Attempt(subject=int(r["subject"]), mode=r["mode"], repetition=int(r["repetition"]),
                        order=int(r["order"]), action=r["action"], agent=r["agent"],
                        t_start=float(r["t_start"]), t_end=float(r["t_end"]), status=r["status"],
                        allocatable=r["allocatable"] == "1",
                        robot=r["agent"] not in ("", worker.get((int(r["subject"]), r["mode"]), "human")))
                for r in csv.DictReader(f)]


def read_subjects(out: Path) -> list[SubjectRow]:
    with _open(Path(out) / "subjects.csv") as f:
        return [SubjectRow(subject=int(r["subject"]), worker=r["worker"], mode=r["mode"],
                           kwear_integral=float(r["kwear_integral"]),
                           time_above_vth=float(r["time_above_vth"]))
                for r in csv.DictReader(f)]


def read_action_traces(out: Path) -> dict[tuple[int, str], tuple[np.ndarray, np.ndarray]]:
    """(subject, action) -> (t (n,) [s], V (n, 5)), in file order."""
    groups: dict[tuple[int, str], list[str]] = defaultdict(list)
    with _open(Path(out) / "kwear_actions.csv") as f:
        f.readline()
        for line in f:
            s, action, rest = line.split(",", 2)
            groups[(int(s), action)].append(rest)
    out_ = {}
    for key, lines in groups.items():
        a = np.loadtxt(lines, delimiter=",", ndmin=2)
        out_[key] = (a[:, 0], a[:, 1:])
    return out_

"""What one simulated subject produces: allocation decisions and per-tick ergonomics.

These are plain data, filled by the loop (:mod:`ergosim.twin.loop`) and the session, and read by what is
made of a run (:mod:`ergosim.experiment`: summaries, files, recordings, videos); nothing here runs the
simulation.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ergosim.ergonomics.rula import RULA_PARTS
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS, STANCE
from ergosim.worker.motion import WORKER_MEASURES

__all__ = ["Allocation", "Failure", "RepetitionOutcome", "TickLog", "SubjectRun", "TICK_COLUMNS",
           "attempt_status"]


TICK_COLUMNS: tuple[str, ...] = (
    ("repetition", "t", "acting", "dropout")
    + ANGLE_NAMES
    + tuple(f"rula_{p}" for p in RULA_PARTS)
    + ("rula_grand",)
    + tuple(f"kwear_{j}" for j in KWEAR_JOINTS)
    + STANCE
    + WORKER_MEASURES
)
"""Columns of ``ticks.csv`` after ``subject`` and ``mode``; angles in degrees, t in seconds; then the
worker's true stance (where the feet stand [m], the turn [deg], knee flexion and ankle dorsiflexion [deg])
and how the posture stands: ``com_margin``, the centre of mass's distance inside the base of support [m],
and ``clearance``, the body's smallest distance to the furniture [m] (capped at 0.1; empty where the cell
has none)."""


@dataclasses.dataclass(frozen=True)
class Allocation:
    """One attempt at an action: who did it, what the planner saw, when (sim time [s]) and how it ended.

    ``status``: ``done`` (the scene saw the action completed), ``failed:<reason>`` (e.g.
    ``failed:unreachable``; the reason is the robot skill's or the worker's status), ``refused`` (the worker
    refused the assignment, negotiation; ``t_start`` = ``t_end`` = the decision) or ``pruned`` (a row
    written when a repetition is abandoned, for an action that every agent allowed to do it failed at;
    ``agent`` is then empty and the costs NaN). ``attempt``: 1 for the first attempt at ``action`` in
    this repetition, 2 for the next, whichever agent. ``forced``: the agent's name when the task and the
    mode let more than one agent do ``action`` but failures earlier in the repetition left only this one,
    else empty. ``allocatable``: the task lets more than one agent do ``action`` (the denominator of
    ``robot_share``).
    """

    subject: int
    mode: str
    repetition: int
    order: int
    action: str
    agent: str
    human_cost: float
    robot_cost: float
    t_start: float
    t_end: float
    had_choice: bool
    status: str = "done"
    attempt: int = 1
    forced: str = ""
    allocatable: bool = True

    @property
    def done(self) -> bool:
        return self.status == "done"


@dataclasses.dataclass(frozen=True)
class Failure:
    """One failed attempt (or an abandoned repetition, ``status`` ``abandoned``, ``action`` and ``agent``
    empty) at sim time ``time`` [s]; ``message`` says what went wrong, in words."""

    time: float
    subject: int
    mode: str
    repetition: int
    action: str
    agent: str
    status: str
    message: str

    def __str__(self) -> str:
        return self.message


@dataclasses.dataclass(frozen=True)
class RepetitionOutcome:
    """How one repetition ended: ``completed``, ``abandoned`` (no agent left able to finish the assembly;
    ``reason`` says why) or ``not_run`` (an earlier repetition of the run was abandoned). Times [s]."""

    subject: int
    mode: str
    repetition: int
    outcome: str
    reason: str = ""
    t_start: float = math.nan
    t_end: float = math.nan

    def to_dict(self) -> dict:
        finite = math.isfinite(self.t_start) and math.isfinite(self.t_end)
        return {"subject": self.subject, "repetition": self.repetition, "outcome": self.outcome,
                "reason": self.reason, "duration_s": (self.t_end - self.t_start) if finite else None}


class TickLog:
    """Preallocated per-tick buffers at the ergonomics rate; grows by doubling, never per tick.

    Row layout follows ``columns``: :data:`TICK_COLUMNS`, then the columns of any further posture feature
    (REBA's, with its ``kwear_legs``). ``kwear`` is (n, m), every ``kwear_*`` column (KWEAR_JOINTS first).
    """

    def __init__(self, columns: tuple[str, ...] = TICK_COLUMNS, capacity: int = 4096) -> None:
        self.columns = tuple(columns)
        self._data = np.full((max(capacity, 16), len(self.columns)), np.nan)
        self.n = 0
        self._kwear = [i for i, c in enumerate(self.columns) if c.startswith("kwear_")]

    def append(self, row: np.ndarray) -> None:
        if self.n == self._data.shape[0]:
            self._data = np.concatenate([self._data, np.full_like(self._data, np.nan)])
        self._data[self.n] = row
        self.n += 1

    @property
    def rows(self) -> np.ndarray:
        """(n, len(columns)) view of the filled rows."""
        return self._data[: self.n]

    def column(self, name: str) -> np.ndarray:
        return self.rows[:, self.columns.index(name)]

    @property
    def kwear(self) -> np.ndarray:
        if len(self._kwear) == len(KWEAR_JOINTS):  # the paper's five: a view
            return self.rows[:, self._kwear[0]: self._kwear[0] + len(KWEAR_JOINTS)]
        return self.rows[:, self._kwear]


@dataclasses.dataclass
class SubjectRun:
    """Everything one subject produced in one mode."""

    subject: int
    mode: str
    allocations: list[Allocation]
    ticks: TickLog
    repetitions_completed: int
    takt_overruns: int
    dt_tick: float
    v_th: float
    failures: list[Failure] = dataclasses.field(default_factory=list)
    """Every failed attempt and abandoned repetition, in time order."""
    outcomes: list[RepetitionOutcome] = dataclasses.field(default_factory=list)
    """One per repetition of the schedule, in order."""
    calibration_eta: dict[str, int] = dataclasses.field(default_factory=dict)
    decisions: list = dataclasses.field(default_factory=list)
    """The allocator's decisions (ergosim.twin.allocator.Decision), in order."""
    bodies: tuple[np.ndarray, np.ndarray] | None = None
    """When recorded: body positions (n, nbody, 3) [m] and quaternions (n, nbody, 4) wxyz per tick row."""
    horizon: float = math.inf
    """The production schedule [s]: repetitions × takt. The session runs at least this long (a worker who
    finishes early rests), so every mode covers the same window."""
    human: str = "human"
    """The task's name for the worker (its human agent); every other agent in the records is a robot."""
    robots: tuple[str, ...] = ()
    """The task's robot agents."""
    execution: str = "sequential"
    """How the team worked: ``sequential`` (one action at a time, the paper's) or ``parallel``."""
    offers: list = dataclasses.field(default_factory=list)
    """With negotiation: every action offered to the worker (ergosim.twin.negotiation.Offer), in order."""
    safety: object | None = None
    """With speed and separation monitoring: its figures (ergosim.twin.ssm_monitor.SafetyRecord)."""
    robot_spans: list = dataclasses.field(default_factory=list)
    """(robot, t_start, t_end, waited) [s] of every robot skill: dispatched, finished (home again), and the
    time it held a part out waiting for the worker."""

    def by_robot(self, agent: str) -> bool:
        """``agent`` (of an allocation or a failure) is one of the robots (not the worker, not empty)."""
        return agent not in (self.human, "")

    @property
    def kwear_integral(self) -> float:
        """Physical-load proxy: ∫_0^H Σ_i V_i dt [s] over the production schedule H = repetitions × takt,
        the same window in every mode (a mode whose repetitions overrun the takt is not credited for the
        rest it takes after H, nor charged for the wear)."""
        kw = self.ticks.kwear
        if not np.isfinite(self.horizon) or len(kw) == 0:
            return self.kwear_integral_run
        inside = self.ticks.column("t") <= self.horizon + 1e-9
        return float(kw[inside].sum() * self.dt_tick)

    @property
    def kwear_integral_run(self) -> float:
        """∫ Σ_i V_i dt over the whole run [s], however long its repetitions took."""
        return float(self.ticks.kwear.sum() * self.dt_tick)

    @property
    def kwear_mean(self) -> float:
        """Time-averaged Σ_i V_i over the whole run."""
        kw = self.ticks.kwear
        return float(kw.sum(axis=1).mean()) if len(kw) else 0.0

    @property
    def duration(self) -> float:
        """Simulated time of the run [s]."""
        return float(len(self.ticks.kwear) * self.dt_tick)

    @property
    def time_above_threshold(self) -> float:
        """Seconds during which at least one joint had V_i ≥ V_th."""
        return float((self.ticks.kwear >= self.v_th).any(axis=1).sum() * self.dt_tick)


def attempt_status(out) -> str:
    """An attempt's ``status`` in the allocation and failure rows from how it ended (an
    :class:`~ergosim.twin.session.Outcome`): ``done``, or ``failed:`` and the status word of the failure
    (``unreachable (12 cm short)`` -> ``failed:unreachable``)."""
    return "done" if out.ok else f"failed:{out.status.split(' ', 1)[0] or 'failed'}"

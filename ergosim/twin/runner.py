"""Run a scenario: per subject, calibrate in the workcell, then every mode's repetitions.

Subjects are independent jobs (``--jobs`` runs them in parallel processes). Every random draw of subject
i comes from ``SeedSequence([seed, i])``, so a parallel run equals the serial run bit for bit.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ergosim.ergonomics.kwear import kwear_trajectory
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.posture import KWEAR_JOINTS
from ergosim.scenes import Workcell, build_cell
from ergosim.twin.allocator import Allocator
from ergosim.twin.calibration import SceneCalibration
from ergosim.twin.loop import Plant
from ergosim.twin.modes import IndexContext, get_mode, get_risk_index
from ergosim.twin.records import SubjectRun
from ergosim.twin.robot_track import RobotTrack
from ergosim.twin.scenariofile import Scenario
from ergosim.twin.session import Session
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker.motion import Worker
from ergosim.worker.subjects import Subject, make_subjects

__all__ = ["SubjectResult", "Rig", "subject_cell", "build_rig", "make_allocator", "run_subject"]


@dataclasses.dataclass
class SubjectResult:
    """Runs per mode plus the subject's calibration figures."""

    subject: int
    name: str
    runs: dict[str, SubjectRun]
    eta: dict[str, int]
    calibration_errors: dict[str, float]
    alphas: dict[str, list[float]]
    rula_g: dict[str, float]
    traces: dict[str, tuple[np.ndarray, np.ndarray]] = dataclasses.field(default_factory=dict)
    """action -> (t (n,) [s], V (n, 5)): KWear from zero wear in the first calibration execution."""


@dataclasses.dataclass
class Rig:
    """Everything physical for one subject: workcell, plant, worker, robot (None in a cell without one)."""

    cell: Workcell
    plant: Plant
    worker: Worker
    robot: RobotTrack | None
    graph: object


def subject_cell(scenario: Scenario, subject: Subject) -> Workcell:
    """The scenario's workcell built for ``subject``'s body (the scenario's own overrides win)."""
    return build_cell(scenario.cell(**subject.workcell_fields))


def _subject_in(cell: Workcell, subject: Subject) -> Subject:
    """The subject acting with the workcell worker's dominant hand."""
    hand = cell.config.worker.hand
    return subject if subject.handedness == hand else dataclasses.replace(subject, handedness=hand)


def build_rig(scenario: Scenario, subject: Subject, rng: np.random.Generator, record_bodies: bool = False,
              alphas=None) -> Rig:
    cfg = scenario.protocol
    cell = subject_cell(scenario, subject)
    subject = _subject_in(cell, subject)
    track = WorkerTrack.for_subject(subject, rng, rate=cfg.mocap_rate, dropout_rate=cfg.dropout_rate,
                                    noise=cfg.noise_scale)
    kwear = KWearIndex(subject.kwear_params(), alphas or {}, online_weight=cfg.online_alpha_weight)
    plant = Plant(cell, track, kwear, mocap_rate=cfg.mocap_rate,
                  ergonomics_rate=cfg.ergonomics_rate, physics_dt=cfg.physics_dt, record_bodies=record_bodies)
    robot = RobotTrack(cell, ee_speed=cfg.ee_speed) if cell.robots else None
    plant.robot = robot
    return Rig(cell, plant, track.worker, robot, scenario.task())


def _calibrate(scenario: Scenario, subject: Subject, rng: np.random.Generator):
    """Calibrate ``subject`` in the scenario's workcell; also return the first pass's KWear traces."""
    cfg = scenario.protocol
    cell = subject_cell(scenario, subject)
    subject = _subject_in(cell, subject)
    cal = SceneCalibration.for_subject(cell, subject, rng, mocap_rate=cfg.mocap_rate,
                                       ergonomics_rate=cfg.ergonomics_rate, actions=scenario.task().actions,
                                       dropout_rate=cfg.dropout_rate, noise=cfg.noise_scale)
    params = subject.kwear_params()
    result = cal.run(params, eta0=cfg.eta0, eta_max=cfg.eta_max, v_des=cfg.v_des)
    traces = {}
    for action, ex in cal.passes[0].items():
        v = kwear_trajectory(np.zeros(len(KWEAR_JOINTS)), ex.g, ex.dt, params)
        traces[action] = (np.arange(1, len(v) + 1) * cal.dt_tick, v)
    return result, traces


def make_allocator(scenario: Scenario, mode_name: str, rig: Rig, calibration) -> Allocator:
    """The mode's risk index and cost rule (none for modes without one) on the rig's task graph."""
    cfg = scenario.protocol
    mode = get_mode(mode_name)
    index = cost = None
    if mode.risk_index is not None:
        index, cost = get_risk_index(mode.risk_index).build(IndexContext(cfg, rig.plant.kwear, calibration))
    return Allocator(rig.graph, mode, index=index, cost=cost, planner=cfg.planner)


def run_subject(scenario: Scenario, index: int, seed: int, modes: tuple[str, ...],
                record_mode: str | None = None, slots: tuple[int, ...] | None = None) -> SubjectResult:
    """Calibrate subject ``index`` of ``seed``'s population, then run each mode from zero wear.

    ``record_mode``: keep body poses per tick for that mode's run (for the rerun recording). ``slots``: the
    random stream of each mode, its position in the run's mode list (default ``0, 1, ...``): the
    calibration draws from child 0 of ``SeedSequence([seed, index])`` and mode slot k from child 1 + k,
    so one mode run alone with its slot (a sweep's work unit) equals that mode in the whole run."""
    cfg = scenario.protocol
    subject = make_subjects(index + 1, seed)[index]
    slots = tuple(range(len(modes))) if slots is None else tuple(slots)
    seqs = [np.random.SeedSequence([seed, index], spawn_key=(k,)) for k in (0, *(1 + s for s in slots))]
    calibration, traces = _calibrate(scenario, subject, np.random.default_rng(seqs[0]))
    runs: dict[str, SubjectRun] = {}
    for mode, seq in zip(modes, seqs[1:], strict=True):
        rng = np.random.default_rng(seq)
        rig = build_rig(scenario, subject, rng, record_bodies=mode == record_mode, alphas=calibration.alphas)
        allocator = make_allocator(scenario, mode, rig, calibration)
        session = Session(cfg=cfg, mode=mode, subject_index=index, worker=rig.worker, plant=rig.plant,
                          robot=rig.robot, allocator=allocator, rng=rng)
        runs[mode] = session.run(cfg.repetitions)
        runs[mode].calibration_eta = calibration.eta
    return SubjectResult(
        subject=index, name=subject.name, runs=runs, eta=calibration.eta,
        calibration_errors={a: float(c.max_error.max()) for a, c in calibration.actions.items()},
        alphas={a: [float(x) for x in c.alpha] for a, c in calibration.actions.items()},
        rula_g={a: float(c.rula_grand) for a, c in calibration.actions.items()},
        traces=traces,
    )

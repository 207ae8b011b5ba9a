"""Run a scenario: per subject, calibrate in the workcell, then every mode's repetitions.

Subjects are independent jobs (``--jobs`` runs them in parallel processes). Every random draw of subject
i comes from ``SeedSequence([seed, i])``, so a parallel run equals the serial run bit for bit.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np

from ergosim.ergonomics.kwear import KWearParams, kwear_trajectory
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.errors import ConfigError
from ergosim.experiment.scenario import Scenario
from ergosim.posture import KWEAR_JOINTS
from ergosim.scenes import Workcell, build_cell
from ergosim.twin.allocator import Allocator
from ergosim.twin.calibration import SceneCalibration
from ergosim.twin.durations import human_durations
from ergosim.twin.loop import Plant
from ergosim.twin.modes import IndexContext, get_mode, get_risk_index
from ergosim.twin.records import SubjectRun
from ergosim.twin.robot_track import RobotTrack
from ergosim.twin.session import Session
from ergosim.twin.team_setup import make_session
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker.motion import Worker
from ergosim.worker.subjects import Subject, make_subjects

__all__ = ["SubjectResult", "Rig", "scenario_subject", "subject_cell", "build_rig", "make_allocator",
           "subject_session", "run_subject"]

log = logging.getLogger(__name__)


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
    kwear_params: KWearParams = KWearParams()
    """The subject's KWear constants (C, r, ...; eq. 6-7)."""
    mtm: dict[str, str] = dataclasses.field(default_factory=dict)
    """action -> its MTM-1 analysis in the first calibration execution (ergosim.worker.action_timing)."""


@dataclasses.dataclass
class Rig:
    """Everything physical for one subject: workcell, plant, worker, the robots by name (none in a cell
    without one) and the task graph."""

    cell: Workcell
    plant: Plant
    worker: Worker
    robots: dict[str, RobotTrack]
    graph: object

    @property
    def robot(self) -> RobotTrack | None:
        """The cell's first robot, or None."""
        return next(iter(self.robots.values()), None)


def scenario_subject(scenario: Scenario, index: int, seed: int) -> Subject:
    """Subject ``index`` of ``seed``'s population, drawn as the scenario's protocol says (female fraction,
    pace); it depends only on (seed, index)."""
    people = scenario.protocol.population
    return make_subjects(index + 1, seed, female_fraction=people.female_fraction, pace=people.pace)[index]


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
    sensing = cfg.sensing
    cell = subject_cell(scenario, subject)
    subject = _subject_in(cell, subject)
    track = WorkerTrack.for_subject(subject, rng, rate=sensing.mocap_rate, dropout_rate=sensing.dropout_rate,
                                    noise=sensing.noise_scale)
    kwear = KWearIndex(subject.kwear_params(), alphas or {},
                       online_weight=cfg.calibration.online_alpha_weight)
    plant = Plant(cell, track, kwear, mocap_rate=sensing.mocap_rate,
                  ergonomics_rate=sensing.ergonomics_rate, physics_dt=sensing.physics_dt,
                  record_bodies=record_bodies)
    robots = {r: RobotTrack(cell, ee_speed=cfg.robot.ee_speed, transit_speed=cfg.robot.transit_speed, robot=r)
              for r in cell.robots}
    plant.robot = next(iter(robots.values()), None)
    return Rig(cell, plant, track.worker, robots, scenario.task())


def _calibrate(scenario: Scenario, subject: Subject, rng: np.random.Generator):
    """Calibrate ``subject`` in the scenario's workcell; also return the first pass's KWear traces and MTM-1
    analyses, and the mean duration of each action's executions [s] (the worker's expected durations)."""
    sensing, calibration = scenario.protocol.sensing, scenario.protocol.calibration
    cell = subject_cell(scenario, subject)
    subject = _subject_in(cell, subject)
    cal = SceneCalibration.for_subject(cell, subject, rng, mocap_rate=sensing.mocap_rate,
                                       ergonomics_rate=sensing.ergonomics_rate,
                                       actions=scenario.task().actions,
                                       dropout_rate=sensing.dropout_rate, noise=sensing.noise_scale)
    params = subject.kwear_params()
    result = cal.run(params, eta0=calibration.eta0, eta_max=calibration.eta_max, v_des=calibration.v_des)
    traces = {}
    for action, ex in cal.passes[0].items():
        v = kwear_trajectory(np.zeros(len(KWEAR_JOINTS)), ex.g, ex.dt, params)
        traces[action] = (np.arange(1, len(v) + 1) * cal.dt_tick, v)
    return result, traces, dict(cal.mtm), human_durations(cal.passes)


def make_allocator(scenario: Scenario, mode_name: str, rig: Rig, calibration) -> Allocator:
    """The mode's risk index and cost rule (none for modes without one) on the rig's task graph."""
    cfg = scenario.protocol
    mode = get_mode(mode_name)
    index = cost = None
    if mode.risk_index is not None:
        index, cost = get_risk_index(mode.risk_index).build(IndexContext(cfg, rig.plant.kwear, calibration))
    return Allocator(rig.graph, mode, index=index, cost=cost, planner=cfg.planner, tie=cfg.tie_break)


def _session(scenario: Scenario, index: int, subject: Subject, mode: str, rng: np.random.Generator,
             calibration, record_bodies: bool = False, seed: int = 0,
             human_seconds: dict[str, float] | None = None) -> Session:
    rig = build_rig(scenario, subject, rng, record_bodies=record_bodies,
                    alphas=calibration.alphas if calibration is not None else None)
    allocator = make_allocator(scenario, mode, rig, calibration)
    return make_session(scenario.protocol, rig=rig, allocator=allocator, mode=mode, subject=index, seed=seed,
                        rng=rng, human_seconds=human_seconds)


def subject_session(scenario: Scenario, index: int, seed: int, mode: str, *, calibrate: bool = True,
                    record_bodies: bool = False) -> Session:
    """A ready :class:`Session` of subject ``index`` of ``seed``'s population in ``mode``, for stepping by
    hand: ``session.run(n)`` repetitions, or ``session.perform(action, agent)`` one action at a time.

    ``calibrate``: calibrate the subject first (§5), as a run does; a mode without a risk index (``h-only``,
    ``r-only``) may skip it. Draws from ``SeedSequence([seed, index])`` like the subject's run, whose first
    mode it then equals."""
    mode_spec = get_mode(mode)
    if not calibrate and mode_spec.risk_index is not None:
        raise ConfigError(f"mode {mode!r} prices the worker with risk index {mode_spec.risk_index!r}, which "
                          "needs the subject's calibration: calibrate=True", where="subject_session")
    subject = scenario_subject(scenario, index, seed)
    seqs = np.random.SeedSequence([seed, index]).spawn(2)
    calibration = seconds = None
    if calibrate:
        calibration, _, _, seconds = _calibrate(scenario, subject, np.random.default_rng(seqs[0]))
    return _session(scenario, index, subject, mode, np.random.default_rng(seqs[1]), calibration,
                    record_bodies=record_bodies, seed=seed, human_seconds=seconds)


def run_subject(scenario: Scenario, index: int, seed: int, modes: tuple[str, ...],
                record_mode: str | tuple[str, ...] | None = None,
                slots: tuple[int, ...] | None = None) -> SubjectResult:
    """Calibrate subject ``index`` of ``seed``'s population, then run each mode from zero wear.

    ``record_mode``: keep body poses per tick for that mode's run, or those modes' runs (for the rerun
    recording and the video); copying the poses changes nothing in the simulation. ``slots``: the random
    stream of each mode, its position in the run's mode list (default ``0, 1, ...``): the calibration
    draws from child 0 of ``SeedSequence([seed, index])`` and mode slot k from child 1 + k, so one mode
    run alone with its slot (a sweep's work unit) equals that mode in the whole run."""
    cfg = scenario.protocol
    recorded = {record_mode} if isinstance(record_mode, str) else set(record_mode or ())
    subject = scenario_subject(scenario, index, seed)
    slots = tuple(range(len(modes))) if slots is None else tuple(slots)
    seqs = [np.random.SeedSequence([seed, index], spawn_key=(k,)) for k in (0, *(1 + s for s in slots))]
    calibration, traces, mtm, seconds = _calibrate(scenario, subject, np.random.default_rng(seqs[0]))
    log.debug("subject %d (%s): calibrated, η %s", index, subject.name, dict(calibration.eta))
    runs: dict[str, SubjectRun] = {}
    for mode, seq in zip(modes, seqs[1:], strict=True):
        session = _session(scenario, index, subject, mode, np.random.default_rng(seq), calibration,
                           record_bodies=mode in recorded, seed=seed, human_seconds=seconds)
        runs[mode] = session.run(cfg.pacing.repetitions)
        runs[mode].calibration_eta = calibration.eta
    return SubjectResult(
        subject=index, name=subject.name, runs=runs, eta=calibration.eta,
        calibration_errors={a: float(c.max_error.max()) for a, c in calibration.actions.items()},
        alphas={a: [float(x) for x in c.alpha] for a, c in calibration.actions.items()},
        rula_g={a: float(c.rula_grand) for a, c in calibration.actions.items()},
        traces=traces, kwear_params=subject.kwear_params(), mtm=mtm,
    )

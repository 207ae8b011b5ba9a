"""Run a scenario: per subject, calibrate in the workcell, then every mode's repetitions.

Subjects are independent jobs (``--jobs`` runs them in parallel processes). Every random draw of subject
i comes from ``SeedSequence([seed, i])``, so a parallel run equals the serial run bit for bit.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np

from ergosim.ergonomics.features import feature as feature_spec
from ergosim.ergonomics.kwear import KWearParams, kwear_trajectory
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.errors import ConfigError
from ergosim.experiment.robot_refusals import robot_refusals
from ergosim.experiment.scenario import Scenario
from ergosim.posture import KWEAR_JOINTS
from ergosim.scenes import Workcell, build_cell
from ergosim.twin.allocator import Allocator
from ergosim.twin.calibration import SceneCalibration
from ergosim.twin.durations import human_durations
from ergosim.twin.features import FeatureScorer, cell_hold
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
           "calibrate_subject", "subject_session", "run_subject"]

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
    reba_g: dict[str, float] | None = None
    """action -> G(a_k) on REBA (the REBA score held longest), when a mode of the run reads REBA."""


@dataclasses.dataclass
class Rig:
    """Everything physical for one subject: workcell, plant, worker, the robots by name (none in a cell
    without one) and the task graph."""

    cell: Workcell
    plant: Plant
    worker: Worker
    robots: dict[str, RobotTrack]
    graph: object
    refused: frozenset = frozenset()
    """(action, robot) pairs a robot of the cell cannot do
    (:func:`~ergosim.experiment.robot_refusals.robot_refusals`)."""

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


def scenario_features(scenario: Scenario) -> tuple[str, ...]:
    """The posture features the scenario's modes read: ``rula`` always, then e.g. ``reba``."""
    extra = [get_risk_index(m.risk_index).features for m in map(get_mode, scenario.protocol.modes)
             if m.risk_index is not None]
    return tuple(dict.fromkeys(("rula", *extra)))


def build_rig(scenario: Scenario, subject: Subject, rng: np.random.Generator, record_bodies: bool = False,
              alphas=None, feature: str = "rula") -> Rig:
    """The subject's cell, plant and robots; the worker's online KWear reads ``feature`` (``alphas``: its
    calibrated α per action on that feature); the worker's frames are scored with every feature the
    scenario's modes read."""
    cfg = scenario.protocol
    sensing = cfg.sensing
    cell = subject_cell(scenario, subject)
    subject = _subject_in(cell, subject)
    extra = [f for f in scenario_features(scenario) if f != "rula"]
    track = WorkerTrack.for_subject(subject, rng, rate=sensing.mocap_rate, dropout_rate=sensing.dropout_rate,
                                    noise=sensing.noise_scale,
                                    scorer=FeatureScorer(extra, cell_hold(cell)) if extra else None)
    kwear = KWearIndex(subject.kwear_params(), alphas or {},
                       online_weight=cfg.calibration.online_alpha_weight,
                       features=feature, joints=feature_spec(feature).joints)
    plant = Plant(cell, track, kwear, mocap_rate=sensing.mocap_rate,
                  ergonomics_rate=sensing.ergonomics_rate, physics_dt=sensing.physics_dt,
                  record_bodies=record_bodies)
    robots = {r: RobotTrack(cell, ee_speed=cfg.robot.ee_speed, transit_speed=cfg.robot.transit_speed, robot=r)
              for r in cell.robots}
    plant.robot = next(iter(robots.values()), None)
    graph = scenario.task()
    refused = frozenset(robot_refusals(graph, cell)) if robots else frozenset()
    return Rig(cell, plant, track.worker, robots, graph, refused)


def _calibrate(scenario: Scenario, subject: Subject, rng: np.random.Generator):
    """Calibrate ``subject`` in the scenario's workcell on every posture feature its modes read (feature ->
    Calibration, ``rula`` first); also return the first pass's KWear traces and MTM-1 analyses, and the mean
    duration of each action's executions [s] (the worker's expected durations), both from the RULA
    calibration's passes."""
    sensing, calibration = scenario.protocol.sensing, scenario.protocol.calibration
    cell = subject_cell(scenario, subject)
    subject = _subject_in(cell, subject)
    features = scenario_features(scenario)
    cal = SceneCalibration.for_subject(cell, subject, rng, mocap_rate=sensing.mocap_rate,
                                       ergonomics_rate=sensing.ergonomics_rate,
                                       actions=scenario.task().actions,
                                       dropout_rate=sensing.dropout_rate, noise=sensing.noise_scale,
                                       features=features)
    params = subject.kwear_params()
    eta = {"eta0": calibration.eta0, "eta_max": calibration.eta_max, "v_des": calibration.v_des}
    result = cal.run(params, **eta)
    passes = list(cal.passes)  # the paper's (RULA) passes: what the durations and traces come from
    others = {f: cal.run(params, **eta, feature=f)
              for f in features if f != "rula" and feature_spec(f).whole is not None}
    traces = {}
    for action, ex in passes[0].items():
        v = kwear_trajectory(np.zeros(len(KWEAR_JOINTS)), ex.g, ex.dt, params)
        traces[action] = (np.arange(1, len(v) + 1) * cal.dt_tick, v)
    return {"rula": result, **others}, traces, dict(cal.mtm), human_durations(passes)


def _feature_of(mode_name: str) -> str:
    """The posture feature the mode's online KWear (and its calibration) reads: its index's feature when
    that is a part score (``rula``, ``reba``); ``rula`` otherwise (an index on raw joint angles runs beside
    the paper's KWear, which stays what ticks.csv logs)."""
    mode = get_mode(mode_name)
    f = get_risk_index(mode.risk_index).features if mode.risk_index is not None else "rula"
    return f if feature_spec(f).whole is not None else "rula"


def make_allocator(scenario: Scenario, mode_name: str, rig: Rig, calibration) -> Allocator:
    """The mode's risk index and cost rule (none for modes without one) on the rig's task graph.
    ``calibration``: the subject's, per posture feature (a dict), or the paper's (RULA) alone."""
    cfg = scenario.protocol
    mode = get_mode(mode_name)
    index = cost = None
    if mode.risk_index is not None:
        entry = get_risk_index(mode.risk_index)
        cal = calibration.get(_feature_of(mode_name)) if isinstance(calibration, dict) else calibration
        index, cost = entry.build(IndexContext(cfg, rig.plant.kwear, cal))
        if index is not rig.plant.kwear:
            rig.plant.indices.append(index)  # a stateful index of its own is fed the plant's ticks too
    build = mode.allocator or Allocator
    order = {"tie": cfg.tie_break} if build is Allocator else {}  # the tie rule of Algorithm 1's dispatch
    return build(rig.graph, mode, index=index, cost=cost, planner=cfg.planner, refused=rig.refused, **order)


def _session(scenario: Scenario, index: int, subject: Subject, mode: str, rng: np.random.Generator,
             calibration, record_bodies: bool = False, seed: int = 0,
             human_seconds: dict[str, float] | None = None) -> Session:
    feature = _feature_of(mode)
    cal = calibration.get(feature) if isinstance(calibration, dict) else calibration
    rig = build_rig(scenario, subject, rng, record_bodies=record_bodies,
                    alphas=cal.alphas if cal is not None else None, feature=feature)
    allocator = make_allocator(scenario, mode, rig, calibration)
    return make_session(scenario.protocol, rig=rig, allocator=allocator, mode=mode, subject=index, seed=seed,
                        rng=rng, human_seconds=human_seconds)


def calibrate_subject(scenario: Scenario, index: int, seed: int, subject: Subject | None = None):
    """Subject ``index`` of ``seed``'s population calibrated in the scenario's workcell, as its run does
    (§5, from child 0 of ``SeedSequence([seed, index])``): (subject, calibration, the worker's expected
    seconds per action). ``subject``: that subject with some fields changed (a what-if, e.g. its
    trial-to-trial variability), calibrated on the same random stream; default the subject as drawn."""
    subject = scenario_subject(scenario, index, seed) if subject is None else subject
    rng = np.random.default_rng(np.random.SeedSequence([seed, index]).spawn(2)[0])
    calibration, _, _, seconds = _calibrate(scenario, subject, rng)
    return subject, calibration, seconds


def subject_session(scenario: Scenario, index: int, seed: int, mode: str, *, calibrate: bool = True,
                    record_bodies: bool = False, calibrated=None) -> Session:
    """A ready :class:`Session` of subject ``index`` of ``seed``'s population in ``mode``, for stepping by
    hand: ``session.run(n)`` repetitions, or ``session.perform(action, agent)`` one action at a time.

    ``calibrate``: calibrate the subject first (§5), as a run does; a mode without a risk index (``h-only``,
    ``r-only``) may skip it; ``calibrated``: what :func:`calibrate_subject` returned for the same subject
    (not calibrated again). Draws from ``SeedSequence([seed, index])`` like the subject's run, whose first
    mode it then equals."""
    mode_spec = get_mode(mode)
    if not calibrate and mode_spec.risk_index is not None:
        raise ConfigError(f"mode {mode!r} prices the worker with risk index {mode_spec.risk_index!r}, which "
                          "needs the subject's calibration: calibrate=True", where="subject_session")
    subject = scenario_subject(scenario, index, seed)
    seqs = np.random.SeedSequence([seed, index]).spawn(2)
    calibration = seconds = None
    if calibrated is not None:
        subject, calibration, seconds = calibrated
    elif calibrate:
        subject, calibration, seconds = calibrate_subject(scenario, index, seed)
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
    calibrations, traces, mtm, seconds = _calibrate(scenario, subject, np.random.default_rng(seqs[0]))
    log.debug("subject %d (%s): calibrated, η %s", index, subject.name, dict(calibrations["rula"].eta))
    runs: dict[str, SubjectRun] = {}
    for mode, seq in zip(modes, seqs[1:], strict=True):
        session = _session(scenario, index, subject, mode, np.random.default_rng(seq), calibrations,
                           record_bodies=mode in recorded, seed=seed, human_seconds=seconds)
        runs[mode] = session.run(cfg.pacing.repetitions)
        runs[mode].calibration_eta = calibrations[_feature_of(mode)].eta
    calibration = calibrations["rula"]
    reba = calibrations.get("reba")
    return SubjectResult(
        subject=index, name=subject.name, runs=runs, eta=calibration.eta,
        calibration_errors={a: float(c.max_error.max()) for a, c in calibration.actions.items()},
        alphas={a: [float(x) for x in c.alpha] for a, c in calibration.actions.items()},
        rula_g={a: float(c.rula_grand) for a, c in calibration.actions.items()},
        traces=traces, kwear_params=subject.kwear_params(), mtm=mtm,
        reba_g=None if reba is None else {a: float(c.rula_grand) for a, c in reba.actions.items()},
    )

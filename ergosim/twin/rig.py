"""One place that builds a session of the twin: the workcell, the worker, the robots, the allocator and the
robots' refusals, from a validated :class:`~ergosim.twin.protocol.SessionConfig` (dm_control's
``composer.Environment(task)``: one constructor; the caller only chooses what to build).

A :class:`RigSpec` says what to build: the session's config, the workcell for a subject's body, the task
graph and the posture features scored. The experiment makes one from a scenario
(:func:`ergosim.experiment.subject.rig_spec`); the Python API and the Gym environment use the same.

Random streams: the calibration draws from child 0 of ``SeedSequence([seed, index])`` and the session of
mode slot k from child 1 + k (:func:`streams`), so one mode run alone with its slot equals that mode in a
whole run.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from typing import NamedTuple

import numpy as np

from ergosim.ergonomics.calibration import Calibration
from ergosim.ergonomics.features import feature as feature_spec
from ergosim.ergonomics.kwear import KWearParams, kwear_trajectory
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.errors import ConfigError
from ergosim.planner import AndOrGraph
from ergosim.posture import KWEAR_JOINTS
from ergosim.scenes import Workcell
from ergosim.twin import robot_refusals as refusals
from ergosim.twin.allocator import Allocator
from ergosim.twin.calibration import SceneCalibration
from ergosim.twin.durations import human_durations
from ergosim.twin.features import FeatureScorer
from ergosim.twin.loop import Plant
from ergosim.twin.modes import IndexContext, get_mode, get_risk_index
from ergosim.twin.protocol import SessionConfig
from ergosim.twin.robot_track import RobotTrack
from ergosim.twin.session import Session
from ergosim.twin.team_setup import make_session
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker.motion import Worker
from ergosim.worker.subjects import Subject

__all__ = ["RigSpec", "Rig", "Calibrated", "streams", "feature_of", "build_rig", "calibrate",
           "make_allocator", "build_session", "calibrated", "ready_session"]


@dataclasses.dataclass(frozen=True)
class RigSpec:
    """What a session is built from. ``cell``: the workcell built for a subject's body; ``task``: a fresh
    task graph; ``features``: every posture feature the worker's frames are scored with (``rula`` first,
    then those the run's modes read, e.g. ``reba``)."""

    config: SessionConfig
    cell: Callable[[Subject], Workcell]
    task: Callable[[], AndOrGraph]
    features: tuple[str, ...] = ("rula",)


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
    (:func:`~ergosim.twin.robot_refusals.robot_refusals`)."""

    @property
    def robot(self) -> RobotTrack | None:
        """The cell's first robot, or None."""
        return next(iter(self.robots.values()), None)


class Calibrated(NamedTuple):
    """A subject's calibration (§5): per posture feature (``rula`` first), the first pass's KWear traces
    (action -> (t (n,) [s], V (n, 5))), its MTM-1 analyses and the worker's expected seconds per action."""

    calibrations: dict[str, Calibration]
    traces: dict[str, tuple[np.ndarray, np.ndarray]]
    mtm: dict[str, str]
    seconds: dict[str, float]


def streams(seed: int, index: int, slots: tuple[int, ...]) -> list[np.random.SeedSequence]:
    """The random streams of subject ``index`` of ``seed``: the calibration's, then mode slot k's."""
    return [np.random.SeedSequence([seed, index], spawn_key=(k,)) for k in (0, *(1 + s for s in slots))]


def _subject_in(cell: Workcell, subject: Subject) -> Subject:
    """The subject acting with the workcell worker's dominant hand."""
    hand = cell.config.worker.hand
    return subject if subject.handedness == hand else dataclasses.replace(subject, handedness=hand)


def _index_feature(mode_name: str) -> str:
    """The posture feature the mode's risk index reads (``rula`` for a mode without one)."""
    mode = get_mode(mode_name)
    return get_risk_index(mode.risk_index).features if mode.risk_index is not None else "rula"


def feature_of(mode_name: str) -> str:
    """The posture feature the mode's online KWear (and its calibration) reads: its index's feature when
    that extends the paper's five part scores (``rula``, ``reba``); ``rula`` otherwise (an index on another
    feature, e.g. raw joint angles, runs beside the paper's KWear, which stays what ticks.csv logs)."""
    f = _index_feature(mode_name)
    return f if feature_spec(f).extends_kwear else "rula"


def build_rig(spec: RigSpec, subject: Subject, rng: np.random.Generator, record_bodies: bool = False,
              alphas=None, feature: str = "rula") -> Rig:
    """The subject's cell, plant and robots; the worker's online KWear reads ``feature`` (``alphas``: its
    calibrated α per action on that feature); the worker's frames are scored with every feature of the
    spec."""
    cfg = spec.config
    sensing = cfg.sensing
    cell = spec.cell(subject)
    subject = _subject_in(cell, subject)
    track = WorkerTrack.for_subject(subject, rng, rate=sensing.mocap_rate, dropout_rate=sensing.dropout_rate,
                                    noise=sensing.noise_scale, scorer=FeatureScorer.of(spec.features, cell))
    kwear = KWearIndex(subject.kwear_params(), alphas or {},
                       online_weight=cfg.calibration.online_alpha_weight,
                       features=feature, joints=feature_spec(feature).joints)
    plant = Plant(cell, track, kwear, mocap_rate=sensing.mocap_rate,
                  ergonomics_rate=sensing.ergonomics_rate, physics_dt=sensing.physics_dt,
                  record_bodies=record_bodies)
    robots = {r: RobotTrack(cell, ee_speed=cfg.robot.ee_speed, transit_speed=cfg.robot.transit_speed, robot=r)
              for r in cell.robots}
    plant.robot = next(iter(robots.values()), None)
    graph = spec.task()
    refused = frozenset(refusals.robot_refusals(graph, cell)) if robots else frozenset()
    return Rig(cell, plant, track.worker, robots, graph, refused)


def calibrate(spec: RigSpec, subject: Subject, rng: np.random.Generator) -> Calibrated:
    """Calibrate ``subject`` in the spec's workcell on every posture feature of the spec that has a
    whole-body score; the traces, MTM-1 analyses and durations come from the RULA calibration's passes."""
    sensing, calibration = spec.config.sensing, spec.config.calibration
    cell = spec.cell(subject)
    subject = _subject_in(cell, subject)
    cal = SceneCalibration.for_subject(cell, subject, rng, mocap_rate=sensing.mocap_rate,
                                       ergonomics_rate=sensing.ergonomics_rate, actions=spec.task().actions,
                                       dropout_rate=sensing.dropout_rate, noise=sensing.noise_scale,
                                       features=spec.features)
    params: KWearParams = subject.kwear_params()
    eta = {"eta0": calibration.eta0, "eta_max": calibration.eta_max, "v_des": calibration.v_des}
    result = cal.run(params, **eta)
    passes = list(cal.passes)  # the paper's (RULA) passes: what the durations and traces come from
    others = {f: cal.run(params, **eta, feature=f)
              for f in spec.features if f != "rula" and feature_spec(f).whole is not None}
    traces = {}
    for action, ex in passes[0].items():
        v = kwear_trajectory(np.zeros(len(KWEAR_JOINTS)), ex.g, ex.dt, params)
        traces[action] = (np.arange(1, len(v) + 1) * cal.dt_tick, v)
    return Calibrated({"rula": result, **others}, traces, dict(cal.mtm), human_durations(passes))


def _on_feature(calibration, feature: str) -> Calibration | None:
    """The calibration on ``feature`` of a per-feature dict; a single (RULA) calibration or None as is."""
    return calibration.get(feature) if isinstance(calibration, Mapping) else calibration


def make_allocator(cfg: SessionConfig, mode_name: str, rig: Rig, calibration) -> Allocator:
    """The mode's risk index and cost rule (none for modes without one) on the rig's task graph.
    ``calibration``: the subject's, per posture feature (a dict), or the paper's (RULA) alone; the index is
    given the calibration on its own feature when there is one, else that of its online KWear."""
    mode = get_mode(mode_name)
    index = cost = None
    if mode.risk_index is not None:
        entry = get_risk_index(mode.risk_index)
        own = calibration.get(entry.features) if isinstance(calibration, Mapping) else None
        index, cost = entry.build(IndexContext(cfg, rig.plant.kwear,
                                               own or _on_feature(calibration, feature_of(mode_name))))
        if index is not rig.plant.kwear:
            rig.plant.indices.append(index)  # a stateful index of its own is fed the plant's ticks too
    build = mode.allocator or Allocator
    order = {"tie": cfg.tie_break} if build is Allocator else {}  # the tie rule of Algorithm 1's dispatch
    return build(rig.graph, mode, index=index, cost=cost, planner=cfg.planner, refused=rig.refused, **order)


def build_session(spec: RigSpec, subject: Subject, mode: str, rng: np.random.Generator, calibration, *,
                  index: int, seed: int = 0, record_bodies: bool = False,
                  human_seconds: dict[str, float] | None = None) -> Session:
    """The session of ``subject`` (``index`` of ``seed``'s population, for the records and negotiation's
    stream) in ``mode``: its rig, the mode's allocator on the calibration, the protocol's team settings."""
    feature = feature_of(mode)
    cal = _on_feature(calibration, feature)
    rig = build_rig(spec, subject, rng, record_bodies=record_bodies,
                    alphas=cal.alphas if cal is not None else None, feature=feature)
    allocator = make_allocator(spec.config, mode, rig, calibration)
    return make_session(spec.config, rig=rig, allocator=allocator, mode=mode, subject=index, seed=seed,
                        rng=rng, human_seconds=human_seconds)


def calibrated(spec: RigSpec, subject: Subject, index: int, seed: int) -> tuple[Subject, dict, dict]:
    """``subject`` (``index`` of ``seed``'s population) calibrated as its run does, on its calibration
    stream: (subject, calibration per feature, the worker's expected seconds per action)."""
    cal = calibrate(spec, subject, np.random.default_rng(streams(seed, index, ())[0]))
    return subject, cal.calibrations, cal.seconds


def ready_session(spec: RigSpec, subject: Subject, index: int, seed: int, mode: str, *,
                  calibrate: bool = True, record_bodies: bool = False, calibrated_as=None) -> Session:
    """A ready session of ``subject`` (``index`` of ``seed``'s population) in ``mode``, for stepping by
    hand, on the stream of mode slot 0: the subject's run's first mode. ``calibrate``: calibrate first
    (§5), as a run does; a mode without a risk index may skip it; ``calibrated_as``: what
    :func:`calibrated` returned for the same subject (not calibrated again)."""
    mode_spec = get_mode(mode)
    if not calibrate and mode_spec.risk_index is not None:
        raise ConfigError(f"mode {mode!r} prices the worker with risk index {mode_spec.risk_index!r}, which "
                          "needs the subject's calibration: calibrate=True", where="subject_session")
    calibration = seconds = None
    if calibrated_as is not None:
        subject, calibration, seconds = calibrated_as
    elif calibrate:
        subject, calibration, seconds = calibrated(spec, subject, index, seed)
    return build_session(spec, subject, mode, np.random.default_rng(streams(seed, index, (0,))[1]),
                         calibration, index=index, seed=seed, record_bodies=record_bodies,
                         human_seconds=seconds)

"""Run a scenario: per subject, calibrate in the workcell, then every mode's repetitions.

Subjects are independent jobs (``--jobs`` runs them in parallel processes). Every random draw of subject
i comes from ``SeedSequence([seed, i])``, so a parallel run equals the serial run bit for bit.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from ergosim.ergonomics.cost import CostParams, rula_baseline_params
from ergosim.ergonomics.kwear import kwear_trajectory
from ergosim.ergonomics.risk_index import KWearIndex, StaticRulaIndex
from ergosim.planner import corner_joint_task
from ergosim.posture import KWEAR_JOINTS
from ergosim.scenes import build_scene
from ergosim.twin.allocator import Allocator
from ergosim.twin.calibration import SceneCalibration
from ergosim.twin.loop import Plant
from ergosim.twin.records import SubjectRun
from ergosim.twin.robot_track import RobotTrack
from ergosim.twin.scenario import ScenarioConfig
from ergosim.twin.session import Session
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker.motion import Worker
from ergosim.worker.subjects import Subject, make_subjects

__all__ = ["SubjectResult", "Rig", "build_rig", "run_subject"]


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
    """Everything physical for one subject: workcell, plant, worker, robot."""

    cell: object
    plant: Plant
    worker: Worker
    robot: RobotTrack
    graph: object


def build_rig(cfg: ScenarioConfig, subject: Subject, rng: np.random.Generator,
              scene_overrides: Mapping[str, str], record_bodies: bool = False,
              alphas: Mapping[str, np.ndarray] | None = None) -> Rig:
    cell = build_scene(cfg.scene, **{**subject.workcell_fields, **dict(scene_overrides)})
    track = WorkerTrack.for_subject(subject, rng, rate=cfg.mocap_rate, dropout_rate=cfg.dropout_rate,
                                    noise=cfg.noise_scale > 0)
    worker = track.worker
    kwear = KWearIndex(subject.kwear_params(), alphas or {}, online_weight=cfg.online_alpha_weight)
    plant = Plant(cell, track, kwear, mocap_rate=cfg.mocap_rate,
                  ergonomics_rate=cfg.ergonomics_rate, physics_dt=cfg.physics_dt, record_bodies=record_bodies)
    robot = RobotTrack(cell, ee_speed=cfg.ee_speed)
    plant.robot = robot
    return Rig(cell, plant, worker, robot, corner_joint_task(cfg.task))


def _calibrate(cfg: ScenarioConfig, subject: Subject, rng: np.random.Generator,
               scene_overrides: Mapping[str, str]):
    """Calibrate ``subject`` in the scenario's workcell; also return the first pass's KWear traces."""
    cal = SceneCalibration.for_subject(cfg.scene, subject, rng, mocap_rate=cfg.mocap_rate,
                                       ergonomics_rate=cfg.ergonomics_rate,
                                       actions=corner_joint_task(cfg.task).actions,
                                       dropout_rate=cfg.dropout_rate, noise=cfg.noise_scale > 0,
                                       scene_overrides=scene_overrides)
    params = subject.kwear_params()
    result = cal.run(params, eta0=cfg.eta0, eta_max=cfg.eta_max, v_des=cfg.v_des)
    traces = {}
    for action, ex in cal.passes[0].items():
        v = kwear_trajectory(np.zeros(len(KWEAR_JOINTS)), ex.g, ex.dt, params)
        traces[action] = (np.arange(1, len(v) + 1) * cal.dt_tick, v)
    return result, traces


def make_allocator(cfg: ScenarioConfig, mode: str, rig: Rig, calibration) -> Allocator:
    """KWear (hrc) or static RULA (rula) costs; single-agent modes need no index."""
    if mode == "hrc":
        index = rig.plant.kwear
        cost = CostParams(gamma=cfg.gamma, v_th=cfg.v_th, robot_cost=cfg.robot_cost,
                          v_max=rig.plant.kwear.params.v_max)
    elif mode == "rula":
        index = StaticRulaIndex(calibration.rula_scores, g_max=cfg.rula_g_max)
        cost = rula_baseline_params(cfg.robot_cost, cfg.gamma, g_th=cfg.rula_threshold, g_max=cfg.rula_g_max)
    else:
        index, cost = None, None
    return Allocator(rig.graph, mode, index=index, cost=cost, planner=cfg.planner)


def run_subject(cfg: ScenarioConfig, index: int, seed: int, modes: tuple[str, ...],
                scene_overrides: Mapping[str, str] | None = None,
                record_mode: str | None = None) -> SubjectResult:
    """Calibrate subject ``index`` of ``seed``'s population, then run each mode from zero wear.

    ``record_mode``: keep body poses per tick for that mode's run (for the rerun recording)."""
    scene_overrides = dict(scene_overrides or {})
    subject = make_subjects(index + 1, seed)[index]
    seqs = np.random.SeedSequence([seed, index]).spawn(1 + len(modes))
    calibration, traces = _calibrate(cfg, subject, np.random.default_rng(seqs[0]), scene_overrides)
    runs: dict[str, SubjectRun] = {}
    for mode, seq in zip(modes, seqs[1:], strict=True):
        rng = np.random.default_rng(seq)
        rig = build_rig(cfg, subject, rng, scene_overrides, record_bodies=mode == record_mode,
                        alphas=calibration.alphas)
        allocator = make_allocator(cfg, mode, rig, calibration)
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

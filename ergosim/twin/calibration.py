"""Calibrating a subject in a scene (paper §5): recorded executions of every action, from zero wear.

A calibration pass is the worker doing the whole task alone, in the task's fixed order, in the subject's
workcell. Each action's motion is planned from the scene's current geometry and measured by the mocap
stream exactly as in the loop (noise, dropouts, RULA per frame); its G_i at the ergonomics rate is one
execution, whose coefficient is α = exp(-∫G/C), i.e. V after the action from zero wear (eq. 4, 9). The
part is then put where the action leaves it (placed on its target, or seated in its slot), so the next
action sees the right scene: postures depend on where things are, not on how the part got there, so the
passes skip the physics. Passes are recorded lazily, as many as the adaptive-η procedure of
:func:`ergosim.ergonomics.calibration.calibrate` asks for.

:func:`calibrate_subject` is the one call that does all of it for a subject in a named scene and stores
the result (α per action and joint, eq. 9; G(a_k); η) in a per-worker
:class:`~ergosim.ergonomics.param_store.ParamStore`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any

import mujoco
import numpy as np

from ergosim.ergonomics.calibration import Calibration, Execution, calibrate
from ergosim.ergonomics.kwear import KWearParams
from ergosim.ergonomics.param_store import ParamStore, WorkerParams
from ergosim.errors import ConfigError
from ergosim.scenes import build_scene
from ergosim.twin.features import FeatureScorer
from ergosim.twin.worker_track import WorkerTrack
from ergosim.worker.subjects import Subject

__all__ = ["SceneCalibration", "put_part", "calibrate_subject"]


def put_part(cell, part: str, pos: np.ndarray, quat: np.ndarray) -> None:
    """Set free body ``part`` at the world pose (pos (3,) [m], quat wxyz), at rest, and update kinematics."""
    m, d = cell.model, cell.data
    jnt = m.body_jntadr[m.body(part).id]
    qa, va = m.jnt_qposadr[jnt], m.jnt_dofadr[jnt]
    d.qpos[qa:qa + 3] = pos
    d.qpos[qa + 3:qa + 7] = quat
    d.qvel[va:va + 6] = 0.0
    mujoco.mj_kinematics(m, d)


class SceneCalibration:
    """Records calibration passes of ``actions`` (fixed order) for one worker in workcell ``cell``.

    ``tick_every``: mocap frames per ergonomics tick; ``dt_tick`` [s] the tick length.
    """

    def __init__(self, actions: Sequence[str], cell, track: WorkerTrack, rng: np.random.Generator,
                 tick_every: int, dt_tick: float) -> None:
        self.actions = tuple(actions)
        self.cell = cell
        self.track = track
        self.rng = rng
        self.tick_every = int(tick_every)
        self.dt_tick = float(dt_tick)
        self.passes: list[dict[str, Execution]] = []
        """Per pass, action -> its execution's RULA part scores (the paper's KWear inputs)."""
        self.feature_passes: list[dict[str, dict[str, Execution]]] = []
        """Per pass, feature -> action -> its execution on that feature (``rula``'s are :attr:`passes`)."""
        self.mtm: dict[str, str] = {}
        """action -> the MTM-1 analysis of its first recorded execution."""

    def _record_pass(self) -> None:
        cell, worker = self.cell, self.track.worker
        cell.reset_parts()
        by_feature: dict[str, dict[str, Execution]] = {}
        for action in self.actions:
            geom = cell.actions[action]
            motion = worker.plan(cell, geom, self.rng, action=action)
            self.mtm.setdefault(action, motion.mtm)
            seg = self.track.start_action(motion)
            ticks = np.arange(self.tick_every - 1, seg.n, self.tick_every)
            for feat, g in seg.g_by.items():
                whole = seg.whole_by.get(feat)
                by_feature.setdefault(feat, {})[action] = Execution(
                    g[ticks], self.dt_tick, None if whole is None else whole[ticks])
            pos, quat = cell.site_pose(geom.target)
            put_part(cell, geom.part, pos, quat)
            if geom.seats:
                cell.seat(geom.part)
            elif geom.received:
                cell.receive(geom.part, pos)
        cell.reset_parts()
        self.passes.append(by_feature["rula"])
        self.feature_passes.append(by_feature)

    def execute(self, action: str, l: int, feature: str = "rula") -> Execution:  # noqa: E741 - the paper's index
        """Execution ``l`` of ``action`` on posture feature ``feature`` (recorded when first asked for)."""
        while len(self.passes) <= l:
            self._record_pass()
        return self.feature_passes[l][feature][action]

    @classmethod
    def for_subject(cls, scene, subject: Subject, rng: np.random.Generator, *, mocap_rate: float,
                    ergonomics_rate: float, actions: Sequence[str] | None = None, dropout_rate: float = 0.0,
                    noise: bool | float = True, scene_overrides: Mapping[str, Any] | None = None,
                    features: Sequence[str] = ()) -> SceneCalibration:
        """The recorder for ``subject`` in workcell ``scene`` (a name or file, built for the subject's body as
        the twin builds it, ``scene_overrides`` winning; or an already built :class:`Workcell`), its mocap
        stream drawing from ``rng``. ``actions``: the order of a pass (default: the scene's); ``features``:
        posture features to record besides RULA's (``reba``)."""
        if isinstance(scene, str | os.PathLike):
            scene = build_scene(scene, **{**subject.workcell_fields, **dict(scene_overrides or {})})
        cell = scene
        track = WorkerTrack.for_subject(subject, rng, rate=mocap_rate, dropout_rate=dropout_rate, noise=noise,
                                        scorer=FeatureScorer.of(features, cell))
        tick_every = int(round(mocap_rate / ergonomics_rate))
        return cls(tuple(cell.actions) if actions is None else actions, cell, track, rng, tick_every,
                   tick_every * (1.0 / mocap_rate))

    def run(self, params: KWearParams, *, eta0: int, eta_max: int, v_des: float,
            feature: str = "rula") -> Calibration:
        """The adaptive-η calibration of every action (§5) on posture feature ``feature`` (``rula``: the
        paper's; ``reba``: REBA's six part scores, when the track scores them), sharing the recorded
        passes."""
        return calibrate(self.actions, lambda a, l: self.execute(a, l, feature), params, eta0=eta0,  # noqa: E741
                         eta_max=eta_max, v_des=v_des)


def _check_rates(mocap_rate: float, ergonomics_rate: float) -> None:
    ratio = mocap_rate / ergonomics_rate if mocap_rate > 0 and ergonomics_rate > 0 else 0.0
    if not (ratio >= 1 and abs(ratio - round(ratio)) < 1e-9):
        raise ConfigError(f"mocap_rate ({mocap_rate} Hz) must be a whole multiple of ergonomics_rate "
                          f"({ergonomics_rate} Hz)", where="calibrate_subject")


def calibrate_subject(scene: str, subject: Subject, *,
                      store: ParamStore | str | os.PathLike[str] | None = None, worker_id: str | None = None,
                      eta0: int = 2, eta_max: int = 10, v_des: float = 1e-3, seed: int = 0,
                      mocap_rate: float = 60.0, ergonomics_rate: float = 20.0, dropout_rate: float = 0.0,
                      **scene_overrides: Any) -> Calibration:
    """Calibrate ``subject`` in workcell ``scene`` (a registered scene name) and optionally store the result.

    The workcell is built for the subject's body, stature and segment scaling, as the twin builds it
    (``scene_overrides`` fix any layout field by name, these included). Every action of the scene is
    recorded from zero wear in the task's order, as many passes as the adaptive η asks for (paper §5):
    ``eta0`` >= 2 executions first, more while some |V̂ - V_l| >= ``v_des`` (Ṽ_des), at most ``eta_max``. The
    mocap stream runs at ``mocap_rate`` [Hz] with the subject's sensor noise and ``dropout_rate`` (per frame,
    as :class:`MocapStream`); G_i is sampled at ``ergonomics_rate`` [Hz], a whole divisor of the mocap rate.
    All randomness (posture and timing variability, sensor noise) comes from ``np.random.default_rng(seed)``.

    ``store``: a :class:`ParamStore` or its directory; if given, the subject's KWear constants, α_{k,i},
    G(a_k) and η are saved as worker ``worker_id`` (default ``subject.name``). Returns the
    :class:`~ergosim.ergonomics.calibration.Calibration` (per action: α, η, errors, converged).
    """
    _check_rates(mocap_rate, ergonomics_rate)
    wid = subject.name if worker_id is None else worker_id
    if store is not None:
        store = store if isinstance(store, ParamStore) else ParamStore(store)
        store.path(wid)  # a bad worker id fails before any motion is recorded
    rng = np.random.default_rng(seed)
    recorder = SceneCalibration.for_subject(scene, subject, rng, mocap_rate=mocap_rate,
                                            ergonomics_rate=ergonomics_rate, dropout_rate=dropout_rate,
                                            scene_overrides=scene_overrides)
    result = recorder.run(subject.kwear_params(), eta0=eta0, eta_max=eta_max, v_des=v_des)
    if store is not None:
        store.save(WorkerParams.from_calibration(wid, result))
    return result

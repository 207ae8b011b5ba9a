"""Calibrating a subject in a scene (paper §5): recorded executions of every action, from zero wear.

A calibration pass is the worker doing the whole task alone, in the task's fixed order, in the subject's
workcell. Each action's motion is planned from the scene's current geometry and measured by the mocap
stream exactly as in the loop (noise, dropouts, RULA per frame); its G_i at the ergonomics rate is one
execution, whose coefficient is α = exp(-∫G/C), i.e. V after the action from zero wear (eq. 4, 9). The
part is then put where the action leaves it (placed on its target, or seated in its hollow), so the next
action sees the right scene: postures depend on where things are, not on how the part got there, so the
passes skip the physics. Passes are recorded lazily, as many as the adaptive-η procedure of
:func:`ergosim.ergonomics.calibration.calibrate` asks for.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from ergosim.ergonomics.calibration import Calibration, Execution, calibrate
from ergosim.ergonomics.kwear import KWearParams
from ergosim.twin.worker_track import WorkerTrack

__all__ = ["SceneCalibration", "put_part"]


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

    def _record_pass(self) -> None:
        cell, worker = self.cell, self.track.worker
        cell.reset_parts()
        executions: dict[str, Execution] = {}
        for action in self.actions:
            geom = cell.actions[action]
            seg = self.track.start_action(worker.plan(cell, geom, self.rng, action=action))
            ticks = np.arange(self.tick_every - 1, seg.n, self.tick_every)
            executions[action] = Execution(seg.g[ticks], self.dt_tick, seg.grand[ticks])
            pos, quat = cell.site_pose(geom.target)
            put_part(cell, geom.part, pos, quat)
            if geom.kind == "insert":
                cell.seat(geom.part)
        cell.reset_parts()
        self.passes.append(executions)

    def execute(self, action: str, l: int) -> Execution:  # noqa: E741 - the paper's index
        while len(self.passes) <= l:
            self._record_pass()
        return self.passes[l][action]

    def run(self, params: KWearParams, *, eta0: int, eta_max: int, v_des: float) -> Calibration:
        return calibrate(self.actions, self.execute, params, eta0=eta0, eta_max=eta_max, v_des=v_des)

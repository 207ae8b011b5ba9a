"""The whole-body IK's own mink tasks: the gaze beyond what the eyes take, the comfort boxes, and the legs.

- :class:`GazeTask`: the head looks at a point. The eyes take the gaze within their preferred zone (the
  prior's ``eye_down_deg``, ``eye_up_deg``, ``eye_side_deg``: Hill & Kroemer 1986); what lies beyond is the
  task's error (yaw, pitch) [rad], which neck, trunk and knees share by their priors. Its weight falls off
  beyond :data:`GAZE_HUBER` (iteratively reweighted), so a target far to the side does not outweigh the
  hand. The error and its Jacobian are :func:`ergosim.worker.gaze.look_excess` and
  :func:`~ergosim.worker.gaze.gaze_jacobian`.
- :class:`ComfortTask`: a joint outside its comfort box [lo, hi] costs one unit per ``comfort_sigma_deg``
  beyond the edge (an almost straight elbow, a neck flexed past its comfort, trunk or neck extension).
- :class:`LegCoupling`: an equality constraint that keeps the pelvis and the left leg where the knee and
  the ankle put them (:mod:`ergosim.human.legs`), linearised at the current configuration.
"""

from __future__ import annotations

import math

import mink
import mujoco
import numpy as np

from ergosim.human.legs import Legs
from ergosim.worker.gaze import gaze_jacobian, look_excess

__all__ = ["GazeTask", "ComfortTask", "LegCoupling", "GAZE_HUBER"]

GAZE_HUBER = math.radians(10.0)
"""rad of gaze error beyond which its pull stays constant (a target behind the worker must not outweigh
the hand task while the body turns towards it)."""


class GazeTask(mink.Task):
    """The gaze excess beyond the eyes' zone (2,) [rad], weighted by ``1 / sigma`` [1/rad]."""

    def __init__(self, model: mujoco.MjModel, eye_site: int, sigma: float, side: float, down: float,
                 up: float) -> None:
        super().__init__(cost=np.full(2, 1.0 / sigma), gain=1.0, lm_damping=0.0)
        self.model, self.site = model, eye_site
        self.zone = (side, down, up)
        self.point = np.zeros(3)
        self.base_cost = 1.0 / sigma
        self._jp = np.zeros((3, model.nv))
        self._jr = np.zeros((3, model.nv))

    def look_at(self, point: np.ndarray) -> None:
        self.point = np.asarray(point, dtype=float)

    def _excess(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        pos, rot = data.site_xpos[self.site], data.site_xmat[self.site].reshape(3, 3)
        return look_excess(self.point, pos, rot, *self.zone)

    def compute_error(self, configuration: mink.Configuration) -> np.ndarray:
        _, excess = self._excess(configuration.data)
        # Huber reweighting: beyond GAZE_HUBER the residual's weight falls as 1/sqrt(|e|)
        self.cost = self.base_cost * np.sqrt(np.minimum(1.0, GAZE_HUBER / np.maximum(np.abs(excess), 1e-12)))
        return excess

    def compute_jacobian(self, configuration: mink.Configuration) -> np.ndarray:
        data = configuration.data
        v, excess = self._excess(data)
        mujoco.mj_jacSite(self.model, data, self._jp, self._jr, self.site)
        return gaze_jacobian(v, excess, data.site_xmat[self.site].reshape(3, 3), self._jp, self._jr)

    def cost_of(self, data: mujoco.MjData) -> float:
        """The task's squared weighted error at ``data`` (Huber: quadratic within, linear beyond)."""
        _, e = self._excess(data)
        a = np.abs(e)
        quad = np.where(a <= GAZE_HUBER, a * a, GAZE_HUBER * (2.0 * a - GAZE_HUBER))
        return float(self.base_cost ** 2 * quad.sum())


class ComfortTask(mink.Task):
    """One-sided: the excess of the joints ``dofs`` (qpos addresses ``qadr``) over [lo, hi] [rad]."""

    def __init__(self, nv: int, qadr: np.ndarray, dofs: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                 sigma: float) -> None:
        super().__init__(cost=np.full(len(dofs), 1.0 / sigma), gain=1.0, lm_damping=0.0)
        self.qadr, self.dofs, self.lo, self.hi = qadr, dofs, lo, hi
        self._jac = np.zeros((len(dofs), nv))

    def violation(self, qpos: np.ndarray) -> np.ndarray:
        q = qpos[self.qadr]
        return np.minimum(q - self.lo, 0.0) + np.maximum(q - self.hi, 0.0)

    def compute_error(self, configuration: mink.Configuration) -> np.ndarray:
        return self.violation(configuration.data.qpos)

    def compute_jacobian(self, configuration: mink.Configuration) -> np.ndarray:
        self._jac[:] = 0.0
        on = self.violation(configuration.data.qpos) != 0.0
        rows = np.flatnonzero(on)
        self._jac[rows, self.dofs[rows]] = 1.0
        return self._jac


class LegCoupling(mink.Task):
    """Equality constraint: the :data:`~ergosim.human.legs.DRIVEN` joints follow the knee and the ankle."""

    def __init__(self, model: mujoco.MjModel, legs: Legs) -> None:
        super().__init__(cost=np.ones(6), gain=1.0, lm_damping=0.0)
        self.legs = legs
        dof = {int(model.jnt_qposadr[j]): int(model.jnt_dofadr[j]) for j in range(model.njnt)}
        self.driven_dof = np.array([dof[a] for a in legs.driven_adr])
        self.knee_dof, self.ankle_dof = dof[legs.knee], dof[legs.ankle]
        self._jac = np.zeros((6, model.nv))
        self._jac[np.arange(6), self.driven_dof] = 1.0

    def _at(self, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.legs.driven(float(qpos[self.legs.knee]), float(qpos[self.legs.ankle]))

    def compute_error(self, configuration: mink.Configuration) -> np.ndarray:
        qpos = configuration.data.qpos
        values, _ = self._at(qpos)
        return qpos[self.legs.driven_adr] - values

    def compute_jacobian(self, configuration: mink.Configuration) -> np.ndarray:
        _, jac = self._at(configuration.data.qpos)
        self._jac[:, self.knee_dof] = -jac[:, 0]
        self._jac[:, self.ankle_dof] = -jac[:, 1]
        return self._jac

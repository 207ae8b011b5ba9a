"""The cost of one whole-body IK solve and its Levenberg-Marquardt descent (:mod:`ergosim.worker.ik`).

:class:`Problem` holds a solve's constants over its active joints in solver units (rad, m; the knee as the
pelvis drop): the priors (:mod:`ergosim.worker.ik_prior`) and the bounds, the standing area's included.
:class:`Task` adds the hand target and the gaze point and descends the cost from a start.
"""

from __future__ import annotations

import copy
import math
from typing import TYPE_CHECKING

import mujoco
import numpy as np

from ergosim.posture import HUMAN_JOINTS, STANCE
from ergosim.worker.gaze import gaze_jacobian, look_excess
from ergosim.worker.ik_prior import BODY, IKPrior
from ergosim.worker.stance import StandingArea

if TYPE_CHECKING:
    from ergosim.worker.ik import WholeBodyIK

__all__ = ["Problem", "Task", "log_so3"]

_IDX = {n: i for i, n in enumerate(BODY)}
_N = len(HUMAN_JOINTS)
_KNEE = _IDX["knee_flexion"]
_SLIDES = (_IDX["pelvis_x"], _IDX["pelvis_y"])
_TOL_COST = 1e-5  # converged when an iteration lowers the cost by less than this fraction
_LM_START, _LM_TRIES = 1e-4, 8  # Levenberg-Marquardt damping: first value, increases by 10 before giving up
_GAZE_HUBER = math.radians(10.0)  # beyond this the gaze error costs linearly: a target behind the worker
# must not outweigh the hand task while the body turns towards it


def log_so3(r: np.ndarray) -> np.ndarray:
    """Rotation vector (3,) [rad] of a 3x3 rotation matrix, angle in [0, pi]: through the unit quaternion
    (MuJoCo's ``mju_mat2Quat``, stable near pi) and its logarithm (``mju_quat2Vel``)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(r, dtype=float).reshape(9))
    vel = np.empty(3)
    mujoco.mju_quat2Vel(vel, quat, 1.0)
    return vel


class Problem:
    """One solve's constant data over the active variables, in solver units (rad, m, pelvis drop [m])."""

    def __init__(self, ik: WholeBodyIK, act: np.ndarray, prior: IKPrior, area: StandingArea,
                 q0_body: np.ndarray) -> None:
        legs = ik.human.legs
        scale = np.where((act == _SLIDES[0]) | (act == _SLIDES[1]), 1.0, np.pi / 180.0)
        knee = act == _KNEE
        self.pref = prior.pref[act] * scale
        sigma = prior.sigma[act] * scale
        self.lo = ik.lo[act].copy()
        self.hi = ik.hi[act].copy()
        bounds = area.bounds(q0_body[_N:])
        for k, name in enumerate(STANCE[:3]):
            where = np.flatnonzero(act == _IDX[name])
            if where.size:
                lo, hi = bounds[k]
                s = 1.0 if k < 2 else np.pi / 180.0
                self.lo[where] = max(self.lo[where][0], lo * s)
                self.hi[where] = min(self.hi[where][0], hi * s)
        if knee.any():  # the solver moves the pelvis drop: the knee's bounds as drops, its prior below
            self.lo[knee], self.hi[knee] = legs.drop(self.lo[knee]), legs.drop(self.hi[knee])
            self.knee_sigma2 = float(sigma[knee][0]) ** 2
            self.pref[knee], sigma[knee] = 0.0, np.inf
        self.legs = legs
        self.w2 = sigma ** -2.0
        self.lo_c = prior.comfort_lo[act] * scale
        self.hi_c = prior.comfort_hi[act] * scale
        self.wc2 = np.deg2rad(prior.comfort_sigma_deg) ** -2.0
        self.wg2 = np.deg2rad(prior.gaze_sigma_deg) ** -2.0
        self.eyes = tuple(np.deg2rad([prior.eye_side_deg, prior.eye_down_deg, prior.eye_up_deg]).tolist())
        self.knee = knee
        self.knee_at = int(np.flatnonzero(knee)[0]) if knee.any() else -1
        self.scale = scale

    def restricted(self, keep: np.ndarray) -> Problem:
        """This problem over the variables of the mask ``keep`` only (the numbers of a Problem built over
        them: every per-variable constant is computed element by element)."""
        out = copy.copy(self)
        for name in ("pref", "lo", "hi", "w2", "lo_c", "hi_c", "knee", "scale"):
            setattr(out, name, getattr(self, name)[keep])
        out.knee_at = int(np.flatnonzero(out.knee)[0]) if out.knee.any() else -1
        return out

    def violation(self, qa: np.ndarray) -> np.ndarray:
        """Signed excess over the comfort box (0 inside)."""
        return np.minimum(qa - self.lo_c, 0.0) + np.maximum(qa - self.hi_c, 0.0)

    def knee_terms(self, qa: np.ndarray) -> tuple[float, float, float]:
        """The knee prior (κ(d) / σ)^2, straight knees preferred, as a function of the pelvis drop d: (cost,
        gradient, curvature). With θ = κ / 2 = acos(1 - d / L): cost 4 θ^2 / σ^2, gradient
        8 θ / (σ^2 L sin θ), curvature 8 (sin θ - θ cos θ) / (σ^2 L^2 sin^3 θ); the slope with straight legs
        is finite (8 / (σ^2 L)), so the knees stay straight until bending them pays for itself."""
        if self.knee_at < 0:
            return 0.0, 0.0, 0.0
        length, s2 = self.legs.length, self.knee_sigma2
        theta = math.acos(min(max(1.0 - float(qa[self.knee_at]) / length, -1.0), 1.0))
        if theta < 1e-4:
            return 4.0 * theta * theta / s2, 8.0 / (s2 * length), 8.0 / (3.0 * s2 * length * length)
        sin, cos = math.sin(theta), math.cos(theta)
        return (4.0 * theta * theta / s2, 8.0 * theta / (s2 * length * sin),
                8.0 * (sin - theta * cos) / (s2 * length * length * sin ** 3))


class Task:
    """The cost of one solve and its descent: hand task, posture priors, gaze, knees (module docstring)."""

    def __init__(self, ik: WholeBodyIK, side: str, target: np.ndarray, target_rot: np.ndarray | None,
                 look: np.ndarray, act: np.ndarray, prob: Problem) -> None:
        self.ik, self.target, self.target_rot, self.look = ik, target, target_rot, look
        self.act, self.prob = act, prob
        data = ik.data
        self.site, self.eye_site = ik.human.hand_site[side], ik.human.eye_site
        self.xpos, self.xmat = data.site_xpos[self.site], data.site_xmat[self.site].reshape(3, 3)
        self.epos, self.emat = data.site_xpos[self.eye_site], data.site_xmat[self.eye_site].reshape(3, 3)
        self.dof, self.qadr = ik.dofadr[act], ik.qadr[act]
        n_task = 6 if target_rot is not None else 3
        self.wt = np.array([ik.s_pos ** -2.0] * 3 + [ik.s_rot ** -2.0] * 3)[:n_task]
        self.err = np.zeros(n_task)
        self.a = np.zeros((n_task, len(act)))
        self._v = np.zeros(3)  # the gaze direction at the last look (head frame)
        self._at: tuple = ()  # (q - pref, comfort violation, knee terms) at the last cost

    def _kinematics(self, qa: np.ndarray) -> None:
        data = self.ik.data
        data.qpos[self.qadr] = qa
        mujoco.mj_kinematics(self.ik.model, data)
        mujoco.mj_comPos(self.ik.model, data)

    def _look(self) -> np.ndarray:
        """Gaze excess at the current kinematics (positions only: no Jacobian, no mj_comPos needed)."""
        self._v, gex = look_excess(self.look, self.epos, self.emat, *self.prob.eyes)
        return gex

    def _gaze_jacobian(self, gex: np.ndarray) -> np.ndarray | None:
        """Jacobian of the last :meth:`_look`'s excess, None where the eyes take the whole gaze (a zero
        Jacobian, whose terms in the step are exact zeros and are skipped)."""
        if gex[0] == 0.0 and gex[1] == 0.0:
            return None
        ik = self.ik
        mujoco.mj_jacSite(ik.model, ik.data, ik._jep, ik._jer, self.eye_site)
        return gaze_jacobian(self._v, gex, self.emat, ik._jep[:, self.dof], ik._jer[:, self.dof])

    def _task(self) -> None:
        """The task error (target - hand; rotation vector) and its Jacobian at the current kinematics."""
        ik = self.ik
        mujoco.mj_jacSite(ik.model, ik.data, ik._jacp, ik._jacr, self.site)
        np.subtract(self.target, self.xpos, out=self.err[:3])
        np.take(ik._jacp, self.dof, axis=1, out=self.a[:3])
        if self.target_rot is not None:
            self.err[3:] = log_so3(self.target_rot @ self.xmat.T)
            np.take(ik._jacr, self.dof, axis=1, out=self.a[3:])

    def errors(self) -> tuple[float, float]:
        """(position error [m], rotation error [deg]) at the current kinematics."""
        pos = float(np.linalg.norm(self.xpos - self.target))
        rot = 0.0
        if self.target_rot is not None:
            rot = float(np.rad2deg(np.linalg.norm(log_so3(self.target_rot @ self.xmat.T))))
        return pos, rot

    def cost(self, qa: np.ndarray, gex: np.ndarray) -> float:
        """The whole cost at ``qa`` (the kinematics must be at ``qa``; ``gex`` its gaze excess). Keeps its
        posture terms for the step from ``qa`` (:meth:`descend`)."""
        prob = self.prob
        d = qa - prob.pref
        viol = prob.violation(qa)
        knee = prob.knee_terms(qa)
        self._at = (d, viol, knee)
        e = self.xpos - self.target
        task = self.wt[0] * float(e @ e)
        if self.target_rot is not None:
            r = log_so3(self.target_rot @ self.xmat.T)
            task += self.wt[3] * float(r @ r)
        return float(prob.w2 @ (d * d) + prob.wc2 * (viol @ viol) + prob.wg2 * _huber_sum(gex)
                     + knee[0] + task)

    def posture_cost(self, qa: np.ndarray) -> float:
        """The cost without the hand task, at ``qa`` (the kinematics must be at ``qa``)."""
        prob = self.prob
        d = qa - prob.pref
        viol = prob.violation(qa)
        return float(prob.w2 @ (d * d) + prob.wc2 * (viol @ viol) + prob.wg2 * _huber_sum(self._look())
                     + prob.knee_terms(qa)[0])

    def descend(self, q: np.ndarray, max_iter: int) -> tuple[np.ndarray, float, int]:
        """Gauss-Newton from ``q`` (solver units, full vector): (the end, its cost, iterations)."""
        prob, act = self.prob, self.act
        model, data = self.ik.model, self.ik.data
        qa = q[act].copy()
        self.ik._fk(q)
        gex = self._look()
        c0 = self.cost(qa, gex)
        n = len(act)
        damped = np.empty((n, n))
        damped_diag = damped.reshape(-1)[::n + 1]  # a view of its diagonal
        skip_gaze = math.isfinite(prob.wg2)  # a zero gaze Jacobian adds exact zeros (not NaN: 0 * inf)
        mu = _LM_START
        it = 0
        for it in range(1, max_iter + 1):
            # the line search below moves only the kinematics: the Jacobians at the accepted point here
            mujoco.mj_comPos(model, data)
            gjac = self._gaze_jacobian(gex)
            self._task()
            d, viol, (_, kg, kh) = self._at  # the last cost was at qa
            # accumulated in place in the order of diag + gaze + task; where the eyes take the gaze the
            # gaze products are exact zeros, added as such (the same bits, signed zeros included)
            hess = np.diag(prob.w2 + prob.wc2 * (viol != 0.0) + 0.5 * kh * prob.knee)
            grad = prob.w2 * d + prob.wc2 * viol
            if gjac is not None or not skip_gaze:
                gjac = np.zeros((2, n)) if gjac is None else gjac
                # Huber weights (iteratively reweighted): a large gaze error pulls with a bounded force
                wg = prob.wg2 * np.minimum(1.0, _GAZE_HUBER / np.maximum(np.abs(gex), 1e-12))
                hess += (gjac.T * wg) @ gjac
                grad += gjac.T @ (wg * gex)
            else:
                hess += 0.0
                grad += 0.0
            hess += (self.a.T * self.wt) @ self.a
            grad += 0.5 * kg * prob.knee
            grad -= self.a.T @ (self.wt * self.err)
            # Levenberg-Marquardt: a step that raises the cost is retried with more damping (towards a
            # scaled gradient step), a step that lowers it relaxes the damping
            scale = hess.diagonal().copy()
            for _ in range(_LM_TRIES):
                # hess + diag(mu scale): hess's off-diagonal entries are never -0, so adding zeros there is
                # the identity
                np.copyto(damped, hess)
                damped_diag += mu * scale
                step = _bounded_step(damped, grad, qa, prob.lo, prob.hi)
                q1 = qa + step
                data.qpos[self.qadr] = q1
                mujoco.mj_kinematics(model, data)
                gex = self._look()
                c1 = self.cost(q1, gex)
                if c1 < c0:
                    mu = max(mu * 0.1, _LM_START)
                    break
                mu *= 10.0
            if c1 >= c0:
                # no step lowers the cost: converged (a joint on the edge of its comfort box, where the
                # quadratic model switches on and off, would cycle about it), or at the best approach
                self._kinematics(qa)
                break
            qa, c0, fell = q1, c1, c0 - c1
            if np.abs(step).max() < 1e-4 or fell < _TOL_COST * (1.0 + c1):
                break
        out = q.copy()
        out[act] = qa
        return out, c0, it


def _huber_sum(e: np.ndarray) -> float:
    """Sum over the (2,) gaze excess of e^2 within :data:`_GAZE_HUBER`, growing linearly beyond (continuous
    with its slope)."""
    total = 0.0
    for x in e:
        a = abs(x)
        total += a * a if a <= _GAZE_HUBER else _GAZE_HUBER * (2.0 * a - _GAZE_HUBER)
    return total


def _bounded_step(hess: np.ndarray, grad: np.ndarray, qa: np.ndarray, lo: np.ndarray,
                  hi: np.ndarray) -> np.ndarray:
    """argmin 1/2 s^T H s + g^T s with variables pushed past [lo, hi] frozen there and the others re-solved
    (up to three rounds), scaled to at most 0.3 per variable and clipped into the bounds."""
    step = np.linalg.solve(hess, -grad)  # the first round, every variable free
    new = qa + step
    out = (new < lo) | (new > hi)
    if np.count_nonzero(out):
        step = _frozen_step(hess, grad, qa, lo, hi, new, out)
    step *= min(1.0, 0.3 / max(np.abs(step).max(), 1e-12))
    return np.minimum(np.maximum(qa + step, lo), hi) - qa


def _frozen_step(hess: np.ndarray, grad: np.ndarray, qa: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                 new: np.ndarray, out: np.ndarray) -> np.ndarray:
    """The rounds of :func:`_bounded_step` after the first: ``out`` frozen at the bounds ``new`` passed."""
    free = ~out
    fixed = np.zeros(len(grad))
    fixed[out] = (np.minimum(np.maximum(new, lo), hi) - qa)[out]
    step = fixed
    g = np.flatnonzero(out)
    for _ in range(3):
        f = np.flatnonzero(free)
        rows = f[:, None]  # hess[rows, g] is np.ix_(f, g)'s indexing
        rhs = -grad[f] - hess[rows, g] @ fixed[g]
        step = fixed.copy()
        step[f] = np.linalg.solve(hess[rows, f], rhs)
        new = qa + step
        out = free & ((new < lo) | (new > hi))
        if not np.count_nonzero(out):
            break
        fixed[out] = (np.minimum(np.maximum(new, lo), hi) - qa)[out]
        free &= ~out
        g = np.flatnonzero(~free)
    return step

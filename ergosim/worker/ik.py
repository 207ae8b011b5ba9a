"""Whole-body inverse kinematics of the kinematic human: stance, trunk, neck and one arm, with a gaze.

One hand's grasp site is driven to a target position (and optionally orientation) while the head looks at
a point, by sequential quadratic programming on a regularised least-squares problem:

    min_q  |p_hand(q) - p*|^2 / s_p^2 (+ |log(R* R_hand(q)^T)|^2 / s_R^2)
           + sum_j ((q_j - pref_j) / s_j)^2 + comfort-box excess^2 / s_c^2 + |gaze excess|^2 / s_g^2,
    q within its ranges and the standing area.

The hand task has tiny tolerances (s_p = 0.5 mm, s_R = 0.5 deg), so the posture priors
(:mod:`ergosim.worker.ik_prior`) and the gaze act in its null space; a target beyond reach ends at the best
approach. Each iteration is a Levenberg-Marquardt step on the cost. The gaze (:mod:`ergosim.worker.gaze`)
is what the eyes cannot take: the neck, the
trunk and the stance share it by their priors, so a target far to the side turns the head, then the trunk
and the body, and a near, low one flexes the neck. The stance (pelvis step and turn, knee flexion) moves
within the standing area it is given (:mod:`ergosim.worker.stance`); a planted area keeps the feet where they
are. The knees enter the solve through the pelvis height, whose Jacobian does not vanish with straight legs
(:mod:`ergosim.human.legs`).

Bodies are (26,) vectors in :data:`~ergosim.worker.ik_prior.BODY` order at the interface (degrees, metres
for the pelvis step); radians and the pelvis drop [m] inside.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import mujoco
import numpy as np

from ergosim.human.model import HumanModel
from ergosim.posture import ARM, HUMAN_JOINTS, NECK, STANCE, TRUNK
from ergosim.worker.gaze import gaze_excess
from ergosim.worker.ik_prior import BODY, IKPrior, default_prior
from ergosim.worker.stance import StandingArea

__all__ = ["IKSolution", "WholeBodyIK", "log_so3"]

_IDX = {n: i for i, n in enumerate(BODY)}
_N = len(HUMAN_JOINTS)
_KNEE = _IDX["knee_flexion"]
_SLIDES = (_IDX["pelvis_x"], _IDX["pelvis_y"])
_TOL_COST = 1e-5  # converged when an iteration lowers the cost by less than this fraction
_LM_START, _LM_TRIES = 1e-4, 8  # Levenberg-Marquardt damping: first value, increases by 10 before giving up
_REACH_RETRY = 0.005  # m: a free-stance solve this far from its target also starts from the planted one
_TURN_START = 45.0  # deg of a target's azimuth the head and eyes take before a solve starts turned
_GAZE_HUBER = math.radians(10.0)  # beyond this the gaze error costs linearly: a target behind the worker
# must not outweigh the hand task while the body turns towards it


class IKSolution(NamedTuple):
    """Result of one solve: (26,) body [deg, m], residual position error [m] and rotation error [deg],
    iterations, and the posture's cost (priors, gaze and knees: what the worker avoids, in units of one
    neutral-zone edge)."""

    body: np.ndarray
    pos_error: float
    rot_error_deg: float
    iterations: int
    cost: float = float("nan")

    @property
    def angles(self) -> np.ndarray:
        """(22,) posture angles [deg]."""
        return self.body[:_N]

    @property
    def stance(self) -> np.ndarray:
        """(4,) stance [m, m, deg, deg]."""
        return self.body[_N:]


def log_so3(r: np.ndarray) -> np.ndarray:
    """Rotation vector (3,) [rad] of a 3x3 rotation matrix, angle in [0, pi]: through the unit quaternion
    (MuJoCo's ``mju_mat2Quat``, stable near pi) and its logarithm (``mju_quat2Vel``)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(r, dtype=float).reshape(9))
    vel = np.empty(3)
    mujoco.mju_quat2Vel(vel, quat, 1.0)
    return vel


class _Problem:
    """One solve's constant data over the active variables, in solver units (rad, m, pelvis drop [m])."""

    def __init__(self, ik: WholeBodyIK, act: np.ndarray, prior: IKPrior, area: StandingArea,
                 q0_body: np.ndarray) -> None:
        legs = ik.human.legs
        scale = np.where(np.isin(act, _SLIDES), 1.0, np.pi / 180.0)
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
        self.eyes = tuple(np.deg2rad([prior.eye_side_deg, prior.eye_down_deg, prior.eye_up_deg]))
        self.knee = knee
        self.scale = scale

    def violation(self, qa: np.ndarray) -> np.ndarray:
        """Signed excess over the comfort box (0 inside)."""
        return np.minimum(qa - self.lo_c, 0.0) + np.maximum(qa - self.hi_c, 0.0)

    def knee_terms(self, qa: np.ndarray) -> tuple[float, float, float]:
        """The knee prior (κ(d) / σ)^2, straight knees preferred, as a function of the pelvis drop d: (cost,
        gradient, curvature). With θ = κ / 2 = acos(1 - d / L): cost 4 θ^2 / σ^2, gradient
        8 θ / (σ^2 L sin θ), curvature 8 (sin θ - θ cos θ) / (σ^2 L^2 sin^3 θ); the slope with straight legs
        is finite (8 / (σ^2 L)), so the knees stay straight until bending them pays for itself."""
        if not self.knee.any():
            return 0.0, 0.0, 0.0
        length, s2 = self.legs.length, self.knee_sigma2
        theta = math.acos(min(max(1.0 - float(qa[self.knee][0]) / length, -1.0), 1.0))
        if theta < 1e-4:
            return 4.0 * theta * theta / s2, 8.0 / (s2 * length), 8.0 / (3.0 * s2 * length * length)
        sin, cos = math.sin(theta), math.cos(theta)
        return (4.0 * theta * theta / s2, 8.0 * theta / (s2 * length * sin),
                8.0 * (sin - theta * cos) / (s2 * length * length * sin ** 3))


class _Task:
    """The cost of one solve and its descent: hand task, posture priors, gaze, knees (module docstring)."""

    def __init__(self, ik: WholeBodyIK, side: str, target: np.ndarray, target_rot: np.ndarray | None,
                 look: np.ndarray, act: np.ndarray, prob: _Problem) -> None:
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

    def _kinematics(self, qa: np.ndarray) -> None:
        data = self.ik.data
        data.qpos[self.qadr] = qa
        mujoco.mj_kinematics(self.ik.model, data)
        mujoco.mj_comPos(self.ik.model, data)

    def gaze(self) -> tuple[np.ndarray, np.ndarray]:
        ik = self.ik
        mujoco.mj_jacSite(ik.model, ik.data, ik._jep, ik._jer, self.eye_site)
        return gaze_excess(self.look, self.epos, self.emat, ik._jep[:, self.dof], ik._jer[:, self.dof],
                           *self.prob.eyes)

    def _task(self) -> None:
        """The task error (target - hand; rotation vector) and its Jacobian at the current kinematics."""
        ik = self.ik
        mujoco.mj_jacSite(ik.model, ik.data, ik._jacp, ik._jacr, self.site)
        np.subtract(self.target, self.xpos, out=self.err[:3])
        self.a[:3] = ik._jacp[:, self.dof]
        if self.target_rot is not None:
            self.err[3:] = log_so3(self.target_rot @ self.xmat.T)
            self.a[3:] = ik._jacr[:, self.dof]

    def errors(self) -> tuple[float, float]:
        """(position error [m], rotation error [deg]) at the current kinematics."""
        pos = float(np.linalg.norm(self.xpos - self.target))
        rot = 0.0
        if self.target_rot is not None:
            rot = float(np.rad2deg(np.linalg.norm(log_so3(self.target_rot @ self.xmat.T))))
        return pos, rot

    def cost(self, qa: np.ndarray, gex: np.ndarray) -> float:
        """The whole cost at ``qa`` (the kinematics must be at ``qa``; ``gex`` its gaze excess)."""
        prob = self.prob
        d = qa - prob.pref
        viol = prob.violation(qa)
        e = self.xpos - self.target
        task = self.wt[0] * float(e @ e)
        if self.target_rot is not None:
            r = log_so3(self.target_rot @ self.xmat.T)
            task += self.wt[3] * float(r @ r)
        return float(prob.w2 @ (d * d) + prob.wc2 * (viol @ viol) + prob.wg2 * _huber(gex).sum()
                     + prob.knee_terms(qa)[0] + task)

    def posture_cost(self, qa: np.ndarray) -> float:
        """The cost without the hand task, at ``qa`` (the kinematics must be at ``qa``)."""
        prob = self.prob
        d = qa - prob.pref
        viol = prob.violation(qa)
        return float(prob.w2 @ (d * d) + prob.wc2 * (viol @ viol) + prob.wg2 * _huber(self.gaze()[0]).sum()
                     + prob.knee_terms(qa)[0])

    def descend(self, q: np.ndarray, max_iter: int) -> tuple[np.ndarray, float, int]:
        """Gauss-Newton from ``q`` (solver units, full vector): (the end, its cost, iterations)."""
        prob, act = self.prob, self.act
        qa = q[act].copy()
        self.ik._fk(q)
        mujoco.mj_comPos(self.ik.model, self.ik.data)
        gex, gjac = self.gaze()
        c0 = self.cost(qa, gex)
        mu = _LM_START
        it = 0
        for it in range(1, max_iter + 1):
            self._task()
            d = qa - prob.pref
            viol = prob.violation(qa)
            _, kg, kh = prob.knee_terms(qa)
            # Huber weights (iteratively reweighted): a large gaze error pulls with a bounded force
            wg = prob.wg2 * np.minimum(1.0, _GAZE_HUBER / np.maximum(np.abs(gex), 1e-12))
            hess = (np.diag(prob.w2 + prob.wc2 * (viol != 0.0) + 0.5 * kh * prob.knee) + (gjac.T * wg) @ gjac
                    + (self.a.T * self.wt) @ self.a)
            grad = (prob.w2 * d + prob.wc2 * viol + gjac.T @ (wg * gex) + 0.5 * kg * prob.knee
                    - self.a.T @ (self.wt * self.err))
            # Levenberg-Marquardt: a step that raises the cost is retried with more damping (towards a
            # scaled gradient step), a step that lowers it relaxes the damping
            scale = np.diag(hess).copy()
            for _ in range(_LM_TRIES):
                step = _bounded_step(hess + np.diag(mu * scale), grad, qa, prob.lo, prob.hi)
                self._kinematics(qa + step)
                gex, gjac = self.gaze()
                c1 = self.cost(qa + step, gex)
                if c1 < c0:
                    mu = max(mu * 0.1, _LM_START)
                    break
                mu *= 10.0
            if c1 >= c0:
                # no step lowers the cost: converged (a joint on the edge of its comfort box, where the
                # quadratic model switches on and off, would cycle about it), or at the best approach
                self._kinematics(qa)
                break
            qa, c0, fell = qa + step, c1, c0 - c1
            if np.abs(step).max() < 1e-4 or fell < _TOL_COST * (1.0 + c1):
                break
        out = q.copy()
        out[act] = qa
        return out, c0, it


class WholeBodyIK:
    """IK on a compiled model containing the human (use the subject's standalone human model for speed).

    Targets are in that model's world frame, whose origin is the worker's spot on the floor. Not
    thread-safe: owns one MjData.
    """

    def __init__(self, model: mujoco.MjModel, prior: IKPrior | None = None, pos_tol: float = 2e-3,
                 max_iter: int = 80) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self.human = HumanModel(model)
        self.prior = prior if prior is not None else default_prior()
        self.s_pos = pos_tol
        self.s_rot = math.radians(2.0)
        self.max_iter = max_iter
        stance = [_IDX[n] for n in STANCE]
        self.active = {
            side: np.array(stance + [_IDX[n] for n in TRUNK + NECK] + [_IDX[prefix + n] for n in ARM])
            for side, prefix in (("right", ""), ("left", "left_"))
        }
        h = self.human
        drop_j = model.joint("pelvis_drop").id
        self.qadr = np.concatenate([h.qadr, h.stance_qadr[:3], [model.jnt_qposadr[drop_j]]])
        self.dofadr = np.concatenate([h.dofadr, [model.jnt_dofadr[model.joint(n).id] for n in STANCE[:3]],
                                      [model.jnt_dofadr[drop_j]]])
        lo = [np.deg2rad(h.range_deg[:, 0])]
        hi = [np.deg2rad(h.range_deg[:, 1])]
        for n in STANCE:
            r = model.jnt_range[model.joint(n).id]
            lo.append([r[0]])
            hi.append([r[1]])
        self.lo = np.concatenate(lo)
        self.hi = np.concatenate(hi)
        self._jacp = np.zeros((3, model.nv))
        self._jacr = np.zeros((3, model.nv))
        self._jep = np.zeros((3, model.nv))
        self._jer = np.zeros((3, model.nv))

    # -- conversions -----------------------------------------------------------------------------------------
    def to_solver(self, body: np.ndarray) -> np.ndarray:
        """(26,) body [deg, m] -> solver units [rad, m, drop m]."""
        q = np.deg2rad(np.asarray(body, dtype=float))
        q[list(_SLIDES)] = body[list(_SLIDES)]
        q[_KNEE] = self.human.legs.drop(np.deg2rad(body[_KNEE]))
        return q

    def to_body(self, q: np.ndarray) -> np.ndarray:
        """Solver units -> (26,) body [deg, m]."""
        body = np.rad2deg(q)
        body[list(_SLIDES)] = q[list(_SLIDES)]
        body[_KNEE] = np.rad2deg(self.human.legs.knee_of(q[_KNEE]))
        return body

    def _fk(self, q: np.ndarray) -> None:
        self.data.qpos[self.qadr] = q
        mujoco.mj_kinematics(self.model, self.data)

    # -- solving ---------------------------------------------------------------------------------------------
    def solve(self, q0: np.ndarray, target: np.ndarray, side: str = "right",
              target_rot: np.ndarray | None = None, gaze: np.ndarray | None = None,
              prior: IKPrior | None = None, area: StandingArea | None = None,
              max_iter: int | None = None) -> IKSolution:
        """Drive the ``side`` hand site to ``target`` (3,) [m] (and (3, 3) ``target_rot``) from the body
        ``q0`` (26,), looking at ``gaze`` (3,) [m] (default: the target), the stance within ``area``
        (default: planted where ``q0`` stands).

        Each iteration minimises the Gauss-Newton model of the cost; joints pushed past their range are
        frozen at it and the step re-solved; a line search keeps the cost falling. Unreachable targets
        converge to the best approach. With a stance free to turn, the solve also starts turned towards a
        target far to the side, and the cheaper of the two ends is kept.
        """
        pr = prior if prior is not None else self.prior
        area = area if area is not None else StandingArea.planted()
        q0 = np.asarray(q0, dtype=float)
        act = self.active[side]
        prob = _Problem(self, act, pr, area, q0)
        if (prob.hi <= prob.lo).any():  # joints held where they are (a planted stance) are not variables
            act = act[prob.hi > prob.lo]
            prob = _Problem(self, act, pr, area, q0)
        task = _Task(self, side, np.asarray(target, dtype=float), target_rot,
                     np.asarray(target if gaze is None else gaze, dtype=float), act, prob)
        starts = [q0]
        if not area.is_planted:
            home = q0.copy()
            home[_N:_N + 3] = 0.0  # the worker's own spot
            turned = self._turned_towards(home, target, area)
            starts += [s for s in (home, turned) if not np.array_equal(s, q0)]
        best = None
        for start in starts:
            q = self.to_solver(start)
            q[act] = np.minimum(np.maximum(q[act], prob.lo), prob.hi)
            end = task.descend(q, max_iter or self.max_iter)
            if best is None or end[1] < best[1]:
                best = end
        q, _, it = best
        self._fk(q)
        if not area.is_planted and task.errors()[0] > _REACH_RETRY:
            # free to step, yet short of the target: a local minimum; go on from where the feet stand
            planted = self.solve(q0, target, side, target_rot, gaze, pr, StandingArea.planted(), max_iter)
            end = task.descend(self.to_solver(planted.body), max_iter or self.max_iter)
            if end[1] < best[1]:
                q, _, it = end
            self._fk(q)
        mujoco.mj_comPos(self.model, self.data)
        pos_err, rot_err = task.errors()
        return IKSolution(self.to_body(q), pos_err, rot_err, it, task.posture_cost(q[act]))

    def _turned_towards(self, body: np.ndarray, point: np.ndarray, area: StandingArea) -> np.ndarray:
        """``body`` with the stance turned towards ``point`` by what neck and eyes do not take
        (:data:`_TURN_START`), within the area: the start of a solve whose target lies far to the side or
        behind, where a linearisation from the front would not find the turn."""
        if area.is_planted or area.turn[0] == area.turn[1]:
            return body
        az = math.degrees(math.atan2(point[1] - body[_IDX["pelvis_y"]], point[0] - body[_IDX["pelvis_x"]]))
        turn = body[_IDX["pelvis_rotation"]]
        rel = (az - turn + 180.0) % 360.0 - 180.0
        if abs(rel) <= _TURN_START:
            return body
        out = np.array(body, dtype=float)
        out[_IDX["pelvis_rotation"]] = min(max(turn + rel - math.copysign(_TURN_START, rel), area.turn[0]),
                                           area.turn[1])
        return out

    # -- forward kinematics ----------------------------------------------------------------------------------
    def hand_pose(self, body: np.ndarray, side: str = "right") -> tuple[np.ndarray, np.ndarray]:
        """((3,) position [m], (3, 3) rotation) of a hand's grasp site for a (26,) body."""
        self._fk(self.to_solver(body))
        s = self.human.hand_site[side]
        return self.data.site_xpos[s].copy(), self.data.site_xmat[s].reshape(3, 3).copy()

    def hand_pos(self, body: np.ndarray, side: str = "right") -> np.ndarray:
        """(3,) grasp point for a (26,) body, in this model's world frame."""
        return self.hand_pose(body, side)[0]

    def point(self, body: np.ndarray, body_name: str) -> np.ndarray:
        """(3,) origin of body ``body_name`` (e.g. a shoulder) for a (26,) body."""
        self._fk(self.to_solver(body))
        return self.data.xpos[self.model.body(body_name).id].copy()

    def hand_path(self, bodies: np.ndarray, side: str = "right") -> np.ndarray:
        """(n, 3) grasp-point positions for (n, 26) bodies (forward kinematics per row)."""
        out = np.empty((len(bodies), 3))
        xpos = self.data.site_xpos[self.human.hand_site[side]]
        qs = np.array([self.to_solver(b) for b in bodies]) if len(bodies) < 2 else self._solver_rows(bodies)
        for k in range(len(qs)):
            self.data.qpos[self.qadr] = qs[k]
            mujoco.mj_kinematics(self.model, self.data)
            out[k] = xpos
        return out

    def _solver_rows(self, bodies: np.ndarray) -> np.ndarray:
        q = np.deg2rad(bodies)
        q[:, list(_SLIDES)] = bodies[:, list(_SLIDES)]
        q[:, _KNEE] = self.human.legs.drop(np.deg2rad(bodies[:, _KNEE]))
        return q


def _huber(e: np.ndarray) -> np.ndarray:
    """e^2 within :data:`_GAZE_HUBER`, growing linearly beyond (continuous with its slope)."""
    a = np.abs(e)
    return np.where(a <= _GAZE_HUBER, a * a, _GAZE_HUBER * (2.0 * a - _GAZE_HUBER))


def _bounded_step(hess: np.ndarray, grad: np.ndarray, qa: np.ndarray, lo: np.ndarray,
                  hi: np.ndarray) -> np.ndarray:
    """argmin 1/2 s^T H s + g^T s with variables pushed past [lo, hi] frozen there and the others re-solved
    (up to three rounds), scaled to at most 0.3 per variable and clipped into the bounds."""
    n = len(grad)
    free = np.ones(n, dtype=bool)
    fixed = np.zeros(n)
    step = np.zeros(n)
    for _ in range(4):
        f = np.flatnonzero(free)
        rhs = -grad[f] - hess[np.ix_(f, ~free)] @ fixed[~free]
        step = fixed.copy()
        step[f] = np.linalg.solve(hess[np.ix_(f, f)], rhs)
        new = qa + step
        out = free & ((new < lo) | (new > hi))
        if not out.any():
            break
        fixed[out] = np.minimum(np.maximum(new[out], lo[out]), hi[out]) - qa[out]
        free &= ~out
    step *= min(1.0, 0.3 / max(np.abs(step).max(), 1e-12))
    return np.minimum(np.maximum(qa + step, lo), hi) - qa

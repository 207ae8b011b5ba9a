"""Whole-upper-body inverse kinematics of the kinematic human, with natural posture priors.

One hand's grasp site is driven to a target position (and optionally orientation) by a damped Gauss-Newton
(Levenberg-Marquardt) solve of a regularised least-squares problem over the trunk and that arm:

    min_q  |p(q) - p*|^2 / s_p^2  +  |log(R* R(q)^T)|^2 / s_R^2  +  sum_j (q_j - q_pref_j)^2 / s_j^2
           + max(0, elbow_comfort - q_elbow)^2 / s_elbow^2,            subject to the joint ranges.

The task terms have tiny tolerances (s_p = 0.5 mm), so the priors act in the task's null space: the trunk has
a stiff prior (a few degrees), so it bends or twists only when the arm alone cannot reach comfortably (the
one-sided elbow term makes an almost straight arm expensive); the shoulder abduction and rotation priors keep
the elbow low. The neck is not part of the solve: the head looks at the hand's target (:meth:`look_at`),
with the eyes taking the first few degrees of gaze, so near, low targets flex the neck.

Angles are in degrees at the interface (HUMAN_JOINTS order, (22,)), radians inside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import mujoco
import numpy as np

from ergosim.human.model import HumanModel
from ergosim.posture import ARM, HUMAN_JOINTS, TRUNK

__all__ = ["IKPrior", "IKSolution", "UpperBodyIK", "default_prior", "log_so3"]

_IDX = {n: i for i, n in enumerate(HUMAN_JOINTS)}


@dataclass(frozen=True)
class IKPrior:
    """Preferred angles and their softness, (22,) each in HUMAN_JOINTS order [deg], plus gaze sharing.

    ``sigma_deg`` is how far a joint may move from ``pref_deg`` for the cost of one unit (a large sigma is a
    free joint). Outside the comfort box [``comfort_lo_deg``, ``comfort_hi_deg``] a joint costs one unit per
    ``comfort_sigma_deg`` more: an almost straight elbow or an arm behind the back is expensive, so the
    trunk takes over. ``neck_turn_deg``: how far the head turns comfortably; a target whose azimuth is beyond
    neck + eyes makes the trunk's preferred rotation face it (people turn to what they work on).
    ``eye_down_deg``/``eye_up_deg``/``eye_side_deg``: gaze the eyes take before the neck moves.
    """

    pref_deg: np.ndarray
    sigma_deg: np.ndarray
    comfort_lo_deg: np.ndarray
    comfort_hi_deg: np.ndarray
    comfort_sigma_deg: float = 4.0
    neck_turn_deg: float = 35.0
    eye_down_deg: float = 20.0
    eye_up_deg: float = 5.0
    eye_side_deg: float = 15.0

    def jittered(self, rng: np.random.Generator, deg: float) -> IKPrior:
        """A copy whose preferred angles are perturbed by N(0, deg) (trial-to-trial variability)."""
        return replace(self, pref_deg=self.pref_deg + rng.normal(0.0, deg, self.pref_deg.shape))


def default_prior(trunk_use: float = 1.0, elbow_comfort_deg: float = 25.0) -> IKPrior:
    """Natural priors; ``trunk_use`` > 1 is a person who bends/twists the trunk sooner (stoop style)."""
    pref = np.zeros(len(HUMAN_JOINTS))
    sigma = np.full(len(HUMAN_JOINTS), 30.0)
    lo_c = np.full(len(HUMAN_JOINTS), -360.0)
    hi_c = np.full(len(HUMAN_JOINTS), 360.0)
    box = {"elbow_flexion": (elbow_comfort_deg, 360.0), "shoulder_flexion": (-15.0, 360.0),
           "shoulder_abduction": (-25.0, 360.0)}
    arm = {
        "shoulder_flexion": (15.0, 70.0),
        "shoulder_abduction": (8.0, 18.0),  # elbow stays low
        "shoulder_rotation": (25.0, 30.0),
        "shoulder_elevation": (0.0, 10.0),  # shrug only when needed
        "elbow_flexion": (80.0, 80.0),
        "forearm_pronation": (20.0, 35.0),
        "wrist_flexion": (0.0, 18.0),
        "wrist_deviation": (0.0, 12.0),
    }
    for prefix in ("", "left_"):
        for name, (p, s) in arm.items():
            pref[_IDX[prefix + name]], sigma[_IDX[prefix + name]] = p, s
        for name, (lo, hi) in box.items():
            lo_c[_IDX[prefix + name]], hi_c[_IDX[prefix + name]] = lo, hi
    for name, s in (("trunk_flexion", 6.0), ("trunk_lateral_bend", 4.0), ("trunk_rotation", 6.0)):
        sigma[_IDX[name]] = s * trunk_use
    return IKPrior(pref, sigma, lo_c, hi_c)


class IKSolution(NamedTuple):
    """Result of one solve: (22,) angles [deg], residual position error [m] and rotation error [deg]."""

    angles: np.ndarray
    pos_error: float
    rot_error_deg: float
    iterations: int


def log_so3(r: np.ndarray) -> np.ndarray:
    """Rotation vector (3,) [rad] of a 3x3 rotation matrix, angle in [0, pi]: through the unit quaternion
    (MuJoCo's ``mju_mat2Quat``, stable near pi) and its logarithm (``mju_quat2Vel``)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(r, dtype=float).reshape(9))
    vel = np.empty(3)
    mujoco.mju_quat2Vel(vel, quat, 1.0)
    return vel


class UpperBodyIK:
    """IK on a compiled model containing the human (use the small standalone human model for speed).

    Targets are in that model's world frame. Not thread-safe: owns one MjData.
    """

    def __init__(self, model: mujoco.MjModel, prior: IKPrior | None = None, pos_tol: float = 5e-4,
                 max_iter: int = 80, rel_tol: float = 1e-3) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self.human = HumanModel(model)
        self.prior = prior if prior is not None else default_prior()
        self.s_pos = pos_tol
        self.s_rot = np.deg2rad(0.5)
        self.max_iter = max_iter
        self.rel_tol = rel_tol
        self.active = {
            side: np.array([_IDX[n] for n in TRUNK] + [_IDX[prefix + n] for n in ARM])
            for side, prefix in (("right", ""), ("left", "left_"))
        }
        self.lo = np.deg2rad(self.human.range_deg[:, 0])
        self.hi = np.deg2rad(self.human.range_deg[:, 1])
        self.torso = model.body("human_torso").id
        self.neck = np.array([_IDX["neck_flexion"], _IDX["neck_lateral_bend"], _IDX["neck_rotation"]])
        self._dof = {side: self.human.dofadr[act] for side, act in self.active.items()}
        self._qadr_act = {side: self.human.qadr[act] for side, act in self.active.items()}
        self._jacp = np.zeros((3, model.nv))
        self._jacr = np.zeros((3, model.nv))

    def _fk(self, q: np.ndarray) -> None:
        self.data.qpos[self.human.qadr] = q
        mujoco.mj_kinematics(self.model, self.data)

    def solve(self, q0_deg: np.ndarray, target: np.ndarray, side: str = "right",
              target_rot: np.ndarray | None = None, prior: IKPrior | None = None,
              max_iter: int | None = None) -> IKSolution:
        """Drive the ``side`` hand site to ``target`` (3,) [m] (and (3, 3) ``target_rot``) from ``q0_deg``.

        Sequential quadratic programming: each iteration minimises the posture cost (quadratic, diagonal)
        subject to the linearised task, closed form through the KKT system; joints that hit their range are
        frozen and the step re-solved. Unreachable targets converge to the damped best approach.
        """
        pr = prior if prior is not None else self.prior
        act = self.active[side]
        dof = self._dof[side]
        qadr = self._qadr_act[side]
        site = self.human.hand_site[side]
        model, data = self.model, self.data
        xpos, xmat = data.site_xpos[site], data.site_xmat[site].reshape(3, 3)
        q = np.deg2rad(np.asarray(q0_deg, dtype=float))
        pref = np.deg2rad(pr.pref_deg[act])
        pref[2] += self._trunk_turn(q, target, pr)  # act[2] is trunk_rotation; leaves FK at q
        w2 = np.deg2rad(pr.sigma_deg[act]) ** -2.0
        lo_c, hi_c = np.deg2rad(pr.comfort_lo_deg[act]), np.deg2rad(pr.comfort_hi_deg[act])
        wc2 = np.deg2rad(pr.comfort_sigma_deg) ** -2.0
        lo, hi = self.lo[act], self.hi[act]
        n_task = 6 if target_rot is not None else 3
        diag = np.arange(n_task) * (n_task + 1)
        err = np.zeros(n_task)
        a = np.zeros((n_task, len(act)))
        lam = np.empty(n_task)
        jacp, jacr = self._jacp, self._jacr

        def violation(qa: np.ndarray) -> np.ndarray:  # signed excess over the comfort box (0 inside)
            return np.minimum(qa - lo_c, 0.0) + np.maximum(qa - hi_c, 0.0)

        def merit(d: np.ndarray, viol: np.ndarray, task_err: float) -> float:
            return float(w2 @ (d * d) + wc2 * (viol @ viol)) + 2e4 * task_err

        def task_error() -> float:  # of the current forward kinematics
            e = xpos - target
            err_t = math.sqrt(e @ e)
            if target_rot is not None:
                r = log_so3(target_rot @ xmat.T)
                err_t += math.sqrt(r @ r)
            return err_t

        qa = q[act]
        d = qa - pref
        viol = violation(qa)
        it = 0
        for it in range(1, (max_iter or self.max_iter) + 1):
            # forward kinematics are those of qa here (set by _trunk_turn or by the last line-search trial)
            mujoco.mj_comPos(model, data)
            mujoco.mj_jacSite(model, data, jacp, jacr, site)
            np.subtract(target, xpos, out=err[:3])
            a[:3] = jacp[:, dof]
            if target_rot is not None:
                err[3:] = log_so3(target_rot @ xmat.T)
                a[3:] = jacr[:, dof]
            pos_err = math.sqrt(err[:3] @ err[:3])
            # a linear step cannot be trusted far from the target: cap the task step per iteration
            b = err * min(1.0, 0.15 / max(pos_err, 1e-12))
            outside = viol != 0.0
            h = w2 + wc2 * outside
            g = w2 * d + wc2 * viol
            # the unconstrained step, then: pin joints pushed past their range to it, re-solve the others
            hinv = 1.0 / h
            ah = a * hinv
            kkt = ah @ a.T
            kkt.flat[diag] += 1e-8
            mujoco.mju_cholFactor(kkt, 0.0)
            mujoco.mju_cholSolve(lam, kkt, b + ah @ g)
            step = hinv * (lam @ a - g)
            new = qa + step
            out = (new < lo) | (new > hi)
            if out.any():
                free = ~out
                fixed = np.zeros(len(act))  # steps of joints frozen at their range
                for _ in range(3):
                    fixed[out] = np.minimum(np.maximum(new[out], lo[out]), hi[out]) - qa[out]
                    hinv = np.where(free, 1.0 / h, 0.0)
                    ah = a * hinv
                    kkt = ah @ a.T
                    kkt.flat[diag] += 1e-8
                    mujoco.mju_cholFactor(kkt, 0.0)
                    mujoco.mju_cholSolve(lam, kkt, b - a @ fixed + ah @ g)
                    step = hinv * (lam @ a - g) + fixed
                    new = qa + step
                    out = free & ((new < lo) | (new > hi))
                    if not out.any():
                        break
                    free &= ~out
            step = np.minimum(np.maximum(new, lo), hi) - qa
            step *= min(1.0, 0.3 / max(np.abs(step).max(), 1e-12))
            # exact-penalty merit line search: keeps the SQP from cycling in the wrist/forearm null space
            m0 = merit(d, viol, math.sqrt(err @ err))
            for _ in range(6):
                trial = qa + step
                data.qpos[qadr] = trial
                mujoco.mj_kinematics(model, data)
                d = trial - pref
                viol = violation(trial)
                if merit(d, viol, task_error()) < m0:
                    break
                step *= 0.5
            qa = trial
            if np.abs(step).max() < 1e-3 and pos_err < self.s_pos:
                break
        q[act] = qa
        pos_err = float(np.linalg.norm(xpos - target))
        rot_err = 0.0
        if target_rot is not None:
            rot_err = float(np.rad2deg(np.linalg.norm(log_so3(target_rot @ xmat.T))))
        return IKSolution(np.rad2deg(q), pos_err, rot_err, it)

    def _trunk_turn(self, q: np.ndarray, point: np.ndarray, pr: IKPrior) -> float:
        """Trunk rotation [rad] needed so that neck + eyes can face ``point`` comfortably, for posture ``q``
        [rad]; leaves the forward kinematics at ``q``."""
        self._fk(q)
        root = self.data.xmat[self.human.root_body].reshape(3, 3)
        d = root.T @ (point - self.data.site_xpos[self.human.eye_site])
        az = np.arctan2(d[1], d[0])
        reach = np.deg2rad(pr.neck_turn_deg + pr.eye_side_deg)
        return float(az - np.clip(az, -reach, reach))

    def look_at(self, angles_deg: np.ndarray, point: np.ndarray, prior: IKPrior | None = None) -> np.ndarray:
        """Neck angles that point the gaze at ``point`` (3,) [m]; returns a new (22,) array [deg].

        The eyes take up to ``eye_down``/``eye_up``/``eye_side`` degrees of the gaze; the head turns the rest.
        Yaw and pitch of the gaze are measured in the trunk frame and mapped to the neck's flexion ->
        lateral-bend -> rotation hinges (lateral bend stays 0).
        """
        pr = prior if prior is not None else self.prior
        q = np.deg2rad(np.asarray(angles_deg, dtype=float)).copy()
        for _ in range(3):  # the eyes sit in front of the neck pivot: refine twice
            self._fk(q)
            eye = self.data.site_xpos[self.human.eye_site]
            d = self.data.xmat[self.torso].reshape(3, 3).T @ (point - eye)
            yaw = np.arctan2(d[1], d[0])
            pitch = np.arctan2(-d[2], np.hypot(d[0], d[1]))  # > 0 looking down
            side = np.deg2rad(pr.eye_side_deg)
            yaw_h = yaw - np.clip(yaw, -side, side)
            pitch_h = pitch - np.clip(pitch, -np.deg2rad(pr.eye_up_deg), np.deg2rad(pr.eye_down_deg))
            h = np.array([np.cos(pitch_h) * np.cos(yaw_h), np.cos(pitch_h) * np.sin(yaw_h), -np.sin(pitch_h)])
            neck = np.array([np.arctan2(-h[2], h[0]), 0.0, np.arcsin(np.clip(h[1], -1.0, 1.0))])
            q[self.neck] = np.clip(neck, self.lo[self.neck], self.hi[self.neck])
        return np.rad2deg(q)

    def hand_pos(self, angles_deg: np.ndarray, side: str = "right") -> np.ndarray:
        """(3,) grasp point for (22,) angles [deg], in this model's world frame."""
        self._fk(np.deg2rad(angles_deg))
        return self.data.site_xpos[self.human.hand_site[side]].copy()

    def hand_pose(self, angles_deg: np.ndarray, side: str = "right") -> tuple[np.ndarray, np.ndarray]:
        """((3,) position [m], (3, 3) rotation) of a hand's grasp site for (22,) angles [deg]."""
        self._fk(np.deg2rad(angles_deg))
        s = self.human.hand_site[side]
        return self.data.site_xpos[s].copy(), self.data.site_xmat[s].reshape(3, 3).copy()

    def hand_path(self, angles_deg: np.ndarray, side: str = "right") -> np.ndarray:
        """(n, 3) grasp-point positions for (n, 22) angles [deg] (forward kinematics per row)."""
        out = np.empty((len(angles_deg), 3))
        xpos = self.data.site_xpos[self.human.hand_site[side]]
        qpos = self.data.qpos
        rows = np.empty((len(angles_deg), self.model.nq))
        rows[:] = qpos
        rows[:, self.human.qadr] = np.deg2rad(angles_deg)  # whole qpos rows: one plain copy per frame
        for k in range(len(rows)):
            qpos[:] = rows[k]
            mujoco.mj_kinematics(self.model, self.data)
            out[k] = xpos
        return out

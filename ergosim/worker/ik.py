"""Whole-body inverse kinematics of the kinematic human: stance, trunk, neck and one arm, with a gaze.

One hand's grasp site is driven to a target position (and optionally orientation) while the head looks at
a point, by sequential quadratic programming on a regularised least-squares problem:

    min_q  |p_hand(q) - p*|^2 / s_p^2 (+ |log(R* R_hand(q)^T)|^2 / s_R^2)
           + sum_j ((q_j - pref_j) / s_j)^2 + comfort-box excess^2 / s_c^2 + |gaze excess|^2 / s_g^2,
    q within its ranges and the standing area.

The hand task has tight tolerances (s_p = 2 mm, s_R = 2 deg), so the posture priors
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
from ergosim.worker.ik_cost import Problem, Task, log_so3
from ergosim.worker.ik_prior import BODY, IKPrior, default_prior
from ergosim.worker.stance import StandingArea

__all__ = ["IKSolution", "WholeBodyIK", "log_so3"]

_IDX = {n: i for i, n in enumerate(BODY)}
_N = len(HUMAN_JOINTS)
_KNEE = _IDX["knee_flexion"]
_SLIDES = (_IDX["pelvis_x"], _IDX["pelvis_y"])
_REACH_RETRY = 0.005  # m: a free-stance solve this far from its target also starts from the planted one
_TURN_START = 45.0  # deg of a target's azimuth the head and eyes take before a solve starts turned


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
        prob = Problem(self, act, pr, area, q0)
        if (prob.hi <= prob.lo).any():  # joints held where they are (a planted stance) are not variables
            keep = prob.hi > prob.lo
            act, prob = act[keep], prob.restricted(keep)
        task = Task(self, side, np.asarray(target, dtype=float), target_rot,
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

"""Whole-body inverse kinematics of the kinematic human, on mink, for a stance chosen beforehand.

The stance (where the feet stand and which way the body faces) is chosen first
(:mod:`ergosim.worker.stance`); this solver finds the whole body for it, as posture-prediction tools do
(HUMOSIM, Jack): one hand's grasp site is driven to a target position (and optionally orientation) while
the head looks at a point, the centre of mass stays over the feet, and the body keeps clear of the cell's
furniture. It is mink's differential IK (a QP per iteration through daqp) iterated to a resting posture:

    min_dq  |J_hand dq + e_hand|^2_W + sum_j ((q_j + dq_j - pref_j) / s_j)^2 + |comfort excess|^2 / s_c^2
            + |gaze excess beyond the eyes' zone|^2 / s_g^2
    s.t.    joint ranges (mink ConfigurationLimit), the centre of mass inside the base of support
            (:class:`~ergosim.worker.balance.BalanceLimit`), the legs following the knee and the ankle
            (:class:`~ergosim.worker.ik_tasks.LegCoupling`), the stance frozen
            (mink DofFreezingTask),

with the hand task stiff (2 mm, 2 deg), so the priors (:mod:`ergosim.worker.ik_prior`) act in its null
space and a target beyond reach ends at the best approach. A posture that passes through the cell's
furniture is solved again from there with a stiffer task still, each segment's shortfall from the furniture
(:class:`~ergosim.worker.obstacles.ClearanceTask`). Each accepted step lowers the whole cost (a
halving line search, mink's steps being Gauss-Newton steps of it).

Bodies are (27,) vectors in :data:`~ergosim.worker.ik_prior.BODY` order at the interface (degrees, metres
for the stance's position).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from typing import NamedTuple

import mink
import mujoco
import numpy as np
import qpsolvers

from ergosim.human.legs import DRIVEN
from ergosim.human.model import HumanModel, body_qpos
from ergosim.posture import ARM, HUMAN_JOINTS, STANCE
from ergosim.worker.balance import BalanceLimit, SupportPolygon
from ergosim.worker.ik_prior import BODY, IKPrior, default_prior
from ergosim.worker.ik_tasks import ComfortTask, GazeTask, LegCoupling
from ergosim.worker.obstacles import ClearanceTask, IKModel, clearance

__all__ = ["IKSolution", "WholeBodyIK", "log_so3"]

_IDX = {n: i for i, n in enumerate(BODY)}
_N = len(HUMAN_JOINTS)
_STEP_MAX = 0.2  # rad (or m) per variable and iteration
_TOL_STEP = 1e-4
_TOL_COST = 1e-6  # converged when an iteration lowers the cost by less than this fraction
_DAMPING = 1e-6
GIVE_WAY = 0.01
"""m the hand may leave its target for the body to clear the furniture; a clear posture farther off is not
taken (assumed: within the grasp tolerances of the cells, 2 cm)."""
_THROUGH_PRICE = 1e6  # per m^2 of passing through the furniture, in the descent's merit
COM_SIGMA = 0.05
"""m the centre of mass strays from the middle of the feet for one unit of cost (assumed: a standing person
keeps it near the middle of the base of support and shifts the hips back to do so when leaning forward;
the base of support itself is a hard limit, :mod:`ergosim.worker.balance`)."""
IDLE_ARM_SIGMA_DEG = 10.0
"""deg the idle arm moves from its posture for one unit of cost (assumed: it hangs where it is unless the
furniture is in its way)."""


def log_so3(r: np.ndarray) -> np.ndarray:
    """Rotation vector (3,) [rad] of a 3x3 rotation matrix, angle in [0, pi] (MuJoCo's ``mju_mat2Quat``
    and ``mju_quat2Vel``)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(r, dtype=float).reshape(9))
    vel = np.empty(3)
    mujoco.mju_quat2Vel(vel, quat, 1.0)
    return vel


class IKSolution(NamedTuple):
    """Result of one solve: (27,) body [deg, m], residual position error [m] and rotation error [deg],
    iterations, and the posture's cost (priors, comfort, gaze: what the worker avoids, in units of one
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
        """(5,) stance [m, m, deg, deg, deg]."""
        return self.body[_N:]


class WholeBodyIK:
    """IK on a compiled model containing the human (the subject's standalone human, optionally with the
    cell's obstacles as geoms: :func:`ergosim.worker.obstacles.ik_model`).

    Targets are in that model's world frame, whose origin is the worker's spot on the floor. ``obstacles``:
    geom ids the human's ``segments`` (geom ids) keep clear of. Not thread-safe: owns one mink
    Configuration.
    """

    def __init__(self, model: mujoco.MjModel, prior: IKPrior | None = None, pos_tol: float = 2e-3,
                 max_iter: int = 60, stature: float | None = None, foot_length: float | None = None,
                 segments: Sequence[int] = (), obstacles: Sequence[int] = (),
                 forearms: Sequence[int] = ()) -> None:
        self.model = model
        self.config = mink.Configuration(model)
        self.data = self.config.data
        self.human = HumanModel(model)
        self.prior = prior if prior is not None else default_prior()
        self.s_pos = pos_tol
        self.s_rot = math.radians(2.0)
        self.max_iter = max_iter
        h = self.human
        self.body_qadr = np.concatenate([h.qadr, h.stance_qadr])
        self.body_dof = np.array([model.jnt_dofadr[model.joint(n).id] for n in HUMAN_JOINTS + STANCE])
        ranges = np.array([model.jnt_range[model.joint(n).id] for n in HUMAN_JOINTS + STANCE])
        hinges = [k for k in range(len(BODY)) if k not in (_IDX["pelvis_x"], _IDX["pelvis_y"])]
        ranges[hinges] *= 180.0 / np.pi
        self._body_lo, self._body_hi = ranges[:, 0], ranges[:, 1]
        # the pelvis stands at the hip joint centre's height, 0.530 of stature (Drillis & Contini)
        stature = stature if stature is not None else float(model.body("human_pelvis").pos[2]) / 0.530
        legs = h.legs
        self.support = SupportPolygon(model, stature, foot_length or 0.152 * stature)
        self.frozen = [int(self.body_dof[_IDX[n]]) for n in STANCE[:3]]
        self.idle = {side: np.array([_IDX[other + n] for n in ARM])
                     for side, other in (("right", "left_"), ("left", ""))}
        self.legs = LegCoupling(model, legs)
        # the driven joints follow the knee and the ankle (an equality): their own bounds would duplicate
        # the knee's and the ankle's, a degenerate set of active constraints for the QP
        free = copy.copy(model)
        free.jnt_limited = model.jnt_limited.copy()
        for name in DRIVEN:
            free.jnt_limited[model.joint(name).id] = 0
        self.limits: list[mink.Limit] = [mink.ConfigurationLimit(free, gain=1.0),
                                         BalanceLimit(self.support)]
        self.segments, self.obstacles, self.forearms = tuple(segments), tuple(obstacles), tuple(forearms)
        if self.segments and self.obstacles:
            built = IKModel(model, self.segments, self.obstacles, self.forearms)
            self.clear_task = ClearanceTask(model, built)
        self.hand_task = {side: mink.FrameTask(h.model.site(h.hand_site[side]).name, "site",
                                               position_cost=1.0 / pos_tol, orientation_cost=0.0)
                          for side in ("right", "left")}
        self.posture = mink.PostureTask(model, cost=np.zeros(model.nv))
        self.com = mink.ComTask(cost=np.array([1.0 / COM_SIGMA, 1.0 / COM_SIGMA, 0.0]))
        self._freeze = mink.DofFreezingTask(model, self.frozen)

    # -- conversions -----------------------------------------------------------------------------------------
    def qpos(self, body: np.ndarray) -> np.ndarray:
        """The model's qpos (nq,) for a (27,) body [deg, m], the legs following the knee and the ankle."""
        q = self.model.qpos0.copy()
        self.human.write_body(q, body_qpos(body[:_N], body[_N:]))
        return q

    def clip(self, bodies: np.ndarray) -> np.ndarray:
        """(..., 27) bodies [deg, m] clipped into the joints' ranges."""
        return np.clip(bodies, self._body_lo, self._body_hi)

    def to_body(self, qpos: np.ndarray) -> np.ndarray:
        """The (27,) body [deg, m] of a qpos."""
        body = np.rad2deg(qpos[self.body_qadr])
        body[_N:_N + 2] = qpos[self.body_qadr[_N:_N + 2]]
        return body

    def _fk(self, qpos: np.ndarray) -> None:
        self.config.update(qpos)

    # -- solving ---------------------------------------------------------------------------------------------
    def _tasks(self, pr: IKPrior, side: str, target: np.ndarray, target_rot: np.ndarray | None,
               look: np.ndarray, q0: np.ndarray) -> list[mink.Task]:
        hand = self.hand_task[side]
        rot = np.eye(3) if target_rot is None else np.asarray(target_rot, dtype=float)
        hand.set_target(mink.SE3.from_rotation_and_translation(mink.SO3.from_matrix(rot), target))
        hand.set_orientation_cost(0.0 if target_rot is None else 1.0 / self.s_rot)
        scale = np.where(np.isin(np.arange(len(BODY)), [_IDX["pelvis_x"], _IDX["pelvis_y"]]), 1.0,
                         np.pi / 180.0)
        cost = np.zeros(self.model.nv)
        cost[self.body_dof] = 1.0 / (pr.sigma * scale)
        cost[self.frozen] = 0.0
        # the idle arm keeps the posture it has, moving only to clear the furniture
        idle = self.idle[side]
        cost[self.body_dof[idle]] = 1.0 / math.radians(IDLE_ARM_SIGMA_DEG)
        self.posture.set_cost(cost)
        target_q = self.model.qpos0.copy()
        target_q[self.body_qadr] = pr.pref * scale
        target_q[self.body_qadr[idle]] = np.deg2rad(q0[idle])
        self.posture.set_target(target_q)
        boxed = np.flatnonzero((pr.comfort_lo > -360.0) | (pr.comfort_hi < 360.0))
        boxed = boxed[~np.isin(self.body_dof[boxed], self.frozen) & ~np.isin(boxed, idle)]
        comfort = ComfortTask(self.model.nv, self.body_qadr[boxed], self.body_dof[boxed],
                              np.deg2rad(pr.comfort_lo[boxed]), np.deg2rad(pr.comfort_hi[boxed]),
                              math.radians(pr.comfort_sigma_deg))
        gaze = GazeTask(self.model, self.human.eye_site, math.radians(pr.gaze_sigma_deg),
                        *np.deg2rad([pr.eye_side_deg, pr.eye_down_deg, pr.eye_up_deg]).tolist())
        gaze.look_at(look)
        # the centre of mass prefers the middle of the feet (the feet are where q0 puts them)
        self._fk(self.qpos(q0))
        centre, heading = self.support.frame(self.data)
        middle = centre + heading * 0.5 * (self.support.heel + self.support.toe)
        self.com.set_target(np.array([middle[0], middle[1], 0.0]))
        return [hand, self.posture, comfort, gaze, self.com]

    def _cost(self, tasks: list[mink.Task]) -> tuple[float, float]:
        """(whole cost, posture cost) at the current configuration."""
        hand, posture, comfort, gaze, com = tasks[:5]
        e = hand.compute_error(self.config) * hand.cost
        p = posture.compute_error(self.config) * posture.cost
        c = comfort.compute_error(self.config) * comfort.cost
        m = com.compute_error(self.config) * com.cost
        rest = float(p @ p + c @ c + m @ m) + gaze.cost_of(self.data)
        return float(e @ e) + rest, rest

    def solve(self, q0: np.ndarray, target: np.ndarray, side: str = "right",
              target_rot: np.ndarray | None = None, gaze: np.ndarray | None = None,
              prior: IKPrior | None = None, max_iter: int | None = None, collide: bool = True) -> IKSolution:
        """Drive the ``side`` hand site to ``target`` (3,) [m] (and (3, 3) ``target_rot``) from the body
        ``q0`` (27,), looking at ``gaze`` (3,) [m] (default: the target), standing where ``q0`` stands.

        The feet stay where ``q0`` puts them; knees, ankles (and so the hips over the feet), trunk, neck
        and the acting arm move. Unreachable targets converge to the best approach.

        The furniture is a hard limit, applied where it matters: the body is solved without it, and only a
        posture that passes through the furniture is solved again, from there, with the furniture's
        distances as limits. (From the rest posture the hand hangs below a bench's edge; with the limits on
        from the start the straight way up is blocked and the descent settles in a stooped detour.)
        ``collide=False`` leaves the furniture out altogether (a via posture, checked afterwards).
        """
        pr = prior if prior is not None else self.prior
        target = np.asarray(target, dtype=float)
        q0 = np.asarray(q0, dtype=float)
        tasks = self._tasks(pr, side, target, target_rot, target if gaze is None else np.asarray(gaze), q0)
        constraints = [self._freeze, self.legs]
        max_iter = max_iter or self.max_iter
        self._fk(self.qpos(np.asarray(q0, dtype=float)))
        it = self._descend(tasks, constraints, max_iter)
        if collide and self.obstacles and self.clearance() < 0.0:
            reached = self.data.qpos.copy()
            error = self._errors(side, target, target_rot)[0]
            it += self._descend(tasks + [self.clear_task], constraints, max_iter, clear=True)
            if self._errors(side, target, target_rot)[0] > max(error, GIVE_WAY):
                # clearing the furniture would take the hand off its target: a worker presses the
                # forearm on the edge rather than miss the part
                self._fk(reached)
        _, posture_cost = self._cost(tasks)
        pos_err, rot_err = self._errors(side, target, target_rot)
        return IKSolution(self.to_body(self.data.qpos), pos_err, rot_err, it, posture_cost)

    def clearance(self) -> float:
        """The body's clearance from the obstacles at the current configuration [m]
        (:func:`ergosim.worker.obstacles.clearance`)."""
        return clearance(self.model, self.data, self.segments, self.obstacles, self.forearms)

    def _merit(self, tasks: list[mink.Task], clear: bool) -> float:
        """The cost, plus (with ``clear``) a steep price on passing through the furniture, so that a
        descent started inside it accepts the steps that take it out."""
        cost, _ = self._cost(tasks)
        if clear:
            cost += _THROUGH_PRICE * min(self.clearance(), 0.0) ** 2
        return cost

    def _descend(self, tasks: list[mink.Task], constraints: list[mink.Task], max_iter: int,
                 clear: bool = False) -> int:
        """Iterate mink steps from the current configuration until the cost stops falling; the
        iterations."""
        c0 = self._merit(tasks, clear)
        it = 0
        for it in range(1, max_iter + 1):
            result = self._step(tasks, constraints)
            if not result.found:
                break
            step = result.x * min(1.0, _STEP_MAX / max(float(np.abs(result.x).max()), 1e-12))
            q_start = self.data.qpos.copy()
            accepted = False
            for _ in range(4):  # halve a step that does not lower the cost
                q1 = q_start.copy()
                mujoco.mj_integratePos(self.model, q1, step, 1.0)
                self._snap_legs(q1)
                self._fk(q1)
                c1 = self._merit(tasks, clear)
                # the first step is taken as the QP gives it: it carries a start that lies outside a hard
                # limit (the balance) back inside, which may cost posture; so is every step that pulls the
                # body out of the furniture (the QP's stiff clearance task leads there, not the merit)
                if c1 < c0 or it == 1 or clear:
                    accepted = True
                    break
                step = 0.5 * step
            if not accepted:
                self._fk(q_start)
                break
            fell, c0 = c0 - c1, c1
            if clear and self.clearance() < 0.0:
                continue
            if np.abs(step).max() < _TOL_STEP or 0.0 <= fell < _TOL_COST * (1.0 + c1):
                break
        return it

    def _step(self, tasks: list[mink.Task], constraints: list[mink.Task]) -> qpsolvers.Solution:
        problem = mink.build_ik(self.config, tasks, 1.0, _DAMPING, self.limits, constraints)
        return qpsolvers.solve_problem(problem, solver="daqp")

    def _snap_legs(self, qpos: np.ndarray) -> None:
        legs = self.human.legs
        knee, ankle = qpos[legs.knee], qpos[legs.ankle]
        legs.write(qpos, knee, ankle)

    def _errors(self, side: str, target: np.ndarray, target_rot: np.ndarray | None) -> tuple[float, float]:
        s = self.human.hand_site[side]
        pos = float(np.linalg.norm(self.data.site_xpos[s] - target))
        rot = 0.0
        if target_rot is not None:
            hand_rot = self.data.site_xmat[s].reshape(3, 3)
            rot = float(np.rad2deg(np.linalg.norm(log_so3(target_rot @ hand_rot.T))))
        return pos, rot

    # -- forward kinematics ----------------------------------------------------------------------------------
    def hand_pose(self, body: np.ndarray, side: str = "right") -> tuple[np.ndarray, np.ndarray]:
        """((3,) position [m], (3, 3) rotation) of a hand's grasp site for a (27,) body."""
        self._fk(self.qpos(body))
        s = self.human.hand_site[side]
        return self.data.site_xpos[s].copy(), self.data.site_xmat[s].reshape(3, 3).copy()

    def hand_pos(self, body: np.ndarray, side: str = "right") -> np.ndarray:
        """(3,) grasp point for a (27,) body, in this model's world frame."""
        return self.hand_pose(body, side)[0]

    def point(self, body: np.ndarray, body_name: str) -> np.ndarray:
        """(3,) origin of body ``body_name`` (e.g. a shoulder) for a (27,) body."""
        self._fk(self.qpos(body))
        return self.data.xpos[self.model.body(body_name).id].copy()

    def hand_path(self, bodies: np.ndarray, side: str = "right") -> np.ndarray:
        """(n, 3) grasp-point positions for (n, 27) bodies (forward kinematics per row)."""
        out = np.empty((len(bodies), 3))
        s = self.human.hand_site[side]
        qpos = self.model.qpos0.copy()
        for k, b in enumerate(np.asarray(bodies, dtype=float)):
            self.human.write_body(qpos, body_qpos(b[:_N], b[_N:]))
            self.data.qpos[:] = qpos
            mujoco.mj_kinematics(self.model, self.data)
            out[k] = self.data.site_xpos[s]
        return out

    def balance_path(self, bodies: np.ndarray) -> np.ndarray:
        """(n,) centre-of-mass margin to the edge of the base of support [m] (negative outside) for (n, 27)
        bodies."""
        out = np.empty(len(bodies))
        qpos = self.model.qpos0.copy()
        for k, b in enumerate(np.asarray(bodies, dtype=float)):
            self.human.write_body(qpos, body_qpos(b[:_N], b[_N:]))
            self.data.qpos[:] = qpos
            mujoco.mj_kinematics(self.model, self.data)
            mujoco.mj_comPos(self.model, self.data)
            out[k] = self.support.margin(self.data)
        return out

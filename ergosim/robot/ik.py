"""Inverse kinematics of the TCP: damped least squares inside the joint limits.

Position and orientation, with a null-space pull towards a preferred posture so that redundant solutions
stay near the ready pose (and so near each other along a path). Frames: the robot base frame.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pinocchio as pin

from ergosim.robot.kinematics import ArmKinematics

__all__ = ["IKResult", "solve_ik", "pose_error"]


class IKResult(NamedTuple):
    """``q`` (7,) [rad]; ``pos_error`` [m]; ``rot_error_deg`` [deg]; ``ok`` when both are within tolerance."""

    q: np.ndarray
    pos_error: float
    rot_error_deg: float
    ok: bool
    iterations: int


def pose_error(kin: ArmKinematics, q: np.ndarray, pos: np.ndarray, rot: np.ndarray) -> np.ndarray:
    """(6,) error twist [m, rad] taking the TCP at ``q`` to (``pos``, ``rot``), base-frame axes."""
    p, r = kin.fk(q)
    return np.concatenate([pos - p, pin.log3(rot @ r.T)])


def _solve_from(kin: ArmKinematics, q: np.ndarray, pos: np.ndarray, rot: np.ndarray,
                q_pref: np.ndarray, max_iter: int, damping: float, tol_pos: float, tol_rot: float,
                margin: float) -> tuple[np.ndarray, int]:
    lo, hi = kin.lower + margin, kin.upper - margin
    span = hi - lo
    # a joint whose range is a full turn (the UR5's +-pi) wraps instead of stopping at its limit: past pi is
    # the same pose as just above -pi
    turn = (kin.upper - kin.lower) >= 2 * np.pi - 1e-9
    for it in range(max_iter):
        e = pose_error(kin, q, pos, rot)
        if np.linalg.norm(e[:3]) < tol_pos and np.linalg.norm(e[3:]) < tol_rot:
            return q, it
        # cap the task-space step: DLS is only locally linear
        n = np.linalg.norm(e[:3])
        if n > 0.1:
            e[:3] *= 0.1 / n
        n = np.linalg.norm(e[3:])
        if n > 0.5:
            e[3:] *= 0.5 / n
        jac = kin.jacobian(q)
        jjt = jac @ jac.T + damping**2 * np.eye(6)
        jpinv = jac.T @ np.linalg.inv(jjt)
        # secondary task: stay near q_pref, weighted away from the limits
        dq_null = 0.1 * (q_pref - q) / (span**2) * span.mean() ** 2
        dq = jpinv @ e + (np.eye(kin.nq) - jpinv @ jac) @ dq_null
        q = q + dq
        if turn.any():
            q[turn] = kin.lower[turn] + np.mod(q[turn] - kin.lower[turn], 2 * np.pi)
        q = np.clip(q, lo, hi)
    return q, max_iter


def solve_ik(kin: ArmKinematics, pos: np.ndarray, rot: np.ndarray, q0: np.ndarray | None = None, *,
             q_pref: np.ndarray | None = None, seeds: list[np.ndarray] | None = None,
             rng: np.random.Generator | None = None, restarts: int = 0, max_iter: int = 200,
             damping: float = 1e-3, tol_pos: float = 2e-4, tol_rot_deg: float = 0.05,
             margin: float = 1e-3) -> IKResult:
    """TCP at ``pos`` (3,) [m] with orientation ``rot`` (3, 3), base frame, within the joint limits.

    Tries ``q0`` (default the ready pose), then ``seeds``, then ``restarts`` configurations drawn from
    ``rng``; the
    first that converges is returned, else the best attempt with ``ok=False``. ``margin`` [rad] keeps the
    solution that far inside each limit.
    """
    pos = np.asarray(pos, dtype=float)
    rot = np.asarray(rot, dtype=float)
    q_pref = kin.ready if q_pref is None else np.asarray(q_pref, dtype=float)
    starts = [kin.ready if q0 is None else np.asarray(q0, dtype=float)] + list(seeds or [])
    if rng is not None:
        starts += [rng.uniform(kin.lower, kin.upper) for _ in range(restarts)]
    tol_rot = np.deg2rad(tol_rot_deg)
    best: IKResult | None = None
    for start in starts:
        q, it = _solve_from(kin, np.clip(start, kin.lower + margin, kin.upper - margin), pos, rot, q_pref,
                            max_iter, damping, tol_pos, tol_rot, margin)
        e = pose_error(kin, q, pos, rot)
        pe, re = float(np.linalg.norm(e[:3])), float(np.rad2deg(np.linalg.norm(e[3:])))
        res = IKResult(q, pe, re, pe < tol_pos * 1.5 and re < tol_rot_deg * 1.5, it)
        if res.ok:
            return res
        if best is None or pe + 0.01 * re < best.pos_error + 0.01 * best.rot_error_deg:
            best = res
    assert best is not None
    return best

"""The worker turning a part in the fingers while carrying it.

A grasp keeps the part where the hand took it, but where the part must end (a hollow of J, a ledge) often
needs another orientation in the hand than the one it was picked with (a profile picked lying on the bench,
inserted upright). People re-grip while they carry; the motion planner therefore places the *hand* where
the part can end on its target (:class:`~ergosim.worker.motion.Worker`), and this module moves the
hand→part weld's relative pose from the grasp pose to that final pose during the carry phase, along a
minimum-jerk slerp. The part itself stays a physical body: only the constraint's target moves.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.worker.minimum_jerk import min_jerk

__all__ = ["InHandTurn", "relative_pose"]


def relative_pose(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray,
                  q2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pose of frame 2 in frame 1 (positions (3,) [m], quaternions (4,) wxyz)."""
    r1 = np.empty(9)
    mujoco.mju_quat2Mat(r1, q1)
    conj = q1 * np.array([1.0, -1.0, -1.0, -1.0])
    q = np.empty(4)
    mujoco.mju_mulQuat(q, conj, q2)
    return r1.reshape(3, 3).T @ (p2 - p1), q


def _slerp(qa: np.ndarray, qb: np.ndarray, s: float) -> np.ndarray:
    if np.dot(qa, qb) < 0.0:
        qb = -qb
    dq = np.empty(4)
    mujoco.mju_mulQuat(dq, qa * np.array([1.0, -1.0, -1.0, -1.0]), qb)
    vel = np.empty(3)
    mujoco.mju_quat2Vel(vel, dq, 1.0)
    out = qa.copy()
    mujoco.mju_quatIntegrate(out, vel, s)
    return out


class InHandTurn:
    """Moves weld ``eq`` of ``model`` from its current relative pose to (``pos1``, ``quat1``) between control
    frames ``start`` and ``end`` of the worker's segment."""

    def __init__(self, model: mujoco.MjModel, eq: int, pos1: np.ndarray, quat1: np.ndarray,
                 start: int, end: int) -> None:
        self.model = model
        self.eq = eq
        self.pos1, self.quat1 = np.asarray(pos1, float), np.asarray(quat1, float)
        self.start, self.end = int(start), max(int(end), int(start) + 1)
        self.pos0: np.ndarray | None = None
        self.quat0: np.ndarray | None = None

    def __call__(self, frame: int) -> None:
        if frame < self.start or frame > self.end:
            return
        data = self.model.eq_data[self.eq]
        if self.pos0 is None:
            self.pos0, self.quat0 = data[3:6].copy(), data[6:10].copy()
        s = float(min_jerk(np.array([(frame - self.start) / (self.end - self.start)]))[0])
        data[3:6] = (1.0 - s) * self.pos0 + s * self.pos1
        data[6:10] = _slerp(self.quat0, self.quat1, s)

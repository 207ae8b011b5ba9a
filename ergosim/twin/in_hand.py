"""The worker turning a part in the fingers while carrying it.

A grasp keeps the part where the hand took it, but where the part must end (a slot, a ledge) often
needs another orientation in the hand than the one it was picked with (a profile picked lying on the bench,
inserted upright). People re-grip while they carry; the motion planner therefore places the *hand* where
the part can end on its target (:class:`~ergosim.worker.motion.Worker`), and this module moves the
hand→part weld's relative pose from the grasp pose to that final pose during the carry phase, along a
minimum-jerk slerp. The part itself stays a physical body: only the constraint's target moves.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from ergosim import quat
from ergosim.worker.minimum_jerk import min_jerk

__all__ = ["InHandTurn", "relative_pose", "slerp"]


def relative_pose(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray,
                  q2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pose of frame 2 in frame 1 (positions (3,) [m], quaternions (4,) wxyz)."""
    q = np.empty(4)
    mujoco.mju_mulQuat(q, quat.conj(q1), q2)
    return quat.to_mat(q1).T @ (p2 - p1), q


def slerp(qa: np.ndarray, qb: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(n, 4) unit quaternions from ``qa`` (s = 0) to ``qb`` (s = 1) along the shorter arc, for (n,) ``s``."""
    if np.dot(qa, qb) < 0.0:
        qb = -qb
    dq = quat.mul(quat.conj(qa), qb)
    dq /= np.linalg.norm(dq)
    half = math.atan2(float(np.linalg.norm(dq[1:])), float(dq[0]))  # half the relative rotation angle
    axis = dq[1:] / math.sin(half) if half > 1e-12 else np.zeros(3)
    h = np.asarray(s, dtype=float)[:, None] * half
    step = np.concatenate([np.cos(h), np.sin(h) * axis], axis=1)
    return quat.mul(qa, step)


class InHandTurn:
    """Moves weld ``eq`` of ``model`` from its relative pose at control frame ``start`` (just after the grasp)
    to (``pos1``, ``quat1``) at frame ``end`` of the worker's segment, along a minimum-jerk profile.

    The whole path is computed once, at ``start``; each frame then copies one row into the weld."""

    def __init__(self, model: mujoco.MjModel, eq: int, pos1: np.ndarray, quat1: np.ndarray,
                 start: int, end: int) -> None:
        self.model = model
        self.eq = eq
        self.pos1, self.quat1 = np.asarray(pos1, float), np.asarray(quat1, float)
        self.start, self.end = int(start), max(int(end), int(start) + 1)
        self._pos: np.ndarray | None = None
        self._quat: np.ndarray | None = None

    def _plan(self, pos0: np.ndarray, quat0: np.ndarray) -> None:
        s = min_jerk(np.arange(self.end - self.start + 1) / (self.end - self.start))
        self._pos = pos0 + s[:, None] * (self.pos1 - pos0)
        self._quat = slerp(quat0, self.quat1, s)

    def __call__(self, frame: int) -> None:
        if frame < self.start or frame > self.end:
            return
        data = self.model.eq_data[self.eq]
        if self._pos is None:
            self._plan(data[3:6].copy(), data[6:10].copy())
        i = frame - self.start
        data[3:6] = self._pos[i]
        data[6:10] = self._quat[i]

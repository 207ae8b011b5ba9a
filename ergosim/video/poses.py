"""Body poses recorded at the ergonomics ticks, sampled at any time in between (for video frames).

The loop keeps every body's world pose at each ergonomics tick (:attr:`SubjectRun.bodies`, 20 Hz by default);
a video at 30 frames per second needs poses between those samples. Positions are interpolated linearly and
quaternions by normalised linear interpolation (the rotation between two 50 ms samples is small, so nlerp
and slerp agree to well below a pixel). A body that moved farther than ``jump`` between two samples was
put there, not carried (the parts laid out again at the start of a repetition): it is shown at the nearer
sample instead of sliding across the bench.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PoseTrack"]


class PoseTrack:
    """``t`` (n,) sample times [s], increasing; ``pos`` (n, b, 3) world positions [m]; ``quat`` (n, b, 4)
    world orientations, MuJoCo's wxyz. ``jump`` [m]: the largest move between two samples that is drawn as
    motion (default 0.15 m in one 50 ms tick, 3 m/s: faster than any hand or robot in the twin)."""

    def __init__(self, t: np.ndarray, pos: np.ndarray, quat: np.ndarray, jump: float = 0.15) -> None:
        t = np.asarray(t, dtype=float)
        pos = np.asarray(pos, dtype=float)
        quat = np.asarray(quat, dtype=float)
        if t.ndim != 1 or len(t) == 0:
            raise ValueError(f"t must be a non-empty (n,) array, got shape {t.shape}")
        if pos.shape[:1] != t.shape or pos.ndim != 3 or pos.shape[2] != 3:
            raise ValueError(f"pos must have shape ({len(t)}, b, 3), got {pos.shape}")
        if quat.shape != (*pos.shape[:2], 4):
            raise ValueError(f"quat must have shape {(*pos.shape[:2], 4)}, got {quat.shape}")
        if np.any(np.diff(t) <= 0):
            raise ValueError("sample times must increase")
        self.t, self.pos, self.quat, self.jump = t, pos, quat, float(jump)

    @property
    def start(self) -> float:
        return float(self.t[0])

    @property
    def end(self) -> float:
        return float(self.t[-1])

    def at(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """(b, 3) positions and (b, 4) unit wxyz quaternions at ``time`` [s] (held at the ends)."""
        t = self.t
        if time <= t[0]:
            return self.pos[0].copy(), self.quat[0].copy()
        if time >= t[-1]:
            return self.pos[-1].copy(), self.quat[-1].copy()
        i = int(np.searchsorted(t, time, side="right")) - 1
        w = (time - t[i]) / (t[i + 1] - t[i])
        p0, p1 = self.pos[i], self.pos[i + 1]
        q0, q1 = self.quat[i], self.quat[i + 1]
        q1 = np.where((np.sum(q0 * q1, axis=1) < 0)[:, None], -q1, q1)  # the shorter way round
        pos = (1 - w) * p0 + w * p1
        quat = (1 - w) * q0 + w * q1
        quat /= np.linalg.norm(quat, axis=1, keepdims=True)
        jumped = np.linalg.norm(p1 - p0, axis=1) > self.jump
        if jumped.any():
            near_p, near_q = (p0, q0) if w < 0.5 else (p1, q1)
            pos[jumped], quat[jumped] = near_p[jumped], near_q[jumped]
        return pos, quat

"""Unit quaternions, the one module for them. Every quaternion in ergosim is MuJoCo's (w, x, y, z).

rerun takes (x, y, z, w): :func:`wxyz_to_xyzw` is the one place that converts. :func:`to_mat` is
MuJoCo's own ``mju_quat2Mat`` for one quaternion and for a batch alike, so a rotation matrix is the same to
the last bit wherever it is computed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np

__all__ = ["to_mat", "from_mat", "mul", "conj", "rotate", "angle_deg", "from_yaw_deg", "from_rpy",
           "from_axis_to", "wxyz_to_xyzw", "xyzw_to_wxyz"]

_CONJ = np.array([1.0, -1.0, -1.0, -1.0])
_WXYZ_TO_XYZW = np.array([1, 2, 3, 0])
_XYZW_TO_WXYZ = np.array([3, 0, 1, 2])


def to_mat(quat: np.ndarray) -> np.ndarray:
    """(..., 4) unit quaternions wxyz -> (..., 3, 3) rotation matrices (``mju_quat2Mat``)."""
    q = np.asarray(quat, dtype=float)
    if q.shape[-1:] != (4,):
        raise ValueError(f"expected quaternions of shape (..., 4), got {q.shape}")
    flat = np.ascontiguousarray(q.reshape(-1, 4))
    out = np.empty((len(flat), 9))
    for row, qi in zip(out, flat, strict=True):
        mujoco.mju_quat2Mat(row, qi)
    return out.reshape(*q.shape[:-1], 3, 3)


def from_mat(mat: np.ndarray) -> np.ndarray:
    """(4,) unit quaternion wxyz of a rotation matrix (3, 3) or its 9 entries (``mju_mat2Quat``)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.asarray(mat, dtype=float).reshape(9))
    return quat


def mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products a ⊗ b of (..., 4) wxyz quaternions (rotation ``b`` first, then ``a``)."""
    aw, ax, ay, az = np.moveaxis(np.asarray(a, dtype=float), -1, 0)
    bw, bx, by, bz = np.moveaxis(np.asarray(b, dtype=float), -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def conj(quat: np.ndarray) -> np.ndarray:
    """(..., 4) conjugates: the inverse rotations of unit quaternions."""
    return np.asarray(quat, dtype=float) * _CONJ


def rotate(quat: np.ndarray, vec: np.ndarray) -> np.ndarray:
    """(3,) vector ``vec`` rotated by the unit quaternion ``quat`` (q ⊗ (0, v) ⊗ q*)."""
    q = np.asarray(quat, dtype=float)
    return mul(mul(q, np.concatenate([[0.0], vec])), conj(q))[1:]


def angle_deg(quat: np.ndarray) -> float:
    """The rotation angle of a unit quaternion [deg], in [0, 180]."""
    return float(np.degrees(2 * np.arccos(np.clip(abs(quat[0]), 0.0, 1.0))))


def from_yaw_deg(yaw_deg: float) -> list[float]:
    """wxyz [w, 0, 0, z] of a turn by ``yaw_deg`` [deg] about the world z axis."""
    h = math.radians(yaw_deg) / 2
    return [math.cos(h), 0.0, 0.0, math.sin(h)]


def from_rpy(rpy: Sequence[float], degrees: bool = False) -> np.ndarray:
    """(4,) wxyz of roll, pitch, yaw [rad, or deg with ``degrees``] about the fixed x, y, z axes
    (R = Rz Ry Rx; URDF's ``rpy``)."""
    r, p, y = (0.5 * (math.radians(a) if degrees else a) for a in rpy)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
                     cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy])


def from_axis_to(axis_from: str, axis: tuple[float, float, float]) -> np.ndarray:
    """Unit quaternion wxyz taking local axis ``axis_from`` ("x" | "y" | "z") onto the direction ``axis``.

    The principal cases keep the part's other faces parallel to the host's (exact values, no rounding
    drift): x->x identity, x->y yaw +90 deg, x->z pitch -90 deg."""
    src = np.eye(3)["xyz".index(axis_from)]
    dst = np.asarray(axis, dtype=float)
    dst = dst / np.linalg.norm(dst)
    if np.array_equal(src, dst):
        return np.array([1.0, 0, 0, 0])
    if axis_from == "x" and np.array_equal(dst, [0, 1.0, 0]):
        return np.array([np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)])
    if axis_from == "x" and np.array_equal(dst, [0, 0, 1.0]):
        return np.array([np.cos(np.pi / 4), 0, -np.sin(np.pi / 4), 0])
    c = float(np.dot(src, dst))
    if c < -1 + 1e-12:  # opposite: half a turn about any perpendicular axis
        perp = np.eye(3)[(("xyz".index(axis_from)) + 1) % 3]
        return np.array([0.0, *perp])
    v = np.cross(src, dst)
    q = np.array([1.0 + c, *v])
    return q / np.linalg.norm(q)


def wxyz_to_xyzw(quat_wxyz: np.ndarray) -> np.ndarray:
    """(..., 4) MuJoCo quaternions [w, x, y, z] -> a new (..., 4) float32 array [x, y, z, w] for rerun."""
    q = np.asarray(quat_wxyz)
    if q.shape[-1:] != (4,):
        raise ValueError(f"expected quaternions of shape (..., 4), got {q.shape}")
    return q[..., _WXYZ_TO_XYZW].astype(np.float32)


def xyzw_to_wxyz(quat_xyzw: np.ndarray) -> np.ndarray:
    """(..., 4) rerun (or scipy) quaternions [x, y, z, w] -> a new (..., 4) float64 array [w, x, y, z]."""
    q = np.asarray(quat_xyzw)
    if q.shape[-1:] != (4,):
        raise ValueError(f"expected quaternions of shape (..., 4), got {q.shape}")
    return q[..., _XYZW_TO_WXYZ].astype(float)

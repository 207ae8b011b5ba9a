"""Forward kinematics of a parsed BVH skeleton: joint world rotations and positions, over frames."""

from __future__ import annotations

import numpy as np

from ergosim.worker.bvh_euler import euler_to_matrix
from ergosim.worker.bvh_parse import BvhData

__all__ = ["global_rotations", "joint_positions"]

_AXIS = {"x": 0, "y": 1, "z": 2}


def global_rotations(data: BvhData, which: list[int] | None = None,
                     frames: slice | np.ndarray = slice(None)) -> dict[int, np.ndarray]:
    """World rotation (n, 3, 3) of each joint in ``which`` (and of its ancestors), in the file's axes, for the
    ``frames`` (a slice or indices) of ``data``."""
    motion = data.motion[frames]
    out: dict[int, np.ndarray] = {}

    def get(i: int) -> np.ndarray:
        if i not in out:
            j = data.joints[i]
            if j.parent >= 0 and not j.rotation_order:
                # parent @ I under BLAS: the parent's rotation with its negative zeros made positive
                out[i] = get(j.parent) + 0.0
                return out[i]
            local = euler_to_matrix(np.deg2rad(motion[:, j.rotation_columns]), j.rotation_order)
            local = np.broadcast_to(local, (motion.shape[0], 3, 3))
            out[i] = local.copy() if j.parent < 0 else get(j.parent) @ local
        return out[i]

    for i in range(len(data.joints)) if which is None else which:
        get(i)
    return out


def joint_positions(data: BvhData, frames: slice = slice(None)) -> np.ndarray:
    """(n, n_joints, 3) world positions of the joints [file units], position channels included."""
    motion = data.motion[frames]
    rot = global_rotations(data, frames=frames)
    pos = np.zeros((motion.shape[0], len(data.joints), 3))
    for i, j in enumerate(data.joints):
        local = np.broadcast_to(np.asarray(j.offset, dtype=float), (motion.shape[0], 3)).copy()
        for k, ch in enumerate(j.channels):
            if ch[1:].lower() == "position":
                # Position channels give the joint's translation; a file's OFFSET is then usually zero.
                local[:, _AXIS[ch[0].lower()]] = motion[:, j.first_channel + k]
        pos[:, i] = local if j.parent < 0 else pos[:, j.parent] + np.einsum(
            "nij,nj->ni", rot[j.parent], local)
    return pos

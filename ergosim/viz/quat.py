"""The one place where MuJoCo quaternions (w, x, y, z) become rerun quaternions (x, y, z, w)."""

from __future__ import annotations

import numpy as np

__all__ = ["wxyz_to_xyzw"]

_WXYZ_TO_XYZW = np.array([1, 2, 3, 0])


def wxyz_to_xyzw(quat_wxyz: np.ndarray) -> np.ndarray:
    """(..., 4) MuJoCo quaternions [w, x, y, z] -> a new (..., 4) float32 array [x, y, z, w] for rerun."""
    q = np.asarray(quat_wxyz)
    if q.shape[-1:] != (4,):
        raise ValueError(f"expected quaternions of shape (..., 4), got {q.shape}")
    return q[..., _WXYZ_TO_XYZW].astype(np.float32)

"""Batched 3x3 products with a constant matrix, in one BLAS call instead of one per frame.

``np.matmul`` of a (3, 3) matrix and (n, 3, 3) rotations calls BLAS once per frame; the same products as
one (3, 3) x (3, 3n) or (3n, 3) x (3, 3) matrix product give every entry the same three fused
multiply-adds in the same order, so the result is the same bit for bit, in a fraction of the time.
"""

from __future__ import annotations

import numpy as np

__all__ = ["const_times", "times_const"]


def const_times(c: np.ndarray, g: np.ndarray) -> np.ndarray:
    """``c @ g`` for a (3, 3) ``c`` and (..., 3, 3) ``g``: (..., 3, 3), the bits of np.matmul."""
    g = np.asarray(g, dtype=float)
    stack = g.reshape(-1, 3, 3)
    columns = np.ascontiguousarray(stack.transpose(1, 0, 2)).reshape(3, -1)  # [k, (frame, j)]
    out = (np.asarray(c, dtype=float) @ columns).reshape(3, -1, 3).transpose(1, 0, 2)
    return np.ascontiguousarray(out).reshape(g.shape)


def times_const(g: np.ndarray, c: np.ndarray) -> np.ndarray:
    """``g @ c`` for (..., 3, 3) ``g`` and a (3, 3) ``c``: (..., 3, 3), the bits of np.matmul."""
    g = np.asarray(g, dtype=float)
    rows = np.ascontiguousarray(g).reshape(-1, 3)
    return (rows @ np.asarray(c, dtype=float)).reshape(g.shape)

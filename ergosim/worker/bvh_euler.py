"""Rotation matrices from and to intrinsic Tait-Bryan (Euler) angles, vectorised over frames.

An order such as ``"ZXY"`` means ``R = Rz(a) @ Rx(b) @ Ry(c)``: rotate about z, then about the new x, then
about the newest y (intrinsic), which is how BVH channel lists and the human model's hinge chains compose.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SINGULAR_COS", "axis_rotation", "euler_to_matrix", "matrix_to_euler", "alternate_euler"]

_AXIS = {"X": 0, "Y": 1, "Z": 2}
# cos of the middle angle below which the first and last axes are taken to coincide (gimbal lock): within
# 0.0006 deg of +-90 deg, where 1e-6 deg of noise in a file would already move the outer angles by 0.1 deg.
SINGULAR_COS = 1e-5


def axis_rotation(axis: int, angle: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rotation by ``angle`` [rad] (shape (...)) about the coordinate axis 0, 1 or 2."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    j, k = (axis + 1) % 3, (axis + 2) % 3
    r = np.zeros(angle.shape + (3, 3))
    r[..., axis, axis] = 1.0
    r[..., j, j] = c
    r[..., k, k] = c
    r[..., k, j] = s
    r[..., j, k] = -s
    return r


def _support(axis: int) -> set[tuple[int, int]]:
    """Entries of a rotation about ``axis`` that are not structural zeros."""
    return {(axis, axis)} | {(i, j) for i in range(3) for j in range(3) if axis not in (i, j)}


_PAIR_TERMS = {
    (a, b): tuple(next((k for k in range(3) if (i, k) in _support(a) and (k, j) in _support(b)), None)
                  for i in range(3) for j in range(3))
    for a in range(3) for b in range(3) if a != b
}
"""Per pair of distinct axes (a, b): for each entry (i, j) of R_a @ R_b, the one k whose term
R_a[i, k] R_b[k, j] is not a structural zero (None: the entry is a structural zero)."""


def _pair_product(first: np.ndarray, b: int, angle: np.ndarray, a: int) -> np.ndarray:
    """``first @ axis_rotation(b, angle)`` for ``first`` a rotation about axis ``a != b``, elementwise.

    np.matmul hands these 3x3 products to BLAS, which sums each entry's three terms with fused multiply-adds
    from +0. Here every entry has one term that is not a structural zero, so that sum is the one product,
    rounded once, plus +0: the same bits, without a BLAS call per frame.
    """
    second = axis_rotation(b, angle)
    out = np.empty(np.broadcast_shapes(first.shape, second.shape))
    for e, k in enumerate(_PAIR_TERMS[(a, b)]):
        i, j = divmod(e, 3)
        if k is None:
            out[..., i, j] = 0.0
        else:
            np.add(first[..., i, k] * second[..., k, j], 0.0, out=out[..., i, j])
    return out


def euler_to_matrix(angles: np.ndarray, order: str) -> np.ndarray:
    """(..., 3, 3) from (..., len(order)) angles [rad]; ``order`` of up to 3 letters (empty -> identity).

    Bit for bit the product ``I @ R_1 @ R_2 @ R_3`` of np.matmul (BLAS, fused multiply-adds from +0), with
    the products that have one non-zero term per entry done elementwise: ``I @ R_1`` is R_1 with its
    negative zeros made positive, R_1 @ R_2 about distinct axes has one term per entry, and a rotation by
    an angle that is zero in every frame is the identity up to the sign of zeros.
    """
    angles = np.asarray(angles, dtype=float)
    axes = [_AXIS[ax] for ax in order.upper()]
    if not axes:
        return np.broadcast_to(np.eye(3), angles.shape[:-1] + (3, 3)).copy()
    r = axis_rotation(axes[0], angles[..., 0])
    r += 0.0
    for k in range(1, len(axes)):
        angle = angles[..., k]
        if not np.any(angle):
            r += 0.0
        elif k == 1 and axes[1] != axes[0]:
            r = _pair_product(r, axes[1], angle, axes[0])
        else:
            r = r @ axis_rotation(axes[k], angle)
    return r


def matrix_to_euler(r: np.ndarray, order: str, first_hint: np.ndarray | float = 0.0) -> np.ndarray:
    """(..., 3) angles [rad] with ``euler_to_matrix(angles, order) == r``, middle angle in [-pi/2, pi/2].

    ``order``: three distinct axes. At gimbal lock (middle angle +-90 deg) only a sum or difference of the
    first and last angles is defined; the first angle is then set to ``first_hint`` [rad] (broadcast to
    the frames) and the last one takes the rest, so the result still reproduces ``r`` exactly.
    """
    i, j, k = (_AXIS[a] for a in order.upper())
    if len({i, j, k}) != 3:
        raise ValueError(f"order {order!r} must name three distinct axes")
    s = 1.0 if (j - i) % 3 == 1 else -1.0  # +1 for cyclic orders (XYZ, YZX, ZXY)
    r = np.asarray(r, dtype=float)
    cos_b = np.hypot(r[..., i, i], r[..., i, j])
    b = np.arctan2(s * r[..., i, k], cos_b)
    a = np.arctan2(-s * r[..., j, k], r[..., k, k])
    c = np.arctan2(-s * r[..., i, j], r[..., i, i])
    lock = cos_b < SINGULAR_COS
    if np.any(lock):
        a = np.where(lock, np.broadcast_to(first_hint, a.shape), a)
        m = np.swapaxes(axis_rotation(i, a), -1, -2) @ r  # = R_j(b) R_k(c)
        c = np.where(lock, np.arctan2(s * m[..., j, i], m[..., j, j]), c)
    return np.stack([a, b, c], axis=-1)


def alternate_euler(angles: np.ndarray) -> np.ndarray:
    """The other Tait-Bryan solution of the same rotation: (a + pi, pi - b, c + pi), wrapped to (-pi, pi]."""
    a, b, c = np.moveaxis(np.asarray(angles, dtype=float), -1, 0)
    alt = np.stack([a + np.pi, np.pi - b, c + np.pi], axis=-1)
    return np.pi - np.mod(np.pi - alt, 2.0 * np.pi)

"""The human model's joint chains as rotations: canonical angles <-> relative segment rotations.

Each chain is the hinge sequence of :mod:`ergosim.human.joints` between two segments, in the body frame
(x forward, y left, z up; every segment frame equals the pelvis frame in the anatomical neutral posture).
A chain has three axes so that any relative rotation decomposes; a ``None`` name is a residual that the
human model does not have (elbow carrying angle, wrist axial twist, clavicle protraction and twist) and is
dropped. Left-arm rotations are mirrored through the sagittal plane (``M R M``, M = diag(1, -1, 1)) and use
the right-arm chains, so a left name has the same anatomical meaning as the right one.

Decomposition picks, per frame, the one of the two Euler solutions whose angles lie within (or closest to)
the ranges of motion of :data:`ergosim.human.joints.JOINT_SPECS`, and wraps each angle to its range. For
the shoulder the other solution always has a rotation outside -90..70 deg, so within the ranges of motion
the decomposition is unique except at shoulder abduction = +-90 deg exactly (gimbal lock of the
flexion -> abduction -> rotation chain: the arm points sideways and flexion and axial rotation turn about
the same axis). There the flexion of the last regular frame is kept and the rotation takes the rest.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from ergosim.human.joints import joint_spec
from ergosim.worker.bvh_euler import SINGULAR_COS, alternate_euler, euler_to_matrix, matrix_to_euler
from ergosim.worker.bvh_products import const_times, times_const

__all__ = ["Chain", "CHAINS", "MIRROR", "HeldFrame", "compose", "decompose", "mirror"]

MIRROR = np.diag([1.0, -1.0, 1.0])


class Chain(NamedTuple):
    """Three intrinsic rotations: about ``sign * axis`` of ``order``, angle ``name`` (None = residual)."""

    parent: str  # segment role the rotation is relative to
    child: str
    order: str
    signs: tuple[float, float, float]
    names: tuple[str | None, str | None, str | None]


CHAINS: dict[str, Chain] = {
    "trunk": Chain("pelvis", "thorax", "YXZ", (1, 1, 1), ("trunk_flexion", "trunk_lateral_bend",
                                                             "trunk_rotation")),
    "neck": Chain("thorax", "head", "YXZ", (1, 1, 1), ("neck_flexion", "neck_lateral_bend", "neck_rotation")),
    "clavicle": Chain("thorax", "clavicle", "XZY", (-1, 1, 1), ("shoulder_elevation", None, None)),
    "shoulder": Chain("clavicle", "upper_arm", "YXZ", (-1, -1, 1), ("shoulder_flexion", "shoulder_abduction",
                                                                    "shoulder_rotation")),
    "elbow": Chain("upper_arm", "forearm", "YXZ", (-1, 1, 1), ("elbow_flexion", None, "forearm_pronation")),
    "wrist": Chain("forearm", "hand", "XYZ", (1, 1, 1), ("wrist_flexion", "wrist_deviation", None)),
}
"""Trunk and neck are midline; the arm chains are for the right arm (mirror the left arm's rotations)."""


class HeldFrame(Exception):
    """A frame in gimbal lock among frames that are not consecutive: it holds the angle of the last regular
    frame before it, which only the consecutive frames have (see :func:`decompose`)."""


def mirror(r: np.ndarray) -> np.ndarray:
    """Reflect (..., 3, 3) rotations through the sagittal plane (left arm <-> right arm): M r M."""
    return times_const(const_times(MIRROR, r), MIRROR)


def compose(chain: Chain, angles: Mapping[str, np.ndarray | float], prefix: str = "") -> np.ndarray:
    """(n, 3, 3) relative rotation of ``chain`` from canonical ``angles`` [deg] (missing names are 0).

    ``prefix`` is "" or "left_" (then the result is the left arm's rotation, mirrored).
    """
    cols = [np.zeros(()) if n is None else np.asarray(angles.get(prefix + n, 0.0), dtype=float)
            for n in chain.names]
    cols = np.broadcast_arrays(*[np.atleast_1d(c) for c in cols])
    rad = np.deg2rad(np.stack(cols, axis=-1)) * np.asarray(chain.signs, dtype=float)
    r = euler_to_matrix(rad, chain.order)
    return mirror(r) if prefix else r


def _ranges(chain: Chain) -> np.ndarray:
    return np.array([joint_spec(n).range_deg if n else (0.0, 0.0) for n in chain.names])


def _violation(deg: np.ndarray, ranges: np.ndarray) -> np.ndarray:
    return np.maximum(ranges[:, 0] - deg, 0.0) + np.maximum(deg - ranges[:, 1], 0.0)


def _wrap(deg: np.ndarray, ranges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each angle's representative (mod 360) closest to its range, and the summed range violation.

    deg: (n, 3) [deg]; ranges: (3, 2) [deg]. Returns (n, 3) angles and (n,) violations [deg].
    """
    best = np.mod(deg + 180.0, 360.0) - 180.0
    viol = _violation(best, ranges)
    # Only an angle outside its range can be bettered by base -/+ 360; ties keep the first candidate,
    # the (-180, 180] representative.
    rows, cols = np.nonzero(viol > 0.0)
    if rows.size:
        base, lo, hi = best[rows, cols], ranges[cols, 0], ranges[cols, 1]
        pick, low = base, viol[rows, cols]
        for cand in (base - 360.0, base + 360.0):
            v = np.maximum(lo - cand, 0.0) + np.maximum(cand - hi, 0.0)
            better = v < low
            pick, low = np.where(better, cand, pick), np.where(better, v, low)
        best[rows, cols], viol[rows, cols] = pick, low
    return best, (viol[..., 0] + viol[..., 1]) + viol[..., 2]


def _forward_fill(values: np.ndarray, valid: np.ndarray, default: float = 0.0) -> np.ndarray:
    idx = np.where(valid, np.arange(valid.size), -1)
    idx = np.maximum.accumulate(idx)
    return np.where(idx >= 0, values[np.maximum(idx, 0)], default)


def decompose(chain: Chain, r: np.ndarray, prefix: str = "",
              consecutive: bool = True) -> dict[str, np.ndarray]:
    """Canonical angles [deg], name -> (n,), of the (n, 3, 3) relative rotations ``r`` of ``chain``.

    ``consecutive``: False if the n frames are a sample of a recording; then a frame in gimbal lock raises
    :class:`HeldFrame` instead of taking the angle of the sample's previous frame.
    """
    r = mirror(r) if prefix else np.asarray(r, dtype=float)
    signs = np.asarray(chain.signs, dtype=float)
    ranges = _ranges(chain)
    euler = matrix_to_euler(r, chain.order)
    best, viol1 = _wrap(np.rad2deg(euler * signs), ranges)
    # The other solution is taken where it violates the ranges by 1e-9 deg less, so only where this one
    # violates them by more than that.
    frames = np.flatnonzero(viol1 > 1e-9)
    if frames.size:
        two, viol2 = _wrap(np.rad2deg(alternate_euler(euler[frames]) * signs), ranges)
        take = viol2 < viol1[frames] - 1e-9
        best[frames[take]] = two[take]
    lock = np.abs(np.cos(euler[:, 1])) < SINGULAR_COS
    if lock.any():
        if not consecutive:
            raise HeldFrame(f"{chain.child} in gimbal lock")
        # Gimbal lock: hold the first angle of the last regular frame (continuity in a recording); the
        # other solution would only move it by 180 deg, so it is not considered.
        hint = np.deg2rad(_forward_fill(best[:, 0], ~lock)) * signs[0]
        held, _ = _wrap(np.rad2deg(matrix_to_euler(r, chain.order, hint) * signs), ranges)
        best = np.where(lock[:, None], held, best)
    return {prefix + n: best[:, k] for k, n in enumerate(chain.names) if n is not None}

"""Where the head points: the gaze error to a point, beyond what the eyes take, and its Jacobian.

The head looks along the eye site's x axis. A point p seen from the eyes e, in the head's frame R, is
v = R^T (p - e); its azimuth (yaw, > 0 to the left) and elevation (pitch, > 0 below) are the angles the
gaze must turn. The eyes take the first ``eye_side`` of yaw and ``eye_down`` / ``eye_up`` of pitch; the rest,
the *excess*, is what the neck, the trunk and the stance must turn (the IK's gaze task).

For a joint increment dq: dv = -R^T J_p dq + [v]x R^T J_r dq, with J_p, J_r the eye site's translational and
rotational Jacobians (a world-frame rotation w of the head turns v by -R^T (w x d) = [v]x R^T w).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["gaze_angles", "gaze_excess", "gaze_jacobian", "look_excess"]


def gaze_angles(v: np.ndarray) -> tuple[float, float]:
    """(yaw, pitch) [rad] of a direction ``v`` (3,) in the head frame (x forward, y left, z up); pitch > 0
    looks down."""
    return math.atan2(v[1], v[0]), math.atan2(-v[2], math.hypot(v[0], v[1]))


def gaze_excess(point: np.ndarray, eye: np.ndarray, rot: np.ndarray, jacp: np.ndarray, jacr: np.ndarray,
                side: float, down: float, up: float) -> tuple[np.ndarray, np.ndarray]:
    """The gaze angles the eyes cannot take, (2,) [rad] (yaw, pitch), and their Jacobian (2, nv).

    ``eye`` (3,) and ``rot`` (3, 3): the eye site's position and orientation; ``jacp``, ``jacr`` (3, nv): its
    Jacobians; ``side``, ``down``, ``up`` [rad]: the eyes' share. A component within the eyes' share is 0
    with a zero Jacobian row.
    """
    v, excess = look_excess(point, eye, rot, side, down, up)
    return excess, gaze_jacobian(v, excess, rot, jacp, jacr)


def look_excess(point: np.ndarray, eye: np.ndarray, rot: np.ndarray, side: float, down: float,
                up: float) -> tuple[np.ndarray, np.ndarray]:
    """The direction to ``point`` in the head frame, (3,), and the gaze excess (2,) [rad] of
    :func:`gaze_excess` without its Jacobian (what a line search needs)."""
    v = rot.T @ (point - eye)
    yaw, pitch = gaze_angles(v)
    return v, np.array([yaw - min(max(yaw, -side), side), pitch - min(max(pitch, -up), down)])


def gaze_jacobian(v: np.ndarray, excess: np.ndarray, rot: np.ndarray, jacp: np.ndarray,
                  jacr: np.ndarray) -> np.ndarray:
    """The Jacobian (2, nv) of :func:`gaze_excess` from :func:`look_excess`'s ``v`` and ``excess``."""
    jac = np.zeros((2, jacp.shape[1]))
    if excess[0] == 0.0 and excess[1] == 0.0:
        return jac
    dv = -rot.T @ jacp
    w = rot.T @ jacr
    v0, v1, v2 = v
    # [v]x R^T J_r column by column, each row written out as np.cross computes it (the same bits, without
    # its axis bookkeeping)
    dv[0] += v1 * w[2] - v2 * w[1]
    dv[1] += v2 * w[0] - v0 * w[2]
    rho2 = v0 * v0 + v1 * v1
    rho = math.sqrt(rho2)
    if excess[0] != 0.0 and rho2 > 1e-12:
        jac[0] = (-v1 * dv[0] + v0 * dv[1]) / rho2
    if excess[1] != 0.0 and rho > 1e-9:
        dv[2] += v0 * w[1] - v1 * w[0]  # only the pitch needs the vertical
        n2 = rho2 + v2 * v2
        jac[1] = (v2 * (v0 * dv[0] + v1 * dv[1]) / rho - rho * dv[2]) / n2
    return jac

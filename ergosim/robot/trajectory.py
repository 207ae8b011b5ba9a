"""Cartesian waypoints -> joint trajectories sampled at the physics step.

Each segment moves the TCP on a straight line (orientation by geodesic interpolation) with a trapezoidal
speed profile capped at ``speed`` (the paper's conservative 0.05 m/s end-effector speed, §7.2) and slowed
further wherever a joint would exceed its URDF velocity limit. IK runs once per ``sample`` metres at
planning time, warm-started along the line, so execution is only a table look-up per physics step.
Frames: the robot base frame (see :class:`BaseFrame` for world conversions).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import PandaKinematics

__all__ = ["MotionLimits", "Pose", "BaseFrame", "PathError", "segment_trajectory", "joint_trajectory",
           "transit_trajectory", "trapezoid"]


@dataclass(frozen=True)
class MotionLimits:
    """``speed`` [m/s] and ``accel`` [m/s^2] of the TCP; ``angular_speed`` [rad/s]; joints use at most
    ``joint_speed_fraction`` of their URDF velocity limits; ``sample`` [m] between IK solutions;
    ``max_joint_step`` [rad] largest joint change between two samples (a larger one means the IK
    switched branch and the straight line is not followable)."""

    speed: float = 0.05
    accel: float = 0.25
    angular_speed: float = 0.5
    joint_speed_fraction: float = 0.8
    sample: float = 0.01
    sample_angle: float = 0.05
    max_joint_step: float = 0.2


class Pose(NamedTuple):
    """Position (3,) [m] and rotation matrix (3, 3) in one frame."""

    pos: np.ndarray
    rot: np.ndarray


class PathError(Exception):
    """Raised inside planning when a segment has no IK solution; the skill turns it into a status."""

    def __init__(self, message: str, pos_error: float = float("nan")) -> None:
        super().__init__(message)
        self.pos_error = pos_error


class BaseFrame:
    """The robot base pose in the world: world <-> base conversions of points and rotations."""

    def __init__(self, pos: np.ndarray, rot: np.ndarray) -> None:
        self.pos = np.asarray(pos, dtype=float)
        self.rot = np.asarray(rot, dtype=float)

    def to_base(self, pose: Pose) -> Pose:
        return Pose(self.rot.T @ (pose.pos - self.pos), self.rot.T @ pose.rot)

    def to_world(self, pose: Pose) -> Pose:
        return Pose(self.rot @ pose.pos + self.pos, self.rot @ pose.rot)


def trapezoid(distance: float, speed: float, accel: float, dt: float) -> np.ndarray:
    """Normalised path parameter s(t) in [0, 1] at t = 0, dt, 2 dt, ... of a trapezoidal (or triangular)
    speed profile over ``distance`` with peak ``speed`` and acceleration ``accel``; ends exactly at 1."""
    if distance <= 0:
        return np.array([1.0])
    t_acc = speed / accel
    if accel * t_acc**2 >= distance:  # triangular
        t_acc = np.sqrt(distance / accel)
        speed = accel * t_acc
    t_total = 2 * t_acc + (distance - accel * t_acc**2) / speed
    t = np.arange(1, int(np.ceil(t_total / dt)) + 1) * dt
    t = np.minimum(t, t_total)
    s = np.where(t < t_acc, 0.5 * accel * t**2,
                 np.where(t < t_total - t_acc, 0.5 * accel * t_acc**2 + speed * (t - t_acc),
                          distance - 0.5 * accel * (t_total - t) ** 2))
    return np.clip(s / distance, 0.0, 1.0)


def segment_trajectory(kin: PandaKinematics, q_start: np.ndarray, start: Pose, goal: Pose,
                       limits: MotionLimits, dt: float, speed: float | None = None) -> np.ndarray:
    """(n, 7) joint targets [rad], one per physics step, moving the TCP straight from ``start`` to ``goal``
    (base frame). ``q_start`` must realise ``start``. Raises :class:`PathError` if the line leaves the
    workspace or the joint limits."""
    speed = limits.speed if speed is None else speed
    dist = float(np.linalg.norm(goal.pos - start.pos))
    rot_log = pin.log3(start.rot.T @ goal.rot)
    angle = float(np.linalg.norm(rot_log))
    k = max(1, int(np.ceil(dist / limits.sample)), int(np.ceil(angle / limits.sample_angle)))
    knots = np.linspace(0.0, 1.0, k + 1)
    qs = np.empty((k + 1, kin.nq))
    qs[0] = q_start
    for i in range(1, k + 1):
        s = knots[i]
        pos = start.pos + s * (goal.pos - start.pos)
        rot = start.rot @ pin.exp3(s * rot_log)
        # intermediate knots of a transit need not be exact (1 mm, 0.5 deg); the segment's end does
        loose = i < k
        res = solve_ik(kin, pos, rot, qs[i - 1], q_pref=kin.home, max_iter=100,
                       tol_pos=1e-3 if loose else 2e-4, tol_rot_deg=0.5 if loose else 0.05)
        if not res.ok:
            raise PathError(f"no IK solution at {np.round(pos, 3).tolist()} (base frame), "
                            f"{res.pos_error * 1000:.0f} mm and {res.rot_error_deg:.0f} deg short",
                            res.pos_error)
        if np.max(np.abs(res.q - qs[i - 1])) > limits.max_joint_step:
            raise PathError(f"the straight line near {np.round(pos, 3).tolist()} (base frame) needs a "
                            f"joint flip of {np.max(np.abs(res.q - qs[i - 1])):.2f} rad")
        qs[i] = res.q
    # time scaling: Cartesian speed, angular speed, and joint velocity limits
    d_eff = max(dist, angle * speed / limits.angular_speed)
    joint_span = np.max(np.abs(np.diff(qs, axis=0)) * k / (kin.velocity * limits.joint_speed_fraction))
    # the peak of a trapezoid is `speed`; a joint moving joint_span * ds/dt must stay under its limit
    peak = speed / d_eff if d_eff > 0 else np.inf
    if joint_span * peak > 1.0:
        speed = speed / (joint_span * peak)
    s = trapezoid(max(d_eff, 1e-9), speed, limits.accel * speed / max(limits.speed, 1e-9), dt)
    return np.stack([np.interp(s, knots, qs[:, j]) for j in range(kin.nq)], axis=1)


def joint_trajectory(q_start: np.ndarray, q_goal: np.ndarray, kin: PandaKinematics, limits: MotionLimits,
                     dt: float) -> np.ndarray:
    """(n, 7) joint-space move (same trapezoid shape for every joint) within the joint velocity limits."""
    delta = np.asarray(q_goal) - np.asarray(q_start)
    span = float(np.max(np.abs(delta) / (kin.velocity * limits.joint_speed_fraction * 0.25)))
    if span <= 0:
        return np.asarray(q_goal, dtype=float)[None, :]
    s = trapezoid(span, 1.0, 4.0, dt)
    return np.asarray(q_start) + s[:, None] * delta


def transit_trajectory(kin: PandaKinematics, q_start: np.ndarray, q_goal: np.ndarray, limits: MotionLimits,
                       dt: float, speed: float | None = None, samples: int = 40) -> tuple[np.ndarray, float]:
    """(n, 7) joint-space move from ``q_start`` to ``q_goal`` timed so the TCP's path (not a straight line)
    runs at most at ``speed`` [m/s] and every joint within its velocity limit. Also returns the lowest
    TCP height on the way [m, base frame], so a caller can reject a move that dips."""
    speed = limits.speed if speed is None else speed
    q_start, q_goal = np.asarray(q_start, dtype=float), np.asarray(q_goal, dtype=float)
    knots = np.linspace(0.0, 1.0, samples + 1)
    pts = np.array([kin.fk(q_start + s * (q_goal - q_start))[0] for s in knots])
    length = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    delta = q_goal - q_start
    # a joint's peak speed is |delta| * peak(ds/dt); the trapezoid's peak ds/dt is speed / length
    joint_length = float(np.max(np.abs(delta) / (kin.velocity * limits.joint_speed_fraction))) * speed
    dist = max(length, joint_length, 1e-9)
    s = trapezoid(dist, speed, limits.accel * speed / max(limits.speed, 1e-9), dt)
    return q_start + s[:, None] * delta, float(pts[:, 2].min())

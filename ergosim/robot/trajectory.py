"""Cartesian waypoints -> joint trajectories sampled at the physics step.

Every segment is one of two kinds, each with its own TCP speed cap (:class:`MotionLimits`):

- ``contact``: motion where the gripper or the held part is about to touch, or just left, something -- the
  final approach to a grasp, the lift-off, the approach to a place or an insertion and the insertion
  itself, the retreat, the final approach into the handover pose next to the worker. It runs at the paper's
  conservative 0.05 m/s (§7.2).
- ``transit``: free-space motion between those, at the reduced speed of ISO 10218-1:2011 §5.6 (TCP at most
  250 mm/s), the speed limit of collaborative operation next to a person.

A straight segment moves the TCP on a line (orientation by geodesic interpolation) with a trapezoidal speed
profile, slowed further wherever a joint would exceed its URDF velocity limit. IK runs once per ``sample``
metres at planning time, warm-started along the line, so execution is only a table look-up per physics
step. A joint-space transit is re-timed along the TCP's own (curved) path, so its TCP speed holds the cap
too. Frames: the robot base frame (see :class:`BaseFrame` for world conversions).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import ArmKinematics
from ergosim.robot.time_scaling import speed_profile, trapezoid

__all__ = ["SEGMENT_KINDS", "CONTACT_SPEED", "TRANSIT_SPEED", "SpeedLimit", "MotionLimits", "Pose",
           "BaseFrame", "PathError",
           "line_trajectory", "segment_trajectory", "joint_trajectory", "transit_trajectory", "trapezoid"]

SEGMENT_KINDS = ("contact", "transit")
"""The two kinds of robot motion segment, each with its own speed cap (module docstring)."""

CONTACT_SPEED = 0.05
"""Contact-critical TCP speed [m/s]: the paper's conservative 0.05 m/s (§7.2)."""
TRANSIT_SPEED = 0.25
"""Free-space TCP speed [m/s]: ISO 10218-1:2011 §5.6 reduced speed, TCP at most 250 mm/s."""


class SpeedLimit(NamedTuple):
    """TCP caps of one segment kind: ``speed`` [m/s], ``accel`` [m/s^2], ``angular_speed`` [rad/s],
    ``angular_accel`` [rad/s^2]."""

    speed: float
    accel: float
    angular_speed: float
    angular_accel: float


@dataclass(frozen=True)
class MotionLimits:
    """TCP caps per segment kind and joint limits.

    ``speed``/``accel``/``angular_speed``: contact-critical segments [m/s, m/s^2, rad/s];
    ``transit_speed``/``transit_accel``: free-space transits, whose angular speed is capped so that a point
    ``sweep_radius`` [m] from the TCP moves and accelerates at most at ``transit_speed`` and
    ``transit_accel`` (and within the robot's Cartesian limits ``max_rotation`` [rad/s] and
    ``max_rotation_accel`` [rad/s^2], :meth:`for_robot`);
    a contact-critical rotation ramps up in the same time as the contact speed. Joints use at most
    ``joint_speed_fraction`` of their URDF velocity limits; ``sample`` [m] and ``sample_angle`` [rad] between
    IK solutions of a straight segment; ``max_joint_step`` [rad] largest joint change between two samples (a
    larger one means the IK switched branch and the straight line is not followable)."""

    speed: float = CONTACT_SPEED  # paper §7.2, the conservative 0.05 m/s
    accel: float = 0.25  # assumed: a 0.2 s ramp to the contact speed
    angular_speed: float = 0.5  # assumed
    transit_speed: float = TRANSIT_SPEED  # ISO 10218-1:2011 §5.6 reduced speed, <= 250 mm/s
    transit_accel: float = 1.0  # assumed; well within the bundled robots' limits
    sweep_radius: float = 0.25  # assumed: the hand and a held part (profiles 0.3 m, held mid-way) lie within
    joint_speed_fraction: float = 0.8
    sample: float = 0.01
    sample_angle: float = 0.05
    max_joint_step: float = 0.2
    max_rotation: float = math.inf
    max_rotation_accel: float = math.inf

    def for_robot(self, robot) -> MotionLimits:
        """These limits within ``robot``'s (a :class:`~ergosim.robot.robot_model.RobotModel`) Cartesian
        rotation limits."""
        return dataclasses.replace(self, max_rotation=robot.max_rotation,
                                   max_rotation_accel=robot.max_rotation_accel)

    def limit(self, kind: str) -> SpeedLimit:
        """The TCP caps of a ``kind`` segment (one of :data:`SEGMENT_KINDS`)."""
        if kind == "contact":
            return SpeedLimit(self.speed, self.accel, self.angular_speed,
                              self.accel * self.angular_speed / self.speed)
        if kind == "transit":
            return SpeedLimit(self.transit_speed, self.transit_accel,
                              min(self.transit_speed / self.sweep_radius, self.max_rotation),
                              min(self.transit_accel / self.sweep_radius, self.max_rotation_accel))
        raise ValueError(f"segment kind must be one of {', '.join(SEGMENT_KINDS)}, got {kind!r}")


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


def _timed(knots: np.ndarray, times: np.ndarray, lengths: np.ndarray, angles: np.ndarray,
           accel: np.ndarray, angular_accel: np.ndarray, dt: float) -> np.ndarray:
    """Path parameter s(t) at every physics step over ``knots`` (k + 1,) in [0, 1]. Interval i takes at
    least ``times[i]`` [s] (the slowest of its TCP, rotation and joint limits); its TCP moves ``lengths[i]``
    [m] and turns ``angles[i]`` [rad], accelerating at most ``accel[i]`` [m/s^2] and ``angular_accel[i]``
    [rad/s^2]. A pure null-space move (the TCP still) ramps up in 0.2 s (assumed)."""
    ds = np.diff(knots)
    caps = ds / np.maximum(times, 1e-12)
    with np.errstate(divide="ignore"):
        acc = np.minimum(np.where(lengths > 1e-12, accel * ds / lengths, np.inf),
                         np.where(angles > 1e-12, angular_accel * ds / angles, np.inf))
    acc = np.where(np.isfinite(acc), acc, caps / 0.2)
    return speed_profile(ds, caps, acc, dt)


def _line_ik(kin: ArmKinematics, q_start: np.ndarray, start: Pose, goal: Pose, rot_log: np.ndarray,
             knots: np.ndarray, limits: MotionLimits) -> tuple[np.ndarray, np.ndarray]:
    """IK along the line at ``knots`` (warm-started knot to knot): the knots used and (n, 7) solutions.

    A joint change over ``limits.max_joint_step`` between two knots is split in half, down to an eighth of
    the spacing: where the arm only moves steeply it shrinks with the spacing, a switch of IK branch does
    not (:class:`PathError`)."""
    done, qs = [0.0], [np.asarray(q_start, dtype=float)]
    todo = list(knots[1:][::-1])  # a stack, next knot last
    shortest = float(np.min(np.diff(knots))) / 8 if len(knots) > 1 else 0.0
    while todo:
        s = todo[-1]
        pos = start.pos + s * (goal.pos - start.pos)
        rot = start.rot @ pin.exp3(s * rot_log)
        # intermediate knots of a transit need not be exact (1 mm, 0.5 deg); the segment's end does
        loose = s < 1.0
        tol = dict(tol_pos=1e-3 if loose else 2e-4, tol_rot_deg=0.5 if loose else 0.05)
        res = solve_ik(kin, pos, rot, qs[-1], q_pref=kin.ready, max_iter=100, **tol)
        if not res.ok:  # the pull towards home can pin a joint at its limit near the workspace's edge
            res = solve_ik(kin, pos, rot, qs[-1], q_pref=qs[-1], max_iter=100, **tol)
        if not res.ok:
            raise PathError(f"no IK solution at {np.round(pos, 3).tolist()} (base frame), "
                            f"{res.pos_error * 1000:.0f} mm and {res.rot_error_deg:.0f} deg short",
                            res.pos_error)
        jump = float(np.max(np.abs(res.q - qs[-1])))
        if jump > limits.max_joint_step:
            if s - done[-1] > shortest * 1.001:
                todo.append(0.5 * (done[-1] + s))
                continue
            raise PathError(f"the straight line near {np.round(pos, 3).tolist()} (base frame) needs a "
                            f"joint flip of {jump:.2f} rad")
        done.append(s)
        qs.append(res.q)
        todo.pop()
    return np.array(done), np.array(qs)


def line_trajectory(kin: ArmKinematics, q_start: np.ndarray, start: Pose, goal: Pose, limits: MotionLimits,
                    dt: float, kind: str = "contact", slow_first: float = 0.0,
                    slow_last: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(n, 7) joint targets [rad], one per physics step, moving the TCP straight from ``start`` to ``goal``
    (base frame), and (n,) True where a step is contact-critical.

    The line runs within the caps of a ``kind`` segment, except its first ``slow_first`` and last
    ``slow_last`` metres, which are contact-critical: the TCP brakes to the contact speed before them and
    does not stop in between. ``q_start`` must realise ``start``. Raises :class:`PathError` if the line
    leaves the workspace or the joint limits."""
    dist = float(np.linalg.norm(goal.pos - start.pos))
    rot_log = pin.log3(start.rot.T @ goal.rot)
    angle = float(np.linalg.norm(rot_log))
    k = max(1, int(np.ceil(dist / limits.sample)), int(np.ceil(angle / limits.sample_angle)))
    knots = np.linspace(0.0, 1.0, k + 1)
    # contact zones as fractions of the line; their edges become knots so that each interval has one kind
    if kind == "contact":
        lo, hi = 1.0, 0.0  # all of it
    elif dist > 0:
        lo = min(slow_first / dist, 1.0)
        hi = max(1.0 - slow_last / dist, lo)
    else:
        lo, hi = 0.0, 1.0  # a turn on the spot has no contact zone
    knots = np.unique(np.concatenate([knots, [x for x in (lo, hi) if 0.0 < x < 1.0]]))
    knots, qs = _line_ik(kin, q_start, start, goal, rot_log, knots, limits)
    mid = 0.5 * (knots[:-1] + knots[1:])
    slow = (mid < lo) | (mid > hi)
    fast = limits.limit(kind)
    contact = limits.limit("contact")
    speed = np.where(slow, contact.speed, fast.speed)
    accel = np.where(slow, contact.accel, fast.accel)
    angular = np.where(slow, contact.angular_speed, fast.angular_speed)
    angular_accel = np.where(slow, contact.angular_accel, fast.angular_accel)
    ds = np.diff(knots)
    joint_time = np.max(np.abs(np.diff(qs, axis=0)) / (kin.velocity * limits.joint_speed_fraction), axis=1)
    times = np.maximum.reduce([dist * ds / speed, angle * ds / angular, joint_time])
    s = _timed(knots, times, dist * ds, angle * ds, accel, angular_accel, dt)
    traj = np.stack([np.interp(s, knots, qs[:, j]) for j in range(kin.nq)], axis=1)
    in_slow = ((s < lo + 1e-12) & (lo > 0)) | ((s > hi - 1e-12) & (hi < 1))
    return traj, in_slow


def segment_trajectory(kin: ArmKinematics, q_start: np.ndarray, start: Pose, goal: Pose,
                       limits: MotionLimits, dt: float, kind: str = "contact") -> np.ndarray:
    """(n, 7) joint targets [rad], one per physics step, moving the TCP straight from ``start`` to ``goal``
    (base frame) within the caps of a ``kind`` segment (:func:`line_trajectory` with one speed)."""
    return line_trajectory(kin, q_start, start, goal, limits, dt, kind)[0]


def joint_trajectory(q_start: np.ndarray, q_goal: np.ndarray, kin: ArmKinematics, limits: MotionLimits,
                     dt: float) -> np.ndarray:
    """(n, 7) joint-space move (same trapezoid shape for every joint) at a quarter of the joint velocity
    limits used elsewhere; the TCP speed is not capped (:func:`transit_trajectory` caps it)."""
    delta = np.asarray(q_goal) - np.asarray(q_start)
    span = float(np.max(np.abs(delta) / (kin.velocity * limits.joint_speed_fraction * 0.25)))
    if span <= 0:
        return np.asarray(q_goal, dtype=float)[None, :]
    s = trapezoid(span, 1.0, 4.0, dt)
    return np.asarray(q_start) + s[:, None] * delta


def transit_trajectory(kin: ArmKinematics, q_start: np.ndarray, q_goal: np.ndarray, limits: MotionLimits,
                       dt: float, kind: str = "transit", samples: int = 40) -> tuple[np.ndarray, float]:
    """(n, 7) joint-space move from ``q_start`` to ``q_goal`` timed along the TCP's own path (not a straight
    line) so that its speed and angular speed stay within the caps of a ``kind`` segment and every joint
    within its velocity limit. Also returns the lowest TCP height on the way [m, base frame], so a caller
    can reject a move that dips.

    The joint interpolation is cut into ``samples`` equal steps; each step takes at least the longest of
    its TCP length over the speed cap, its rotation over the angular cap and its joint changes over the
    joint limits, so the TCP slows where the arm sweeps it fast."""
    cap = limits.limit(kind)
    q_start, q_goal = np.asarray(q_start, dtype=float), np.asarray(q_goal, dtype=float)
    delta = q_goal - q_start
    knots = np.linspace(0.0, 1.0, samples + 1)
    poses = [kin.fk(q_start + s * delta) for s in knots]
    pts = np.array([p for p, _ in poses])
    low = float(pts[:, 2].min())
    if not np.any(delta):
        return q_goal[None, :], low
    step_len = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    step_angle = np.array([np.linalg.norm(pin.log3(a.T @ b)) for (_, a), (_, b) in zip(poses, poses[1:])])
    step_joint = float(np.max(np.abs(delta) / (kin.velocity * limits.joint_speed_fraction))) / samples
    times = np.maximum.reduce([step_len / cap.speed, step_angle / cap.angular_speed,
                               np.full(samples, step_joint)])
    s = _timed(knots, times, step_len, step_angle, np.full(samples, cap.accel),
               np.full(samples, cap.angular_accel), dt)
    return q_start + s[:, None] * delta, low

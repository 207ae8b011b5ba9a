"""Joint trajectories of a skill: a robot's moves through world waypoints, planned before the first step.

A :class:`Motion` is (n, dof) joint targets, one per physics step, with the phase of each run of rows
(:data:`~ergosim.robot.status.SKILL_PHASES`). :class:`MotionPlanner` chains moves through
:class:`Waypoint` s -- straight TCP lines and joint-space transits, each at the speed cap of its kind
(:mod:`ergosim.robot.trajectory`) -- and plans the way home and the retreats. It reads the robot's
kinematics and base frame and nothing of the scene's state.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from ergosim.robot.ik import solve_ik
from ergosim.robot.kinematics import ArmKinematics
from ergosim.robot.skill_params import SkillParams
from ergosim.robot.trajectory import BaseFrame, PathError, Pose, line_trajectory, transit_trajectory

__all__ = ["Motion", "Waypoint", "MotionPlanner", "UP", "is_up"]

UP = np.array([0.0, 0.0, 1.0])
"""The world's vertical (z up)."""
_SAME_POS = 1e-6  # m: a waypoint this close to where the TCP is, with the same rotation, is skipped
_SAME_ROT = 1e-9
_SAME_Q = 1e-9  # rad: joint configurations this close need no move between them
_VERTICAL = 1e-9  # a direction within this of UP (in its z component) goes straight up


def is_up(direction: np.ndarray) -> bool:
    """``direction`` (a unit vector, world) points straight up."""
    return bool(direction[2] > 1 - _VERTICAL)


class Motion(NamedTuple):
    """A planned motion: (n, dof) joint targets [rad], one per physics step, and the (phase, steps) spans of
    its rows in order."""

    q: np.ndarray
    spans: tuple[tuple[str, int], ...]

    @property
    def end(self) -> np.ndarray:
        return self.q[-1]

    @property
    def steps(self) -> int:
        """Physics steps it takes."""
        return len(self.q)

    def then(self, other: Motion) -> Motion:
        return Motion(np.concatenate([self.q, other.q]), self.spans + other.spans)

    def phases(self) -> list[str]:
        """The phase of every row (n,)."""
        return [ph for ph, n in self.spans for _ in range(n)]

    @classmethod
    def still(cls, q: np.ndarray, phase: str) -> Motion:
        """One step holding ``q``."""
        return cls(np.asarray(q, dtype=float)[None, :], ((phase, 1),))


class Waypoint(NamedTuple):
    """Where the TCP goes next (world pose) and how: ``mode`` "line" (straight) or "joint" (joint-space);
    ``kind`` of segment; a line's first ``slow_first`` and last ``slow_last`` metres are contact-critical."""

    pose: Pose
    mode: str = "line"
    kind: str = "transit"
    slow_first: float = 0.0
    slow_last: float = 0.0


def _runs(labels: np.ndarray) -> list[tuple[str, int]]:
    """(label, length) of each run of equal consecutive ``labels`` (n,)."""
    cut = np.flatnonzero(labels[1:] != labels[:-1]) + 1
    edges = np.concatenate([[0], cut, [len(labels)]])
    return [(str(labels[i]), int(j - i)) for i, j in zip(edges[:-1], edges[1:])]


class MotionPlanner:
    """Plans one robot's moves: ``kin`` its kinematics (limits, home pose), ``base`` its base frame in the
    world, ``params`` the skill parameters (speed caps in ``params.limits``), ``dt`` the physics step [s]."""

    def __init__(self, kin: ArmKinematics, base: BaseFrame, params: SkillParams, dt: float) -> None:
        self.kin = kin
        self.base = base
        self.params = params
        self.dt = dt

    def through(self, q0: np.ndarray, waypoints: Sequence[Waypoint], phase: str | None = None) -> Motion:
        """Chain moves through world ``waypoints`` from configuration ``q0``.

        "line": the TCP goes straight (approach, descent, insertion, lift). "joint": a joint-space transit
        to an IK solution near the ready pose (large moves), replaced by a straight line if the TCP would
        dip more than ``dip_tolerance`` below both ends. Each move keeps the speed caps of its kind; its
        steps are labelled ``contact`` where contact-critical, else with ``phase`` (default: the kind).
        Raises PathError."""
        q = np.asarray(q0, dtype=float)
        start = Pose(*self.kin.fk(q))
        rows, spans = [], []
        for way in waypoints:
            goal = self.base.to_base(way.pose)
            if np.linalg.norm(goal.pos - start.pos) < _SAME_POS and np.allclose(goal.rot, start.rot,
                                                                                atol=_SAME_ROT):
                continue
            traj = None
            label = "contact" if way.kind == "contact" else (phase or way.kind)
            if way.mode == "joint":
                res = solve_ik(self.kin, goal.pos, goal.rot, self.kin.ready, seeds=[q, *self._wrist_seeds(q)])
                if not res.ok:
                    raise PathError(f"no IK solution at {np.round(goal.pos, 3).tolist()} (base frame), "
                                    f"{res.pos_error * 1000:.0f} mm and {res.rot_error_deg:.0f} deg short",
                                    res.pos_error)
                traj = self.joint_move(q, res.q, start.pos[2], goal.pos[2], way.kind)
                if traj is not None:
                    spans.append((label, len(traj)))
            if traj is None:
                traj, slow = line_trajectory(self.kin, q, start, goal, self.params.limits, self.dt, way.kind,
                                             way.slow_first, way.slow_last)
                spans += _runs(np.where(slow, "contact", label))
            rows.append(traj)
            q, start = traj[-1], goal
        if not rows:
            return Motion.still(q, phase or "transit")
        return Motion(np.concatenate(rows), tuple(spans))

    def _wrist_seeds(self, q: np.ndarray) -> list[np.ndarray]:
        """``q`` with the last (wrist) joint wound by each of ``wrist_turns``: the IK from home and from ``q``
        stalls when the goal's hand yaw needs the wrist unwound past its limit the other way round."""
        out = []
        for turn in self.params.wrist_turns:
            seed = np.array(q, dtype=float)
            seed[-1] = np.clip(seed[-1] + turn, self.kin.lower[-1], self.kin.upper[-1])
            out.append(seed)
        return out

    def joint_move(self, q: np.ndarray, q_goal: np.ndarray, z0: float, z1: float,
                   kind: str) -> np.ndarray | None:
        """A joint-space move, or None if its TCP dips more than ``dip_tolerance`` below both ends
        (base-frame z [m])."""
        traj, low = transit_trajectory(self.kin, q, q_goal, self.params.limits, self.dt, kind)
        return None if low < min(z0, z1) - self.params.dip_tolerance else traj

    def home(self, q_from: np.ndarray, tcp_from: Pose, slow_first: float = 0.0) -> Motion:
        """Up by ``approach`` (at least to the home TCP's height), its first ``slow_first`` [m] at the
        contact speed, then a joint-space transit onto the ready configuration; labelled ``home`` where not
        contact-critical."""
        p = self.params
        home_base = Pose(*self.kin.fk(self.kin.home))
        high = max(tcp_from.pos[2] + p.approach, self.base.to_world(home_base).pos[2])
        up = None
        try:
            up = self.through(q_from, [Waypoint(Pose(np.r_[tcp_from.pos[:2], high], tcp_from.rot),
                                                slow_first=slow_first)], phase="home")
        except PathError:
            if slow_first > 0:  # at least the contact-critical retreat, if the climb is out of reach
                back = Pose(tcp_from.pos + np.array([0.0, 0.0, slow_first]), tcp_from.rot)
                try:
                    up = self.through(q_from, [Waypoint(back, kind="contact")])
                except PathError:
                    pass
        if up is None:
            up = Motion.still(q_from, "home")
        traj = self.joint_move(up.end, self.kin.home, self.kin.fk(up.end)[0][2], home_base.pos[2], "transit")
        if traj is None:  # no straight alternative onto a joint configuration: take it, dip and all
            traj, _ = transit_trajectory(self.kin, up.end, self.kin.home, p.limits, self.dt)
        return up.then(Motion(traj, (("home", len(traj)),)))

    def leave(self, q_from: np.ndarray, tcp_from: Pose, away: np.ndarray, contact: float) -> Motion:
        """Retreat ``contact`` [m] along the world direction ``away`` at the contact speed, then home. A
        retreat upwards flows into the way home without stopping."""
        if is_up(away):
            return self.home(q_from, tcp_from, slow_first=contact)
        back = Pose(tcp_from.pos + away * contact, tcp_from.rot)
        retreat = self.through(q_from, [Waypoint(back, kind="contact")])
        return retreat.then(self.home(retreat.end, back))

    def bridge(self, q_from: np.ndarray, q_to: np.ndarray) -> Motion:
        """A contact-speed joint move from ``q_from`` to ``q_to`` (a fraction of a millimetre apart), or
        nothing if they are the same."""
        if np.allclose(q_from, q_to, atol=_SAME_Q):
            return Motion(np.zeros((0, len(q_to))), ())
        traj, _ = transit_trajectory(self.kin, q_from, q_to, self.params.limits, self.dt, kind="contact")
        return Motion(traj, (("contact", len(traj)),))

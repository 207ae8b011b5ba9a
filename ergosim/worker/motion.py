"""Target-driven motion of the simulated worker: one assembly action as a sequence of phases.

rest -> reach the part where it actually lies in the scene -> grasp it (or take it from the robot at the
handover pose) -> carry it to where it is inserted or placed -> release -> return to rest.

The part and target poses are read from the scene when the action is planned (never constants). Whole-body
postures come from :class:`~ergosim.worker.ik.UpperBodyIK` at six key poses (above the part, at the part,
lifted, above the target, at the target, retreated); between key poses the canonical angles follow
minimum-jerk transitions (:mod:`ergosim.worker.minimum_jerk`) timed by MTM-1 element times
(:mod:`ergosim.worker.action_timing`). The IK runs on the
subject's own standalone human model; poses are moved between the scene's world frame and the human's frame
through the pose of ``human_pelvis`` in the scene.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple, Protocol

import mujoco
import numpy as np

from ergosim.worker.action_timing import action_timing
from ergosim.worker.ik import UpperBodyIK, log_so3
from ergosim.worker.minimum_jerk import interpolate_keyframes
from ergosim.worker.subjects import Subject, rest_angles

__all__ = ["SceneView", "Phase", "ActionMotion", "Worker"]


class SceneView(Protocol):
    """What the worker reads from a scene: world poses (pos (3,) [m], quat (4,) wxyz)."""

    def body_pose(self, name: str) -> tuple[np.ndarray, np.ndarray]: ...

    def site_pose(self, name: str) -> tuple[np.ndarray, np.ndarray]: ...


class Phase(NamedTuple):
    """A named time interval of an action [s from the action's start]."""

    name: str
    start: float
    end: float


@dataclass(frozen=True)
class ActionMotion:
    """One planned execution. ``t``: (n,) [s]; ``angles``: (n, 22) true canonical angles [deg]
    (HUMAN_JOINTS order); ``hand_pos``: (n, 3) grasp point of the acting hand in the scene's world frame [m].
    ``t_grasp``/``t_release``: when the hand closes on / lets go of the part. ``reach_error``/``place_error``
    [m] and ``place_rot_error_deg``: IK residuals at the part and at the target.
    """

    action: str
    part: str
    side: str
    rate: float
    t: np.ndarray
    angles: np.ndarray
    hand_pos: np.ndarray
    phases: tuple[Phase, ...]
    t_grasp: float
    t_release: float
    reach_error: float
    place_error: float
    place_rot_error_deg: float
    mtm: str = ""
    """The action's MTM-1 analysis (:class:`~ergosim.worker.action_timing.ActionTiming`)."""

    @property
    def duration(self) -> float:
        return float(self.t[-1])


def _quat_to_mat(quat: np.ndarray) -> np.ndarray:
    m = np.empty(9)
    mujoco.mju_quat2Mat(m, np.asarray(quat, dtype=float))
    return m.reshape(3, 3)


class Worker:
    """Plans actions for one subject. ``rate``: mocap rate of the produced trajectories [Hz]."""

    PEAK_JOINT_SPEED = 350.0
    """deg/s, the fastest any joint angle turns (assumed: peak shoulder and elbow speeds of natural reaching
    stay well below this; the wrist and trunk of a re-orienting hand are capped with them)."""
    APPROACH_UP = 0.06  # m above the part/target before the final approach
    APPROACH_BACK = 0.04  # m towards the worker
    PLACE_TOL = 0.005  # m, a keep-the-grip place pose worse than this falls back to position-only

    def __init__(self, subject: Subject, rate: float = 60.0) -> None:
        self.subject = subject
        self.rate = float(rate)
        self.model = subject.spec().compile()
        self.ik = UpperBodyIK(self.model, subject.prior())
        self.rest = rest_angles(subject)
        self.side = subject.handedness
        root = self.ik.human.root_body
        self._root_pos = self.model.body_pos[root].copy()

    # -- frames ---------------------------------------------------------------------------------------------
    def _frame(self, scene: SceneView) -> tuple[np.ndarray, np.ndarray]:
        pos, quat = scene.body_pose("human_pelvis")
        return np.asarray(pos, dtype=float), _quat_to_mat(quat)

    def _to_local(self, frame: tuple[np.ndarray, np.ndarray], pos: np.ndarray) -> np.ndarray:
        p, r = frame
        return r.T @ (np.asarray(pos, dtype=float) - p) + self._root_pos

    def _approach(self, point: np.ndarray, angles: np.ndarray) -> np.ndarray:
        """A point above ``point`` and a little towards the acting shoulder (approach/retreat waypoint)."""
        self.ik._fk(np.deg2rad(angles))
        shoulder = self.ik.data.xpos[self.ik.human.shoulder_body[self.side]]
        back = shoulder[:2] - point[:2]
        back = back / max(np.linalg.norm(back), 1e-9)
        return point + np.array([*(self.APPROACH_BACK * back), self.APPROACH_UP])

    # -- planning -------------------------------------------------------------------------------------------
    def plan(self, scene: SceneView, geometry: Any, rng: np.random.Generator, action: str | None = None,
             handover: bool = False) -> ActionMotion:
        """Plan one execution of ``geometry`` from the current scene state.

        ``geometry`` has ``part`` (the part's body name), ``kind`` (an action kind,
        :mod:`ergosim.scenes.action_kinds`), ``seats`` (the part ends in a slot: aligned and pushed in) and
        ``target`` or ``target_site`` (the site where the part's origin must end up); a fasten action also
        has ``turn_time`` [s], the time the fastener is held and turned once inserted.

        ``handover``: the part is taken from the robot's gripper where it currently is. Variability (posture
        and timing: ``subject.variability_deg``, ``subject.timing_variability``) is drawn from ``rng``.
        """
        part = geometry.part
        target_site = getattr(geometry, "target", None) or geometry.target_site
        kind = getattr(geometry, "kind", "place")
        frame = self._frame(scene)
        r_frame = frame[1]
        part_pos_w, part_quat_w = scene.body_pose(part)
        tgt_pos_w, tgt_quat_w = scene.site_pose(target_site)
        part_pos = self._to_local(frame, part_pos_w)
        part_rot = r_frame.T @ _quat_to_mat(part_quat_w)
        tgt_pos = self._to_local(frame, tgt_pos_w)
        tgt_rot = r_frame.T @ _quat_to_mat(tgt_quat_w)
        prior = self.subject.prior().jittered(rng, self.subject.variability_deg)
        ik, side = self.ik, self.side

        def solve(q0: np.ndarray, point: np.ndarray, rot: np.ndarray | None = None,
                  max_iter: int | None = None):
            return ik.solve(q0, point, side, target_rot=rot, prior=prior, max_iter=max_iter)

        def look(sol, point: np.ndarray) -> np.ndarray:
            return ik.look_at(sol.angles, point, prior)

        above_part = self._approach(part_pos, self.rest)
        lift = solve(self.rest, above_part)  # approach and lift share their hand target and their posture
        k1 = look(lift, part_pos)
        grasp = solve(k1, part_pos)
        k2 = look(grasp, part_pos)
        hand_p, hand_r = ik.hand_pose(k2, side)
        part_in_hand = hand_r.T @ (part_pos - hand_p)
        rot_in_hand = hand_r.T @ part_rot
        # Where the hand must be for the part to sit on the target site, keeping the grip. If that orientation
        # is out of reach (e.g. a part taken from high up, set down on a bench) the hand reorients the part
        # in the fingers, which is not modelled: the place pose is then position-only and the remaining
        # orientation error of the part is reported (``place_rot_error_deg``).
        place_rot = tgt_rot @ rot_in_hand.T
        place_pos = tgt_pos - place_rot @ part_in_hand
        k3 = look(lift, tgt_pos)
        above_tgt = self._approach(place_pos, k3)
        place = solve(k3, place_pos, place_rot, max_iter=25)
        keep_grip = place.pos_error <= self.PLACE_TOL
        if not keep_grip:
            place = solve(k3, tgt_pos)
            _, hand_r5 = ik.hand_pose(place.angles, side)
            rot_err = np.rad2deg(np.linalg.norm(log_so3(tgt_rot @ (hand_r5 @ rot_in_hand).T)))
            place = place._replace(rot_error_deg=float(rot_err))
        k5 = look(place, tgt_pos)
        k6 = look(solve(k5, above_tgt), tgt_pos)
        # Lowering onto the target keeps the grip's orientation where that converges quickly; otherwise (and
        # when the place pose is position-only) the hand comes down through the retreat pose.
        k4 = k6
        if keep_grip:
            down = solve(k5, above_tgt, place_rot, max_iter=25)
            if down.pos_error <= self.PLACE_TOL:
                k4 = look(down, tgt_pos)

        keys = [self.rest, k1, k2, k2, k3, k4, k5, k5, k5, k6, self.rest]
        hands = np.array([ik.hand_pos(k, side) for k in keys])
        seats = getattr(geometry, "seats", kind in ("insert", "fasten"))
        timing = action_timing(hands, seats=seats, handover=handover,
                               turn_time=getattr(geometry, "turn_time", 0.0))
        # MTM-1 standard times at the subject's pace, with trial-to-trial jitter on each segment; always
        # drawn, so the rng stream does not depend on its size
        jitter = rng.lognormal(0.0, self.subject.timing_variability, len(timing.durations))
        seg = timing.durations / self.subject.speed * jitter
        # MTM-1 times the hand's path; a segment that turns a joint far for a short hand path (the trunk or
        # the wrist re-orienting on the final approach) is slowed so no joint exceeds PEAK_JOINT_SPEED
        # (the peak of a minimum-jerk transition is 1.875 x its mean speed)
        span = np.abs(np.diff(np.asarray(keys), axis=0)).max(axis=1)
        seg = np.maximum(seg, 1.875 * span / self.PEAK_JOINT_SPEED)
        key_t = np.concatenate([[0.0], np.cumsum(seg)])
        n = int(np.floor(key_t[-1] * self.rate)) + 1
        t = np.arange(n) / self.rate
        if t[-1] < key_t[-1]:
            t = np.append(t, key_t[-1])  # end exactly at rest
        angles = interpolate_keyframes(key_t, np.asarray(keys), t)
        local = ik.hand_path(angles, side)
        hand_world = (local - self._root_pos) @ r_frame.T + frame[0]
        kind_name = "fasten" if getattr(geometry, "turn_time", 0.0) else "insert" if seats else "place"
        phases = (
            Phase("reach", 0.0, key_t[2]),
            Phase("take" if handover else "grasp", key_t[2], key_t[3]),
            Phase("carry", key_t[3], key_t[6]),
            Phase(kind_name, key_t[6], key_t[7]),
            Phase("release", key_t[7], key_t[8]),
            Phase("return", key_t[8], key_t[-1]),
        )
        return ActionMotion(
            action=action or getattr(geometry, "action", part),
            part=part,
            side=side,
            rate=self.rate,
            t=t,
            angles=angles,
            hand_pos=hand_world,
            phases=phases,
            t_grasp=float(key_t[3]),
            t_release=float(key_t[7]),
            reach_error=grasp.pos_error,
            place_error=place.pos_error,
            place_rot_error_deg=place.rot_error_deg,
            mtm=timing.analysis,
        )

    def rest_motion(self, duration: float) -> ActionMotion:
        """The rest posture held for ``duration`` [s] (no part, no phases)."""
        n = max(int(np.floor(duration * self.rate)) + 1, 1)
        t = np.arange(n) / self.rate
        angles = np.broadcast_to(self.rest, (n, len(self.rest))).copy()
        return ActionMotion("rest", "", self.side, self.rate, t, angles, np.full((n, 3), np.nan),
                            (Phase("rest", 0.0, float(t[-1])),), np.nan, np.nan, 0.0, 0.0, 0.0)

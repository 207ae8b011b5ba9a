"""Target-driven motion of the simulated worker: one assembly action as a sequence of phases.

rest -> reach the part where it actually lies in the scene -> grasp it (or take it from the robot where it
holds it out) -> carry it to where it is inserted or placed -> release -> return to rest.

The part and target poses are read from the scene when the action is planned (never constants). Whole
bodies (posture and stance) come from :class:`~ergosim.worker.ik.WholeBodyIK` at the action's key poses
(:mod:`ergosim.worker.keyposes`): the worker steps and turns within the cell's standing area
(:mod:`ergosim.worker.stance`), bends the knees, and trunk, neck and eyes share the gaze. Between key poses
the body follows minimum-jerk transitions (:mod:`ergosim.worker.minimum_jerk`) timed by MTM-1 element times,
the body motions included (:mod:`ergosim.worker.action_timing`). The IK runs on the subject's own
standalone human model; poses are moved between the scene's world frame and the worker's frame (the human's
root on the floor, ``human_base``) through that root's pose in the scene.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, NamedTuple, Protocol

import numpy as np

from ergosim.human.anthropometry import segment_lengths
from ergosim.human.model import ROOT_BODY
from ergosim.posture import HUMAN_JOINTS, STANCE
from ergosim.quat import to_mat
from ergosim.worker.action_timing import action_timing
from ergosim.worker.balance import rebalance
from ergosim.worker.clear_path import clear_transitions
from ergosim.worker.ik import WholeBodyIK
from ergosim.worker.keyposes import plan_keyposes
from ergosim.worker.minimum_jerk import interpolate_keyframes
from ergosim.worker.obstacles import IKModel, clearance, ik_model
from ergosim.worker.stance import StanceRule, StandingArea, area_from_footprints, area_of_cell
from ergosim.worker.subjects import Subject, rest_angles

__all__ = ["SceneView", "Phase", "ActionMotion", "Worker", "WORKER_MEASURES"]

_N = len(HUMAN_JOINTS)
WORKER_MEASURES = ("com_margin", "clearance")
"""What a motion measures of its postures per frame, beside the stance (:attr:`ActionMotion.tick_stance`)."""


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
    [m] and ``place_rot_error_deg``: IK residuals at the part and at the target (with a regrasp, the turn the
    fingers give the part). ``stance``: (n, 5) how the worker stands [m, m, deg, deg, deg]
    (:data:`~ergosim.posture.STANCE`; None: on the spot, straight legs). ``balance``: (n,) the centre of
    mass's margin inside the base of support [m] (:mod:`ergosim.worker.balance`); ``clearance``: (n,) the
    body's smallest distance to the cell's furniture [m], capped at 0.1 (:mod:`ergosim.worker.obstacles`);
    None where not measured.
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
    stance: np.ndarray | None = None
    balance: np.ndarray | None = None
    clearance: np.ndarray | None = None

    @property
    def duration(self) -> float:
        return float(self.t[-1])

    @property
    def stances(self) -> np.ndarray:
        """(n, 5) stance [m, m, deg, deg, deg], zeros when the motion has none."""
        return self.stance if self.stance is not None else np.zeros((len(self.t), len(STANCE)))

    @cached_property
    def tick_stance(self) -> np.ndarray:
        """(n, 7) the stance, the balance margin and the clearance per frame (NaN where not measured): the
        tick log's columns :data:`~ergosim.posture.STANCE` + :data:`WORKER_MEASURES`."""
        n = len(self.t)
        nan = np.full(n, np.nan)
        return np.column_stack([self.stances, nan if self.balance is None else self.balance,
                                nan if self.clearance is None else self.clearance])

    @property
    def body(self) -> np.ndarray:
        """(n, 27) posture and stance [deg, m]."""
        return np.concatenate([self.angles, self.stances], axis=1)


def _grip(scene: SceneView, part: str, part_pos_w: np.ndarray, part_rot: np.ndarray, r_frame: np.ndarray,
          tgt_rot: np.ndarray, handover: bool = False) -> np.ndarray | None:
    """Where the hand takes a part it inserts: by its outer end, the end that stays out (the part's
    ``<part>_grasp_end`` site, as a robot takes a standing profile), when the part goes down into an upper
    hollow (pushed home from above) or the robot holds it out (its gripper holds the middle); None (its
    middle) for any other insertion or a part without that site."""
    try:
        end_w, _ = scene.site_pose(f"{part}_grasp_end")
    except (KeyError, ValueError):
        return None
    offset = part_rot.T @ (r_frame.T @ (np.asarray(end_w, dtype=float) - np.asarray(part_pos_w, dtype=float)))
    length = float(np.linalg.norm(offset))
    upright = UPRIGHT_END_GRIP and (tgt_rot @ offset)[2] / max(length, 1e-12) >= UPRIGHT_COS
    if length < 1e-6 or not (handover or upright):
        return None
    return offset


UPRIGHT_END_GRIP = True
"""A profile pushed down into an upper hollow is held by its upper end (False: by its middle)."""
UPRIGHT_COS = 0.9
"""A part stands upright at its target when its grip end points within 26 deg of straight up."""


class Worker:
    """Plans actions for one subject. ``rate``: mocap rate of the produced trajectories [Hz]."""

    PEAK_JOINT_SPEED = 350.0
    """deg/s, the fastest any joint angle turns (assumed: peak shoulder and elbow speeds of natural reaching
    stay well below this; the wrist and trunk of a re-orienting hand are capped with them)."""

    def __init__(self, subject: Subject, rate: float = 60.0) -> None:
        self.subject = subject
        self.rate = float(rate)
        self.model = subject.spec().compile()
        seg = segment_lengths(subject.stature, subject.scale_map)
        self._ik_args = dict(stature=subject.stature, foot_length=seg.foot)
        self.ik = WholeBodyIK(self.model, subject.prior(), **self._ik_args)
        self.rest = rest_angles(subject)
        self.rest_body = np.concatenate([self.rest, np.zeros(len(STANCE))])
        self.side = subject.handedness
        sign = -1.0 if self.side == "right" else 1.0
        self.rule = StanceRule(seg.arm_reach, sign * seg.shoulder_half_width, seg.hip_height - seg.thigh)
        self._area: tuple[Any, StandingArea] | None = None
        self._cell_ik: tuple[Any, WholeBodyIK, IKModel] | None = None
        self.rest_balance = float(self.ik.balance_path(self.rest_body[None])[0])

    # -- frames ---------------------------------------------------------------------------------------------
    def _frame(self, scene: SceneView) -> tuple[np.ndarray, np.ndarray]:
        pos, quat = scene.body_pose(ROOT_BODY)
        return np.asarray(pos, dtype=float), to_mat(quat)

    def standing_area(self, scene: SceneView) -> StandingArea:
        """Where the worker may stand in ``scene``: its ``standing_area`` if it gives one, else the cell's
        (a scene without a cell description: one step either way and a 90 deg turn, nothing in the way)."""
        given = getattr(scene, "standing_area", None)
        if isinstance(given, StandingArea):
            return given
        config = getattr(scene, "config", None)
        if self._area is None or self._area[0] is not config:
            area = (area_from_footprints((), self.subject.stature) if config is None
                    else area_of_cell(config, self.subject.stature))
            self._area = (config, area)
        return self._area[1]

    def ik_for(self, scene: SceneView) -> tuple[WholeBodyIK, IKModel | None]:
        """The IK for ``scene``: the subject's human with the cell's furniture as obstacles (and that model's
        geom ids), built once per cell; a scene without a cell description has none."""
        config = getattr(scene, "config", None)
        if config is None or not getattr(config, "furniture", None):
            return self.ik, None
        if self._cell_ik is None or self._cell_ik[0] is not config:
            origin, r_frame = self._frame(scene)
            yaw = float(np.degrees(np.arctan2(r_frame[1, 0], r_frame[0, 0])))
            boxes = [(r_frame.T @ (np.asarray(c, dtype=float) - origin), h, box_yaw - yaw)
                     for f in config.furniture for c, h, box_yaw in f.boxes()]
            built = ik_model(self.subject.spec(), boxes)
            ik = WholeBodyIK(built.model, self.subject.prior(), segments=built.segments,
                             obstacles=built.obstacles, forearms=built.forearms, **self._ik_args)
            self._cell_ik = (config, ik, built)
        return self._cell_ik[1:]

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
        origin, r_frame = self._frame(scene)
        part_pos_w, part_quat_w = scene.body_pose(part)
        tgt_pos_w, tgt_quat_w = scene.site_pose(target_site)
        part_pose = (r_frame.T @ (np.asarray(part_pos_w) - origin), r_frame.T @ to_mat(part_quat_w))
        tgt_pose = (r_frame.T @ (np.asarray(tgt_pos_w) - origin), r_frame.T @ to_mat(tgt_quat_w))
        prior = self.subject.prior().jittered(rng, self.subject.variability_deg)
        seats = getattr(geometry, "seats", kind in ("insert", "fasten"))
        grip = _grip(scene, part, part_pos_w, part_pose[1], r_frame, tgt_pose[1], handover) if seats else None
        ik, built = self.ik_for(scene)
        keys = plan_keyposes(ik, self.rest_body, part_pose, tgt_pose, prior, self.standing_area(scene),
                             self.side, self.rule, grip)
        bodies = keys.bodies
        hands = ik.hand_path(bodies, self.side)
        timing = action_timing(hands, seats=seats, handover=handover,
                               turn_time=getattr(geometry, "turn_time", 0.0), stances=bodies[:, _N:],
                               regrasp_deg=keys.regrasp_deg)
        # MTM-1 standard times at the subject's pace, with trial-to-trial jitter on each segment; always
        # drawn, so the rng stream does not depend on its size
        jitter = rng.lognormal(0.0, self.subject.timing_variability, len(timing.durations))
        seg = timing.durations / self.subject.speed * jitter
        # MTM-1 times the hand's path; a segment that turns a joint far for a short hand path (the trunk or
        # the wrist re-orienting on the final approach) is slowed so no joint exceeds PEAK_JOINT_SPEED
        # (the peak of a minimum-jerk transition is 1.875 x its mean speed)
        span = np.abs(np.diff(bodies[:, :_N + 3][:, [*range(_N), _N + 2]], axis=0)).max(axis=1)
        seg = np.maximum(seg, 1.875 * span / self.PEAK_JOINT_SPEED)
        key_t = np.concatenate([[0.0], np.cumsum(seg)])
        n = int(np.floor(key_t[-1] * self.rate)) + 1
        t = np.arange(n) / self.rate
        if t[-1] < key_t[-1]:
            t = np.append(t, key_t[-1])  # end exactly at rest
        body = interpolate_keyframes(key_t, bodies, t)
        body = clear_transitions(ik, key_t, bodies, t, body, range(len(bodies) - 1), self.side, prior, built)
        body, balance = rebalance(ik, body)
        hand_world = ik.hand_path(body, self.side) @ r_frame.T + origin
        clear = self._clearances(ik, body, built)
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
            action=action or getattr(geometry, "action", part), part=part, side=self.side, rate=self.rate,
            t=t, angles=body[:, :_N], hand_pos=hand_world, phases=phases, t_grasp=float(key_t[3]),
            t_release=float(key_t[7]), reach_error=keys.reach_error, place_error=keys.place_error,
            place_rot_error_deg=keys.place_rot_error_deg, mtm=timing.analysis, stance=body[:, _N:],
            balance=balance, clearance=clear,
        )

    @staticmethod
    def _clearances(ik: WholeBodyIK, body: np.ndarray, built: IKModel | None) -> np.ndarray | None:
        """(n,) clearances of the body from the furniture [m] (None without any)."""
        if built is None:
            return None
        out = np.empty(len(body))
        for k, b in enumerate(body):
            ik._fk(ik.qpos(b))
            out[k] = clearance(ik.model, ik.data, built.segments, built.obstacles, built.forearms)
        return out

    def rest_motion(self, duration: float) -> ActionMotion:
        """The rest posture held for ``duration`` [s] on the worker's spot (no part, no phases)."""
        n = max(int(np.floor(duration * self.rate)) + 1, 1)
        t = np.arange(n) / self.rate
        angles = np.broadcast_to(self.rest, (n, len(self.rest))).copy()
        return ActionMotion("rest", "", self.side, self.rate, t, angles, np.full((n, 3), np.nan),
                            (Phase("rest", 0.0, float(t[-1])),), np.nan, np.nan, 0.0, 0.0, 0.0,
                            stance=np.zeros((n, len(STANCE))), balance=np.full(n, self.rest_balance))

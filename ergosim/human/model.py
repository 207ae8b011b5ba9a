"""The kinematic human: build it (:func:`human_spec`) and read or drive it (:class:`HumanModel`).

The human is driven the way mink's ``Configuration.update`` drives a robot: write ``qpos``, run
``mj_kinematics``; it has no actuators and is never integrated as a dynamic body by this module.
"""

from __future__ import annotations

from collections.abc import Mapping

import mujoco
import numpy as np

from ergosim.errors import ModelError
from ergosim.human.anthropometry import segment_lengths
from ergosim.human.legs import Legs
from ergosim.human.mjcf import humanoid_xml
from ergosim.posture import HUMAN_JOINTS, STANCE, Posture

__all__ = ["HAND_SITES", "EYE_SITE", "ROOT_BODY", "PELVIS_BODY", "human_spec", "HumanModel", "HumanReadout",
           "body_qpos"]

ROOT_BODY = "human_base"
"""The human's root: on the floor at the worker's position, facing +x; it never moves."""
PELVIS_BODY = "human_pelvis"
HAND_SITES = {"right": "human_hand_right", "left": "human_hand_left"}
EYE_SITE = "human_eyes"
SHOULDER_BODIES = {"right": "human_right_upper_arm", "left": "human_left_upper_arm"}


def human_spec(stature: float = 1.75, scale: Mapping[str, float] | None = None,
               keyframe: str | None = "home") -> mujoco.MjSpec:
    """MjSpec of the human upper body for ``stature`` [m] with optional per-segment multipliers.

    The root body ``human_base`` has no joint: attach it to a frame on the floor at the worker's position
    (facing +x of that frame). The pelvis above it carries the stance joints (:data:`ergosim.posture.STANCE`).
    Pass ``keyframe=None`` when
    attaching into a scene that defines its own ``home`` keyframe.
    """
    return mujoco.MjSpec.from_string(humanoid_xml(segment_lengths(stature, scale), keyframe=keyframe))


_N = len(HUMAN_JOINTS)
_BODY_SCALE = np.concatenate([np.full(_N, np.pi / 180.0), [1.0, 1.0, np.pi / 180.0, np.pi / 180.0,
                                                            np.pi / 180.0]])


def body_qpos(angles_deg: np.ndarray, stance: np.ndarray | None = None) -> np.ndarray:
    """The qpos values [rad, m] of a posture (..., 22) [deg] and a stance (..., 5) [m, m, deg, deg, deg]
    (:data:`~ergosim.posture.STANCE`; None: standing straight on the spot), as one (..., 27) array in
    HUMAN_JOINTS + STANCE order: what :meth:`HumanModel.pose` and :meth:`MocapHuman.pose` take."""
    angles = np.asarray(angles_deg, dtype=float)
    if stance is None:
        stance = np.zeros(angles.shape[:-1] + (len(STANCE),))
    return np.concatenate([angles, np.asarray(stance, dtype=float)], axis=-1) * _BODY_SCALE


class HumanReadout:
    """Where the human's hands, eyes and shoulders are in a scene's ``data`` (after kinematics), through the
    ids ``hand_site``, ``eye_site`` and ``shoulder_body`` the subclass sets."""

    hand_site: dict[str, int]
    eye_site: int
    shoulder_body: dict[str, int]

    def hand_pos(self, data: mujoco.MjData, side: str = "right") -> np.ndarray:
        """(3,) grasp point of a hand in the world frame [m] (after kinematics)."""
        return data.site_xpos[self.hand_site[side]].copy()

    def hand_xmat(self, data: mujoco.MjData, side: str = "right") -> np.ndarray:
        """(3, 3) orientation of a hand's grasp site in the world frame."""
        return data.site_xmat[self.hand_site[side]].reshape(3, 3).copy()

    def eye_pos(self, data: mujoco.MjData) -> np.ndarray:
        """(3,) eye (gaze origin) position in the world frame [m]."""
        return data.site_xpos[self.eye_site].copy()

    def shoulder_pos(self, data: mujoco.MjData, side: str = "right") -> np.ndarray:
        """(3,) glenohumeral centre in the world frame [m]."""
        return data.xpos[self.shoulder_body[side]].copy()


class HumanModel(HumanReadout):
    """Canonical-angle view of the human inside any compiled model that contains it.

    ``qadr`` is the (22,) array of qpos addresses in :data:`ergosim.posture.HUMAN_JOINTS` order.
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        ids = []
        for name in HUMAN_JOINTS:
            jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
            if jid < 0:
                raise ModelError(f"the model has no human joint {name!r}; attach ergosim.human.human_spec()",
                                 where="HumanModel")
            ids.append(jid)
        self.joint_ids = np.array(ids)
        self.qadr = model.jnt_qposadr[self.joint_ids].copy()
        self.dofadr = model.jnt_dofadr[self.joint_ids].copy()
        self.index = {n: i for i, n in enumerate(HUMAN_JOINTS)}
        self.range_deg = np.rad2deg(model.jnt_range[self.joint_ids])
        self.hand_site = {side: self._id(mujoco.mjtObj.mjOBJ_SITE, n) for side, n in HAND_SITES.items()}
        self.eye_site = self._id(mujoco.mjtObj.mjOBJ_SITE, EYE_SITE)
        self.root_body = self._id(mujoco.mjtObj.mjOBJ_BODY, ROOT_BODY)
        self.shoulder_body = {side: self._id(mujoco.mjtObj.mjOBJ_BODY, n)
                              for side, n in SHOULDER_BODIES.items()}
        self.pelvis_body = self._id(mujoco.mjtObj.mjOBJ_BODY, PELVIS_BODY)
        self.stance_qadr = np.array([model.jnt_qposadr[self._id(mujoco.mjtObj.mjOBJ_JOINT, n)]
                                     for n in STANCE])
        self.legs = Legs(model)

    def _id(self, kind: mujoco.mjtObj, name: str) -> int:
        i = mujoco.mj_name2id(self.model, kind, name)
        if i < 0:
            raise ModelError(f"the model has no human element {name!r}", where="HumanModel")
        return i

    def angles(self, qpos: np.ndarray) -> np.ndarray:
        """(..., nq) qpos [rad] -> (..., 22) canonical angles [deg] in HUMAN_JOINTS order."""
        return np.rad2deg(np.asarray(qpos)[..., self.qadr])

    def posture(self, qpos: np.ndarray) -> dict[str, float | np.ndarray]:
        """THE qpos -> posture mapping: canonical name -> angle [deg] (float, or (n,) for (n, nq) qpos).

        Hinge signs equal the canonical signs, so this is a unit conversion and a reordering.
        """
        a = self.angles(qpos)
        if a.ndim == 1:
            return {n: float(a[i]) for i, n in enumerate(HUMAN_JOINTS)}
        return {n: a[..., i] for i, n in enumerate(HUMAN_JOINTS)}

    def write_angles(self, qpos: np.ndarray, angles_deg: np.ndarray) -> None:
        """Write (22,) canonical angles [deg] (HUMAN_JOINTS order) into ``qpos`` in place."""
        qpos[self.qadr] = np.deg2rad(angles_deg)

    def write_body(self, qpos: np.ndarray, body: np.ndarray) -> None:
        """Write a body vector (22,) [rad] or (27,) [rad, m] (:func:`body_qpos`) into ``qpos`` in place: the
        posture, and with 27 values the stance and the joints that follow the knee and the ankle."""
        qpos[self.qadr] = body[:_N]
        if len(body) > _N:
            qpos[self.stance_qadr[:3]] = body[_N:_N + 3]
            self.legs.write(qpos, body[_N + 3], body[_N + 4])

    def pose(self, data: mujoco.MjData, qpos: np.ndarray, qvel: np.ndarray | None = None) -> None:
        """Write the 22 angles [rad] (and their rates [rad/s], else zero) into ``data``, or a (27,) body
        vector with the stance (:func:`body_qpos`); no kinematics."""
        self.write_body(data.qpos, qpos)
        data.qvel[self.dofadr] = 0.0 if qvel is None else qvel[:_N]

    def set_body(self, data: mujoco.MjData, angles_deg: np.ndarray, stance: np.ndarray | None = None) -> None:
        """Set the posture (22,) [deg] and the stance (5,) [m, m, deg, deg, deg] and run mj_kinematics."""
        self.write_body(data.qpos, body_qpos(angles_deg, stance))
        data.qvel[self.dofadr] = 0.0
        mujoco.mj_kinematics(self.model, data)

    def set_posture(self, data: mujoco.MjData, posture_deg: Posture) -> None:
        """Set the named angles [deg] (others untouched), zero the human's velocities, run mj_kinematics."""
        for name, value in posture_deg.items():
            i = self.index.get(name)
            if i is None:
                raise ModelError(f"unknown canonical angle {name!r}", where="HumanModel.set_posture")
            data.qpos[self.qadr[i]] = np.deg2rad(float(value))
        data.qvel[self.dofadr] = 0.0
        mujoco.mj_kinematics(self.model, data)

    def set_angles(self, data: mujoco.MjData, angles_deg: np.ndarray) -> None:
        """Set all 22 angles [deg] (HUMAN_JOINTS order), zero the human's velocities, run mj_kinematics."""
        data.qpos[self.qadr] = np.deg2rad(angles_deg)
        data.qvel[self.dofadr] = 0.0
        mujoco.mj_kinematics(self.model, data)

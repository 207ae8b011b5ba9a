"""The human inside a physics scene: mocap bodies posed by the forward kinematics of the articulated model.

The human is driven kinematically, the way mink's ``Configuration.update`` drives a robot: motion capture
sets the ``qpos`` of the articulated human model (:class:`~ergosim.human.model.HumanModel`, with its 22
canonical joints and their ranges) and ``mj_kinematics`` places its segments. That model is kept apart from
the physics: the scene holds one MuJoCo *mocap body* per segment, with the segment's name, geoms and sites,
and every frame copies the segments' world poses into ``mocap_pos``/``mocap_quat``.

So MuJoCo never integrates the human. It cannot sag or drift between mocap frames, it adds no degrees of
freedom, inertia or solver rows to the step, and a held part is welded to a hand that is exactly where
motion capture puts it. Its geoms never collide (``contype=conaffinity=0``): it never pushes the robot or a
part.
"""

from __future__ import annotations

import mujoco
import numpy as np

from ergosim.errors import ModelError
from ergosim.human.mjcf import HOME_POSTURE
from ergosim.human.model import HumanModel, HumanReadout, body_qpos
from ergosim.posture import HUMAN_JOINTS, Posture

__all__ = ["add_mocap_segments", "MocapHuman"]


def _segments(kin: mujoco.MjModel) -> list[int]:
    """Body ids of the human's segments in ``kin`` (every body but the world), in tree order."""
    return list(range(1, kin.nbody))


def add_mocap_segments(spec: mujoco.MjSpec, kin: mujoco.MjModel, kin_data: mujoco.MjData) -> None:
    """Add to ``spec`` one mocap body per segment of the compiled human ``kin``, at its pose in ``kin_data``
    (after kinematics), carrying copies of the segment's geoms and sites in the segment's own frame."""
    for mat in range(kin.nmat):
        name = kin.material(mat).name
        if spec.material(name) is None:
            spec.add_material(name=name, rgba=kin.mat_rgba[mat].tolist())
    for b in _segments(kin):
        body = spec.worldbody.add_body(name=kin.body(b).name, mocap=True, pos=kin_data.xpos[b].tolist(),
                                       quat=kin_data.xquat[b].tolist())
        for g in np.flatnonzero(kin.geom_bodyid == b):
            mat = int(kin.geom_matid[g])
            body.add_geom(name=kin.geom(g).name, type=mujoco.mjtGeom(int(kin.geom_type[g])),
                          size=kin.geom_size[g].tolist(), pos=kin.geom_pos[g].tolist(),
                          quat=kin.geom_quat[g].tolist(), group=int(kin.geom_group[g]), contype=0,
                          conaffinity=0, rgba=kin.geom_rgba[g].tolist(),
                          material=kin.material(mat).name if mat >= 0 else "")
        for s in np.flatnonzero(kin.site_bodyid == b):
            body.add_site(name=kin.site(s).name, type=mujoco.mjtGeom(int(kin.site_type[s])),
                          size=kin.site_size[s].tolist(), pos=kin.site_pos[s].tolist(),
                          quat=kin.site_quat[s].tolist(), group=int(kin.site_group[s]),
                          rgba=kin.site_rgba[s].tolist())


class MocapHuman(HumanReadout):
    """The scene's human: poses the mocap segments of ``scene`` from the articulated model ``kin``.

    ``kin`` must sit in the scene's world frame (the worker's placement applied), as built by
    :func:`ergosim.scenes.build.attach_human`. Angles are canonical, in degrees, in
    :data:`~ergosim.posture.HUMAN_JOINTS` order; ``qpos`` arguments are the same angles in radians.
    Not thread-safe: it owns one ``MjData`` of ``kin``.
    """

    def __init__(self, scene: mujoco.MjModel, kin: mujoco.MjModel) -> None:
        self.model = scene
        self.kin_model = kin
        self.kin_data = mujoco.MjData(kin)
        self.kin = HumanModel(kin)
        self.index = self.kin.index
        self.range_deg = self.kin.range_deg
        self.home_deg = np.array([HOME_POSTURE.get(n, 0.0) for n in HUMAN_JOINTS])
        segments = _segments(kin)
        mocap = []
        for b in segments:
            name = kin.body(b).name
            sb = mujoco.mj_name2id(scene, mujoco.mjtObj.mjOBJ_BODY, name)
            if sb < 0 or scene.body_mocapid[sb] < 0:
                raise ModelError(f"the scene has no mocap body {name!r} for the human segment",
                                 where="MocapHuman")
            mocap.append(int(scene.body_mocapid[sb]))
        # one block copy per frame when the segments' mocap ids are consecutive, as add_mocap_segments makes
        first = mocap[0]
        contiguous = mocap == list(range(first, first + len(mocap))) and segments == list(
            range(segments[0], segments[0] + len(segments)))
        self._mocap = slice(first, first + len(mocap)) if contiguous else np.array(mocap)
        self._kbody = slice(segments[0], segments[-1] + 1) if contiguous else np.array(segments)
        self._qadr = self.kin.qadr
        self.hand_site = {side: _scene_id(scene, mujoco.mjtObj.mjOBJ_SITE, kin.site(i).name)
                          for side, i in self.kin.hand_site.items()}
        self.eye_site = _scene_id(scene, mujoco.mjtObj.mjOBJ_SITE, kin.site(self.kin.eye_site).name)
        self.shoulder_body = {side: _scene_id(scene, mujoco.mjtObj.mjOBJ_BODY, kin.body(i).name)
                              for side, i in self.kin.shoulder_body.items()}

    # -- driving ---------------------------------------------------------------------------------------------
    def _fk(self, qpos: np.ndarray) -> mujoco.MjData:
        """Forward kinematics of the articulated model at the 22 angles [rad] (a (27,) body vector also sets
        the stance, :func:`~ergosim.human.model.body_qpos`); its data."""
        kd = self.kin_data
        self.kin.write_body(kd.qpos, qpos)
        mujoco.mj_kinematics(self.kin_model, kd)
        return kd

    def pose(self, data: mujoco.MjData, qpos: np.ndarray, qvel: np.ndarray | None = None) -> None:
        """Set the 22 angles [rad] (or a (27,) body vector with the stance): forward kinematics of the
        articulated model, then the segments' world
        poses into ``data.mocap_pos``/``mocap_quat`` (in effect from the next ``mj_step``/``mj_kinematics``).
        ``qvel`` is accepted for the same call as :meth:`HumanModel.pose` and unused: mocap bodies have no
        velocity state."""
        kd = self._fk(qpos)
        data.mocap_pos[self._mocap] = kd.xpos[self._kbody]
        data.mocap_quat[self._mocap] = kd.xquat[self._kbody]

    def set_angles(self, data: mujoco.MjData, angles_deg: np.ndarray) -> None:
        """Pose the human at (22,) angles [deg] and run the scene's ``mj_kinematics``."""
        self.pose(data, np.deg2rad(np.asarray(angles_deg, dtype=float)))
        mujoco.mj_kinematics(self.model, data)

    def set_posture(self, data: mujoco.MjData, posture_deg: Posture) -> None:
        """Pose the human at the home posture with the named angles [deg] replaced."""
        angles = self.home_deg.copy()
        for name, value in posture_deg.items():
            i = self.index.get(name)
            if i is None:
                raise ModelError(f"unknown canonical angle {name!r}", where="MocapHuman.set_posture")
            angles[i] = float(value)
        self.set_angles(data, angles)

    # -- reading ---------------------------------------------------------------------------------------------
    def segment_pose_at(self, angles_deg: np.ndarray, body: str,
                        stance: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """World pose (position (3,) [m], quaternion (4,) wxyz) segment ``body`` would have at (22,) angles
        [deg] and (5,) ``stance`` [m, m, deg, deg, deg], from the articulated model alone (the scene is
        untouched)."""
        kd = self._fk(body_qpos(angles_deg, stance))
        b = self.kin_model.body(body).id
        return kd.xpos[b].copy(), kd.xquat[b].copy()


def _scene_id(scene: mujoco.MjModel, kind: mujoco.mjtObj, name: str) -> int:
    i = mujoco.mj_name2id(scene, kind, name)
    if i < 0:
        raise ModelError(f"the scene has no human element {name!r}", where="MocapHuman")
    return i

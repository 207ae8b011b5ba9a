"""A minimal scene for worker tests: the subject's human, one free part and one target site."""

from __future__ import annotations

import warnings

import mujoco
import numpy as np


class PointScene:
    """``body_pose``/``site_pose`` over a compiled scene (the worker's SceneView), plus the model/data."""

    def __init__(self, subject, part_pos, target_pos, worker_pos=(0.0, 0.0, 0.0), yaw=0.0,
                 target_euler=(0.0, 0.0, 0.0), standing_area=None) -> None:
        self.standing_area = standing_area  # None: the worker's default (one step either way, no furniture)
        spec = mujoco.MjSpec()
        body = spec.worldbody.add_body(name="part", pos=list(part_pos))
        body.add_freejoint()
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.02, 0.02, 0.02])
        spec.worldbody.add_site(name="target", pos=list(target_pos), euler=list(target_euler))
        frame = spec.worldbody.add_frame(pos=list(worker_pos), euler=[0.0, 0.0, yaw])
        frame.attach_body(subject.spec(keyframe=None).body("human_base"), "", "")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # empty attach prefix: the canonical joint names
            self.model = spec.compile()
        self.data = mujoco.MjData(self.model)
        mujoco.mj_forward(self.model, self.data)

    def body_pose(self, name):
        i = self.model.body(name).id
        return self.data.xpos[i].copy(), self.data.xquat[i].copy()

    def site_pose(self, name):
        i = self.model.site(name).id
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, self.data.site_xmat[i])
        return self.data.site_xpos[i].copy(), quat

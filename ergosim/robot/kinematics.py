"""The robot controller's model: pinocchio on the same URDF as the MuJoCo plant.

Everything here is in the robot **base frame** (``panda_link0``); :class:`~ergosim.robot.frames.BasePose`
converts world targets. The fingers are locked (open), leaving the 7 arm joints.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from ergosim.errors import ModelError
from ergosim.robot.assets import panda_urdf
from ergosim.robot.mjcf import ARM_JOINTS, FINGER_JOINTS, HOME_QPOS

__all__ = ["TCP_FRAME", "PandaKinematics"]

TCP_FRAME = "panda_hand_tcp"
"""The URDF frame of the grasp centre; the MuJoCo site ``panda_tcp`` sits at the same pose."""


class PandaKinematics:
    """Forward kinematics and frame Jacobians of the 7-DoF arm.

    ``lower``/``upper`` (7,) joint limits [rad]; ``velocity`` (7,) [rad/s] and ``effort`` (7,) [N m] limits;
    ``home`` (7,) the ready configuration [rad].
    """

    def __init__(self, urdf: str | Path | None = None) -> None:
        path = str(urdf or panda_urdf())
        try:
            full = pin.buildModelFromUrdf(path)
        except (RuntimeError, ValueError) as err:
            raise ModelError(f"pinocchio cannot read the URDF: {err}", where=path) from None
        lock = [full.getJointId(n) for n in FINGER_JOINTS]
        self.model = pin.buildReducedModel(full, lock, pin.neutral(full))
        names = tuple(self.model.names[1:])
        if names != ARM_JOINTS:
            raise ModelError(f"expected arm joints {ARM_JOINTS}, found {names}", where=path)
        self.data = self.model.createData()
        self.tcp = self.model.getFrameId(TCP_FRAME)
        self.lower = self.model.lowerPositionLimit.copy()
        self.upper = self.model.upperPositionLimit.copy()
        self.velocity = self.model.velocityLimit.copy()
        self.effort = self.model.effortLimit.copy()
        self.home = np.array(HOME_QPOS)

    @property
    def nq(self) -> int:
        return self.model.nq

    def frame_id(self, name: str) -> int:
        if not self.model.existFrame(name):
            raise ModelError(f"no frame {name!r} in the Panda model", where="PandaKinematics")
        return self.model.getFrameId(name)

    def fk(self, q: np.ndarray, frame: int | str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Pose of ``frame`` (default the TCP) for (7,) ``q`` [rad]: position (3,) [m], rotation (3, 3)."""
        fid = self.tcp if frame is None else (frame if isinstance(frame, int) else self.frame_id(frame))
        pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        oMf = pin.updateFramePlacement(self.model, self.data, fid)
        return oMf.translation.copy(), oMf.rotation.copy()

    def jacobian(self, q: np.ndarray, frame: int | str | None = None) -> np.ndarray:
        """(6, 7) Jacobian of ``frame``: rows 0-2 the linear velocity of its origin, rows 3-5 its angular
        velocity, both in base-frame axes (pinocchio LOCAL_WORLD_ALIGNED)."""
        fid = self.tcp if frame is None else (frame if isinstance(frame, int) else self.frame_id(frame))
        return pin.computeFrameJacobian(self.model, self.data, np.asarray(q, dtype=float), fid,
                                        pin.LOCAL_WORLD_ALIGNED)

    def within_limits(self, q: np.ndarray, tol: float = 1e-9) -> bool:
        q = np.asarray(q)
        return bool(np.all(q >= self.lower - tol) and np.all(q <= self.upper + tol))

"""The robot controller's model: pinocchio on the same URDF as the MuJoCo plant.

Everything here is in the robot **base frame** (the URDF's root link);
:class:`~ergosim.robot.trajectory.BaseFrame` converts world targets. Joints other than the arm's (the
fingers) are locked, leaving the arm's joints in the order of :attr:`RobotModel.arm_joints`; frames the
URDF lacks (:attr:`RobotModel.add_frames`, e.g. the UR5's TCP) are added.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ergosim.errors import ModelError
from ergosim.robot.assets import erd_file
from ergosim.robot.robot_model import RobotModel

__all__ = ["ArmKinematics"]


def _build(robot: RobotModel) -> pin.Model:
    path = str(erd_file(robot.urdf))
    try:
        full = pin.buildModelFromUrdf(path)
    except (RuntimeError, ValueError) as err:
        raise ModelError(f"pinocchio cannot read the URDF: {err}", where=path) from None
    lock = [full.getJointId(n) for n in full.names[1:] if n not in robot.arm_joints]
    model = pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full
    for f in robot.add_frames:
        parent = model.frames[model.getFrameId(f.parent)]
        w, x, y, z = f.quat
        local = pin.SE3(pin.Quaternion(w, x, y, z).toRotationMatrix(), np.array(f.pos, dtype=float))
        model.addFrame(pin.Frame(f.name, parent.parentJoint, model.getFrameId(f.parent),
                                 parent.placement * local, pin.FrameType.OP_FRAME))
    names = tuple(model.names[1:])
    if names != robot.arm_joints:
        raise ModelError(f"expected arm joints {robot.arm_joints}, found {names}", where=path)
    return model


class ArmKinematics:
    """Forward kinematics and frame Jacobians of one robot's arm.

    ``lower``/``upper`` (n,) joint limits [rad]; ``velocity`` (n,) [rad/s] and ``effort`` (n,) [N m]
    limits; ``ready`` (n,) the model's ready pose [rad], where inverse kinematics starts and what its null
    space leans towards; ``home`` (n,) the configuration the robot parks in and returns to [rad]: ``home``
    if given (a workcell's park pose, :meth:`~ergosim.scenes.workcell.Workcell.robot_home`), else the ready
    pose; ``robot`` the :class:`RobotModel`.
    """

    def __init__(self, robot: RobotModel, home=None) -> None:
        self.robot = robot
        self.model = _build(robot)
        self.data = self.model.createData()
        self.tcp = self.frame_id(robot.tcp_frame)
        self.lower = self.model.lowerPositionLimit.copy()
        self.upper = self.model.upperPositionLimit.copy()
        self.velocity = self.model.velocityLimit.copy()
        self.effort = self.model.effortLimit.copy()
        self.ready = np.array(robot.home, dtype=float)
        self.home = self.ready.copy() if home is None else np.array(home, dtype=float)

    @property
    def nq(self) -> int:
        return self.model.nq

    def frame_id(self, name: str) -> int:
        if not self.model.existFrame(name):
            raise ModelError(f"no frame {name!r} in the {self.robot.name} model", where="ArmKinematics")
        return self.model.getFrameId(name)

    def fk(self, q: np.ndarray, frame: int | str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Pose of ``frame`` (default the TCP) for (n,) ``q`` [rad]: position (3,) [m], rotation (3, 3)."""
        fid = self.tcp if frame is None else (frame if isinstance(frame, int) else self.frame_id(frame))
        pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        oMf = pin.updateFramePlacement(self.model, self.data, fid)
        return oMf.translation.copy(), oMf.rotation.copy()

    def jacobian(self, q: np.ndarray, frame: int | str | None = None) -> np.ndarray:
        """(6, n) Jacobian of ``frame``: rows 0-2 the linear velocity of its origin, rows 3-5 its angular
        velocity, both in base-frame axes (pinocchio LOCAL_WORLD_ALIGNED)."""
        fid = self.tcp if frame is None else (frame if isinstance(frame, int) else self.frame_id(frame))
        return pin.computeFrameJacobian(self.model, self.data, np.asarray(q, dtype=float), fid,
                                        pin.LOCAL_WORLD_ALIGNED)

    def within_limits(self, q: np.ndarray, tol: float = 1e-9) -> bool:
        q = np.asarray(q)
        return bool(np.all(q >= self.lower - tol) and np.all(q <= self.upper + tol))

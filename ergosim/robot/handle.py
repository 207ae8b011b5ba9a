"""One robot of a compiled scene, found by name: the small compiled object skills and scenes pass around.

A workcell may hold several robots. The first keeps the names of its model's MJCF (``base_link``,
``shoulder_pan_joint``, ...); every further one is attached with the prefix ``<robot name>.``
(``robot2.base_link``). :class:`RobotHandle` resolves one robot's joints, actuators, TCP site and bodies
once, from its :class:`~ergosim.robot.robot_model.RobotModel`, so no code indexes ``ctrl`` or ``qpos`` by
position.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np

from ergosim.robot.robot_model import RobotModel

__all__ = ["RobotHandle", "robot_prefix"]


def robot_prefix(index: int, name: str) -> str:
    """Name prefix of the ``index``-th robot (0-based) of a cell, called ``name``: "" for the first."""
    return "" if index == 0 else f"{name}."


@dataclasses.dataclass(frozen=True, eq=False)
class RobotHandle:
    """Indices of one robot in ``model``: ``arm_qpos`` (n,) and ``finger_qpos`` (2,) qpos addresses,
    ``arm_ctrl`` the slice of its n arm actuators, ``grip_ctrl`` its gripper actuator (ctrl = opening per
    finger [m]), ``tcp`` the TCP site id; body names ``base``, ``hand`` (holds a grasped part) and
    ``fingers``; ``robot`` its model."""

    name: str
    prefix: str
    arm_qpos: np.ndarray
    finger_qpos: np.ndarray
    finger_joints: tuple[int, ...]
    arm_ctrl: slice
    grip_ctrl: int
    tcp: int
    base: str
    hand: str
    fingers: tuple[str, str]
    robot: RobotModel

    @classmethod
    def find(cls, model: mujoco.MjModel, name: str, prefix: str, robot: RobotModel) -> RobotHandle:
        """The handle of the robot of model ``robot`` called ``name`` in ``model``, its names prefixed by
        ``prefix``."""
        arm = [model.actuator(prefix + a).id for a in robot.arm_actuators]
        if arm != list(range(arm[0], arm[0] + len(arm))):
            raise AssertionError(f"the arm actuators of {name!r} are not contiguous: {arm}")
        return cls(
            name=name, prefix=prefix,
            arm_qpos=np.array([model.joint(prefix + j).qposadr[0] for j in robot.arm_joints]),
            finger_qpos=np.array([model.joint(prefix + j).qposadr[0] for j in robot.finger_joints]),
            finger_joints=tuple(model.joint(prefix + j).id for j in robot.finger_joints),
            arm_ctrl=slice(arm[0], arm[0] + len(arm)),
            grip_ctrl=model.actuator(prefix + robot.gripper_actuator).id,
            tcp=model.site(prefix + robot.tcp_site).id,
            base=prefix + robot.base, hand=prefix + robot.hand,
            fingers=(prefix + robot.gripper.bodies[0], prefix + robot.gripper.bodies[1]),
            robot=robot,
        )

    def gripper_open(self, model: mujoco.MjModel) -> float:
        """The widest opening per finger [m] (the gripper actuator's upper control limit)."""
        return float(model.actuator_ctrlrange[self.grip_ctrl, 1])


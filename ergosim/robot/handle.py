"""One Panda of a compiled scene, found by name: the small compiled object skills and scenes pass around.

A workcell may hold several Pandas. The first keeps the names of the Panda's MJCF (``panda_link0``,
``panda_joint1``, ``panda_tcp``, ``panda_actuator1``, ...); every further one is attached with the prefix
``<robot name>.`` (``robot2.panda_link0``). :class:`PandaHandle` resolves one robot's joints, actuators, TCP
site and bodies once, so no code indexes ``ctrl`` or ``qpos`` by position.
"""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np

from ergosim.robot.mjcf import ARM_ACTUATORS, ARM_JOINTS, FINGER_JOINTS, GRIPPER_ACTUATOR, TCP_SITE

__all__ = ["PandaHandle", "robot_prefix"]


def robot_prefix(index: int, name: str) -> str:
    """Name prefix of the ``index``-th robot (0-based) of a cell, called ``name``: "" for the first."""
    return "" if index == 0 else f"{name}."


@dataclasses.dataclass(frozen=True, eq=False)
class PandaHandle:
    """Indices of one Panda in ``model``: ``arm_qpos`` (7,) and ``finger_qpos`` (2,) qpos addresses,
    ``arm_ctrl`` the slice of its 7 arm actuators, ``grip_ctrl`` its gripper actuator (ctrl = opening per
    finger [m]), ``tcp`` the TCP site id; body names ``base`` (``panda_link0``), ``hand``, ``fingers``."""

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

    @classmethod
    def find(cls, model: mujoco.MjModel, name: str, prefix: str = "") -> PandaHandle:
        arm = [model.actuator(prefix + a).id for a in ARM_ACTUATORS]
        if arm != list(range(arm[0], arm[0] + len(arm))):
            raise AssertionError(f"the arm actuators of {name!r} are not contiguous: {arm}")
        return cls(
            name=name, prefix=prefix,
            arm_qpos=np.array([model.joint(prefix + j).qposadr[0] for j in ARM_JOINTS]),
            finger_qpos=np.array([model.joint(prefix + j).qposadr[0] for j in FINGER_JOINTS]),
            finger_joints=tuple(model.joint(prefix + j).id for j in FINGER_JOINTS),
            arm_ctrl=slice(arm[0], arm[0] + len(arm)),
            grip_ctrl=model.actuator(prefix + GRIPPER_ACTUATOR).id,
            tcp=model.site(prefix + TCP_SITE).id,
            base=prefix + "panda_link0", hand=prefix + "panda_hand",
            fingers=(prefix + "panda_leftfinger", prefix + "panda_rightfinger"),
        )

    def gripper_open(self, model: mujoco.MjModel) -> float:
        """The widest opening per finger [m] (the gripper actuator's upper control limit)."""
        return float(model.actuator_ctrlrange[self.grip_ctrl, 1])

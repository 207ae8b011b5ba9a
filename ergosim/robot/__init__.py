"""The Panda: MJCF built from example-robot-data's URDF, pinocchio kinematics, IK, trajectories, skills."""

from ergosim.robot.assets import panda_description_dir, panda_mesh_dir, panda_urdf
from ergosim.robot.ik import IKResult, pose_error, solve_ik
from ergosim.robot.kinematics import TCP_FRAME, PandaKinematics
from ergosim.robot.mjcf import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    FINGER_JOINTS,
    GRIPPER_ACTUATOR,
    HOME_QPOS,
    TCP_SITE,
    PandaGains,
    panda_xml,
)
from ergosim.robot.model import compile_spec, load_mjcf, panda_mjcf_text, panda_spec
from ergosim.robot.skills import Handover, PickPlace, Skill, SkillParams, handover, pick_place
from ergosim.robot.status import SkillResult, SkillStatus
from ergosim.robot.trajectory import (
    BaseFrame,
    MotionLimits,
    PathError,
    Pose,
    joint_trajectory,
    segment_trajectory,
    transit_trajectory,
    trapezoid,
)
from ergosim.robot.urdf import Urdf, read_urdf

__all__ = [
    "panda_description_dir",
    "panda_mesh_dir",
    "panda_urdf",
    "IKResult",
    "pose_error",
    "solve_ik",
    "TCP_FRAME",
    "PandaKinematics",
    "ARM_ACTUATORS",
    "ARM_JOINTS",
    "FINGER_JOINTS",
    "GRIPPER_ACTUATOR",
    "HOME_QPOS",
    "TCP_SITE",
    "PandaGains",
    "panda_xml",
    "compile_spec",
    "load_mjcf",
    "panda_mjcf_text",
    "panda_spec",
    "Handover",
    "PickPlace",
    "Skill",
    "SkillParams",
    "handover",
    "pick_place",
    "SkillResult",
    "SkillStatus",
    "BaseFrame",
    "MotionLimits",
    "PathError",
    "Pose",
    "joint_trajectory",
    "segment_trajectory",
    "transit_trajectory",
    "trapezoid",
    "Urdf",
    "read_urdf",
]

"""Robots: the :class:`RobotModel` contract and its registry (the Panda and the UR5 from
example-robot-data), MJCF built from the URDF, pinocchio kinematics, IK, trajectories, skills."""

from ergosim.robot.assets import erd_file, erd_share, resolve_url
from ergosim.robot.ik import IKResult, pose_error, solve_ik
from ergosim.robot.kinematics import ArmKinematics, PandaKinematics
from ergosim.robot.mjcf import ArmActuation, GripperActuation, MjcfRecipe, RobotFiles, robot_mjcf
from ergosim.robot.model import MODELS_DIR, compile_spec, load_mjcf, model_dir, robot_files, robot_spec
from ergosim.robot.panda import PANDA
from ergosim.robot.robot_model import (
    AddedFrame,
    Gripper,
    Mount,
    RobotModel,
    get_robot,
    register_robot,
    robot_names,
)
from ergosim.robot.skills import Handover, PickPlace, Skill, SkillParams, handover, pick_place
from ergosim.robot.ssm import SSMParams, allowed_speed, protective_distance, speed_scale
from ergosim.robot.status import SKILL_PHASES, SkillResult, SkillStatus
from ergosim.robot.time_scaling import speed_profile, trapezoid
from ergosim.robot.trajectory import (
    CONTACT_SPEED,
    SEGMENT_KINDS,
    TRANSIT_SPEED,
    BaseFrame,
    MotionLimits,
    PathError,
    Pose,
    SpeedLimit,
    joint_trajectory,
    line_trajectory,
    segment_trajectory,
    transit_trajectory,
)
from ergosim.robot.ur5 import UR5
from ergosim.robot.urdf import Urdf, read_urdf

__all__ = [
    "RobotModel",
    "Gripper",
    "Mount",
    "AddedFrame",
    "register_robot",
    "robot_names",
    "get_robot",
    "PANDA",
    "UR5",
    "SSMParams",
    "allowed_speed",
    "protective_distance",
    "speed_scale",
    "erd_share",
    "erd_file",
    "resolve_url",
    "IKResult",
    "pose_error",
    "solve_ik",
    "ArmKinematics",
    "PandaKinematics",
    "ArmActuation",
    "GripperActuation",
    "MjcfRecipe",
    "RobotFiles",
    "robot_mjcf",
    "MODELS_DIR",
    "model_dir",
    "robot_files",
    "robot_spec",
    "compile_spec",
    "load_mjcf",
    "Handover",
    "PickPlace",
    "Skill",
    "SkillParams",
    "handover",
    "pick_place",
    "SKILL_PHASES",
    "SkillResult",
    "SkillStatus",
    "CONTACT_SPEED",
    "SEGMENT_KINDS",
    "TRANSIT_SPEED",
    "SpeedLimit",
    "BaseFrame",
    "MotionLimits",
    "PathError",
    "Pose",
    "joint_trajectory",
    "line_trajectory",
    "segment_trajectory",
    "transit_trajectory",
    "speed_profile",
    "trapezoid",
    "Urdf",
    "read_urdf",
]

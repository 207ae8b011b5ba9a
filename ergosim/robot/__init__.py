"""Robots: the :class:`RobotModel` contract and its registry (the bundled robots come from
example-robot-data, each in its own module), MJCF built from the URDF, pinocchio kinematics, IK,
trajectories, and skills planned as timed programs (skill_motion, skill_plan, skill_program), stepped by an
executor (skill_exec)."""

from ergosim.robot import panda as _first  # noqa: F401  (register the bundled robots)
from ergosim.robot import ur5 as _second  # noqa: F401
from ergosim.robot.assets import erd_file, erd_share, resolve_url
from ergosim.robot.ik import IKResult, pose_error, solve_ik
from ergosim.robot.kinematics import ArmKinematics
from ergosim.robot.mjcf import ArmActuation, GripperActuation, MjcfRecipe, RobotFiles, robot_mjcf
from ergosim.robot.model import MODELS_DIR, compile_spec, load_mjcf, model_dir, robot_files, robot_spec
from ergosim.robot.robot_model import (
    AddedFrame,
    Gripper,
    Mount,
    RobotModel,
    default_robot,
    get_robot,
    register_robot,
    robot_names,
)
from ergosim.robot.skill_motion import Motion, MotionPlanner, Waypoint
from ergosim.robot.skill_plan import CarryGoal, CarryPlan, CarryPlanner, RobotView
from ergosim.robot.skill_program import SkillProgram
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
from ergosim.robot.urdf import Urdf, read_urdf

__all__ = [
    "RobotModel",
    "Gripper",
    "Mount",
    "AddedFrame",
    "register_robot",
    "robot_names",
    "get_robot",
    "default_robot",
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
    "Motion",
    "MotionPlanner",
    "Waypoint",
    "CarryGoal",
    "CarryPlan",
    "CarryPlanner",
    "RobotView",
    "SkillProgram",
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

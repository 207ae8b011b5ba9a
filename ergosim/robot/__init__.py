"""The Panda: MJCF built from example-robot-data's URDF, pinocchio kinematics, IK, trajectories, and skills
planned as timed programs (skill_motion, skill_plan, skill_program), stepped by an executor (skill_exec)."""

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
from ergosim.robot.skill_motion import Motion, MotionPlanner, Waypoint
from ergosim.robot.skill_plan import CarryGoal, CarryPlan, CarryPlanner, RobotView
from ergosim.robot.skill_program import SkillProgram
from ergosim.robot.skills import Handover, PickPlace, Skill, SkillParams, handover, pick_place
from ergosim.robot.ssm import SSMParams, allowed_speed, protective_distance, speed_scale
from ergosim.robot.status import SKILL_PHASES, SkillResult, SkillStatus
from ergosim.robot.time_scaling import speed_profile, trapezoid
from ergosim.robot.trajectory import (
    CONTACT_SPEED,
    PANDA_MAX_ROTATION,
    PANDA_MAX_ROTATION_ACCEL,
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
    "SSMParams",
    "allowed_speed",
    "protective_distance",
    "speed_scale",
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
    "PANDA_MAX_ROTATION",
    "PANDA_MAX_ROTATION_ACCEL",
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

"""The Franka Emika Panda with the Franka Hand, from example-robot-data's URDF.

Names of its MJCF (``models/panda/panda.xml``), the recipe that builds it (:mod:`ergosim.robot.mjcf`) and
the figures a URDF does not hold, each with its source.
"""

from __future__ import annotations

from ergosim.robot.mjcf import ArmActuation, GripperActuation, MjcfRecipe
from ergosim.robot.robot_model import Gripper, Mount, RobotModel, register_robot

__all__ = ["PANDA_URDF", "ARM_JOINTS", "FINGER_JOINTS", "ARM_ACTUATORS", "GRIPPER_ACTUATOR", "TCP_SITE",
           "TCP_FRAME", "HOME_QPOS", "PANDA_RECIPE", "PANDA"]

PANDA_URDF = "robots/panda_description/urdf/panda.urdf"
"""The URDF in example-robot-data (7 arm joints, hand, two prismatic fingers, ``panda_hand_tcp``)."""

ARM_JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")
ARM_ACTUATORS = tuple(f"panda_actuator{i}" for i in range(1, 8))
GRIPPER_ACTUATOR = "panda_gripper"
TCP_SITE = "panda_tcp"
TCP_FRAME = "panda_hand_tcp"
"""The URDF frame of the grasp centre (between the fingertip pads, 0.1034 m from the hand); the MuJoCo
site ``panda_tcp`` sits at the same pose."""
HOME_QPOS = (0.0, -0.785398, 0.0, -2.356194, 0.0, 1.570796, 0.785398)
"""The ``home`` arm configuration [rad]: Franka's ready pose (hand down, elbow up)."""

PANDA_RECIPE = MjcfRecipe(
    name="panda",
    root="panda_link0",
    arm_joints=ARM_JOINTS,
    actuators=ARM_ACTUATORS,
    # kp [N m/rad] assumed (stiff enough to track within ~1 mrad under gravity compensation);
    # armature: reflected rotor inertia, assumed
    arm=ArmActuation(kp=(4500.0, 4500.0, 3500.0, 3500.0, 2000.0, 2000.0, 2000.0), dampratio=1.0,
                     armature=0.1),
    # force limit: Franka Hand 70 N continuous grasp force per finger x 2 (Franka datasheet); kp assumed
    gripper=GripperActuation(joints=FINGER_JOINTS, tendon="panda_split", actuator=GRIPPER_ACTUATOR,
                             kp=1000.0, force=140.0),
    sites={TCP_FRAME: TCP_SITE},
    home=HOME_QPOS,
    finger_links=("panda_leftfinger", "panda_rightfinger"),
    # a tenth of each visual part's 134,300 triangles (assumed: stills at 960x540 look alike, docs/video.md)
    visual_keep=0.15,
)
"""How ``models/panda/panda.xml`` is built from the URDF (models/panda/README.md)."""

PANDA = register_robot(RobotModel(
    name="panda",
    description="Franka Emika Panda with the Franka Hand (example-robot-data)",
    urdf=PANDA_URDF,
    recipe=PANDA_RECIPE,
    tcp_frame=TCP_FRAME,
    base="panda_link0",
    hand="panda_hand",
    # Franka Hand: 80 mm stroke, 70 N continuous grasp force (Franka Emika datasheet)
    gripper=Gripper(max_opening=0.08, force=70.0, bodies=("panda_leftfinger", "panda_rightfinger")),
    payload=3.0,  # kg, Franka Emika Panda datasheet
    reach=0.855,  # m, Franka Emika Panda datasheet
    max_speed=1.7,  # m/s, libfranka rate_limiting.h kMaxTranslationalVelocity
    max_rotation=2.5,  # rad/s, libfranka kMaxRotationalVelocity
    max_rotation_accel=25.0,  # rad/s^2, libfranka kMaxRotationalAcceleration
    mount=Mount(link="panda_link1", pedestal=(0.13, 0.11), offset_x=-0.04),  # pedestal assumed
    tuck=(0.0, -1.7, 0.0, -3.0, 0.0, 1.5, 0.785398),  # forearm folded back over the base, hand down
    source="example-robot-data robots/panda_description (from frankaemika/franka_ros franka_description)",
    licence="Apache-2.0",
))
"""The Panda, registered as ``robot.model = "panda"``."""

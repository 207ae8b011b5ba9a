"""The Universal Robots UR5 with example-robot-data's two-finger gripper (``ur5_gripper.urdf``).

The URDF models the gripper as a rigid fork on ``tool0``: a crossbar and two 5 x 20 x 50 mm finger plates
whose inner faces are 55 mm apart. ergosim makes the two plates a parallel-jaw gripper (:func:`edit_urdf`):
each plate rides a prismatic joint along the fork's axis, open (55 mm) at the URDF's pose and closing to
touch; the second mirrors the first, as the Panda's fingers do. The TCP is added at the grasp centre,
10 mm above the plates' tips (the Panda's pads reach 9.5 mm past its TCP), turned a quarter turn about
z so the fingers close along its y axis like the Panda's.
"""

from __future__ import annotations

import dataclasses
import math

from ergosim.robot.mjcf import ArmActuation, GripperActuation, MjcfRecipe
from ergosim.robot.robot_model import AddedFrame, Gripper, Mount, RobotModel, register_robot
from ergosim.robot.urdf import Inertial, Joint, Link, Origin, Shape, Urdf

__all__ = ["UR5_URDF", "ARM_JOINTS", "FINGER_JOINTS", "ARM_ACTUATORS", "GRIPPER_ACTUATOR", "TCP_SITE",
           "TCP_FRAME", "HOME_QPOS", "UR5_RECIPE", "UR5", "edit_urdf"]

UR5_URDF = "robots/ur_description/urdf/ur5_gripper.urdf"

ARM_JOINTS = ("shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
              "wrist_3_joint")
FINGER_JOINTS = ("ur5_left_finger_joint", "ur5_right_finger_joint")
FINGER_LINKS = ("ur5_left_finger", "ur5_right_finger")
ARM_ACTUATORS = ("shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3")
GRIPPER_ACTUATOR = "ur5_gripper"
TCP_FRAME = "ur5_tcp_link"
TCP_SITE = "ur5_tcp"
HOME_QPOS = (0.0, -1.570796, 1.570796, -1.570796, -1.570796, 0.0)
"""The ``home`` arm configuration [rad]: upper arm up, forearm level, tool pointing down."""

FINGER_HALF_OPEN = 0.0275
"""Per-finger travel [m]: the inner faces of the URDF's plates are 2 x 27.5 mm apart (plates 5 mm thick at
x = +-30 mm)."""
_PLATE = (0.005, 0.02, 0.05)  # the URDF's finger plate boxes [m]
_PLATE_Z = 0.035  # their centre along tool0 z [m]
TCP_DEPTH = 0.05
"""TCP along tool0 z [m]: 10 mm short of the plates' tips at 60 mm (assumed, as the Panda's 9.5 mm)."""
_FINGER_MASS = 0.05  # kg, assumed (a 5 x 20 x 50 mm aluminium plate is 14 g; with its carriage)


def _finger(name: str, joint: str, side: int) -> tuple[Link, Joint]:
    box = Shape("box", Origin((side * _PLATE[0] / 2, 0.0, _PLATE_Z)), size=_PLATE)
    i = _FINGER_MASS * (0.02**2 + 0.05**2) / 12  # a uniform plate's largest moment, used for all three
    link = Link(name, Inertial(Origin((side * _PLATE[0] / 2, 0.0, _PLATE_Z)), _FINGER_MASS,
                               (i, i, i, 0.0, 0.0, 0.0)), visuals=(box,), collisions=(box,))
    # effort 100 N as the Panda URDF's fingers; velocity 0.05 m/s per finger (assumed)
    joint = Joint(joint, "prismatic", "tool0", name, Origin(), axis=(float(side), 0.0, 0.0), lower=0.0,
                  upper=FINGER_HALF_OPEN, effort=100.0, velocity=0.05, damping=0.0)
    return link, joint


def _palm(shapes: tuple[Shape, ...]) -> tuple[Shape, ...]:
    """The fork's shapes without its two finger plates (at x = +-30 mm)."""
    return tuple(s for s in shapes if abs(abs(s.origin.xyz[0]) - 0.03) > 1e-9)


def edit_urdf(urdf: Urdf) -> Urdf:
    """The URDF with the fork's plates on prismatic joints and a TCP link (module docstring)."""
    tool0 = urdf.links["tool0"]
    plates = [s for s in tool0.collisions if s.kind == "box" and abs(abs(s.origin.xyz[0]) - 0.03) < 1e-9]
    if len(plates) != 2:
        raise ValueError(f"expected the fork's two finger plates on tool0, found {len(plates)}")
    links = dict(urdf.links)
    links["tool0"] = dataclasses.replace(tool0, visuals=_palm(tool0.visuals),
                                         collisions=_palm(tool0.collisions))
    joints = list(urdf.joints)
    for name, joint, side in zip(FINGER_LINKS, FINGER_JOINTS, (1, -1), strict=True):
        link, j = _finger(name, joint, side)
        links[name] = link
        joints.append(j)
    links[TCP_FRAME] = Link(TCP_FRAME, None)
    joints.append(Joint("ur5_tcp_joint", "fixed", "tool0", TCP_FRAME,
                        Origin((0.0, 0.0, TCP_DEPTH), (0.0, 0.0, math.pi / 2))))
    return dataclasses.replace(urdf, links=links, joints=tuple(joints))


UR5_RECIPE = MjcfRecipe(
    name="ur5",
    root="base_link",
    arm_joints=ARM_JOINTS,
    actuators=ARM_ACTUATORS,
    # kp [N m/rad] assumed (as the Panda's, by joint size); armature assumed
    arm=ArmActuation(kp=(4500.0, 4500.0, 3500.0, 2000.0, 2000.0, 2000.0), dampratio=1.0, armature=0.1),
    # force limit assumed equal to the Panda's (140 N on the tendon); kp assumed
    gripper=GripperActuation(joints=FINGER_JOINTS, tendon="ur5_split", actuator=GRIPPER_ACTUATOR, kp=1000.0,
                             force=140.0),
    sites={TCP_FRAME: TCP_SITE},
    home=HOME_QPOS,
    finger_links=FINGER_LINKS,
    skip_links=("ee_link",),  # a massless 1 cm marker box inside the flange
    fallback_rgba=(0.2, 0.2, 0.22, 1.0),
)
"""How ``models/ur5/ur5.xml`` is built from the URDF (models/ur5/README.md)."""

UR5 = register_robot(RobotModel(
    name="ur5",
    description="Universal Robots UR5 with a two-finger gripper (example-robot-data ur5_gripper.urdf)",
    urdf=UR5_URDF,
    recipe=UR5_RECIPE,
    tcp_frame=TCP_FRAME,
    base="base_link",
    hand="tool0",
    gripper=Gripper(max_opening=2 * FINGER_HALF_OPEN, force=70.0, bodies=FINGER_LINKS),  # force assumed
    payload=5.0,  # kg, UR5 datasheet
    reach=0.85,  # m, UR5 datasheet
    max_speed=1.0,  # m/s, UR5 datasheet (tool speed)
    max_rotation=math.pi,  # rad/s, the joints' 180 deg/s (UR5 datasheet) about one axis
    max_rotation_accel=25.0,  # rad/s^2, assumed (as the Panda's)
    mount=Mount(link="shoulder_link", pedestal=(0.10, 0.10), offset_x=0.0),  # pedestal assumed (base 149 mm)
    tuck=(0.0, -2.2, 2.0, -1.370796, -1.570796, 0.0),  # upper arm back, forearm over the base, tool down
    add_frames=(AddedFrame(TCP_FRAME, "tool0", (0.0, 0.0, TCP_DEPTH),
                           (math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4))),),
    edit_urdf=edit_urdf,
    source="example-robot-data robots/ur_description (from ros-industrial/universal_robot ur_description)",
    licence="BSD (ur_description)",
))
"""The UR5, registered as ``robot.model = "ur5"``."""

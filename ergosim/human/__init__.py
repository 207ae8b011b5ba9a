"""The kinematic human upper body: anthropometry, MJCF generation, the canonical-angle view, and the mocap
segments that show it in a physics scene."""

from ergosim.human.anthropometry import PROPORTIONS, SEGMENT_SCALES, Segments, segment_lengths
from ergosim.human.joints import DRIVEN_SPECS, JOINT_SPECS, STANCE_SPECS, JointSpec, joint_spec
from ergosim.human.legs import Legs
from ergosim.human.mjcf import HOME_POSTURE, humanoid_xml
from ergosim.human.mocap import MocapHuman, add_mocap_segments
from ergosim.human.model import (
    EYE_SITE,
    HAND_SITES,
    PELVIS_BODY,
    ROOT_BODY,
    HumanModel,
    HumanReadout,
    body_qpos,
    human_spec,
)

__all__ = [
    "PROPORTIONS",
    "SEGMENT_SCALES",
    "Segments",
    "segment_lengths",
    "JOINT_SPECS",
    "STANCE_SPECS",
    "DRIVEN_SPECS",
    "Legs",
    "JointSpec",
    "joint_spec",
    "HOME_POSTURE",
    "humanoid_xml",
    "EYE_SITE",
    "HAND_SITES",
    "ROOT_BODY",
    "PELVIS_BODY",
    "body_qpos",
    "HumanModel",
    "HumanReadout",
    "MocapHuman",
    "add_mocap_segments",
    "human_spec",
]

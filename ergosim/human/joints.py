"""Hinge axes and ranges of motion of the kinematic human, one per canonical angle.

Axes are in the parent segment's frame (x forward, y left, z up in the standing neutral posture) and are
chosen so that a positive hinge angle is the positive direction of :mod:`ergosim.posture`. The left arm
mirrors the right arm through the sagittal plane, so its axes are mirrored and its signs keep the same
anatomical meaning. Hinges of one segment compose intrinsically in the order listed (e.g. the trunk is
flexion about y, then lateral bend about the bent x, then axial rotation about the bent z).

Ranges of motion [deg] are the active ranges of the American Academy of Orthopaedic Surgeons (Greene &
Heckman, *The Clinical Measurement of Joint Motion*, AAOS 1994) for the neck, shoulder, elbow, forearm and
wrist; trunk flexion is measured from the vertical with the pelvis fixed, so it includes hip flexion
(thoracolumbar 80 deg + hip); clavicle elevation (shrug) 0..40 deg follows Inman, Saunders & Abbott
(1944, J Bone Joint Surg 26:1-30).
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["JointSpec", "JOINT_SPECS", "joint_spec"]


class JointSpec(NamedTuple):
    """One hinge: canonical name, axis of the right (or midline) side, range [deg]."""

    name: str
    axis: tuple[float, float, float]
    range_deg: tuple[float, float]


_MIDLINE = (
    JointSpec("trunk_flexion", (0, 1, 0), (-30.0, 100.0)),
    JointSpec("trunk_lateral_bend", (1, 0, 0), (-35.0, 35.0)),
    JointSpec("trunk_rotation", (0, 0, 1), (-45.0, 45.0)),
    JointSpec("neck_flexion", (0, 1, 0), (-45.0, 45.0)),
    JointSpec("neck_lateral_bend", (1, 0, 0), (-45.0, 45.0)),
    JointSpec("neck_rotation", (0, 0, 1), (-60.0, 60.0)),
)
# The right arm hangs along -z with the palm facing +y (medial) and the thumb forward.
_RIGHT_ARM = (
    JointSpec("shoulder_elevation", (-1, 0, 0), (0.0, 40.0)),
    JointSpec("shoulder_flexion", (0, -1, 0), (-60.0, 180.0)),
    JointSpec("shoulder_abduction", (-1, 0, 0), (-45.0, 180.0)),
    JointSpec("shoulder_rotation", (0, 0, 1), (-90.0, 70.0)),
    JointSpec("elbow_flexion", (0, -1, 0), (0.0, 150.0)),
    JointSpec("forearm_pronation", (0, 0, 1), (-80.0, 80.0)),
    JointSpec("wrist_flexion", (1, 0, 0), (-70.0, 80.0)),
    JointSpec("wrist_deviation", (0, 1, 0), (-20.0, 30.0)),
)


def _mirror(axis: tuple[float, float, float]) -> tuple[float, float, float]:
    # Reflecting through the sagittal plane (y -> -y) turns a rotation about a into one about -M a.
    x, y, z = axis
    return (-x, y, -z)


JOINT_SPECS: tuple[JointSpec, ...] = (
    _MIDLINE
    + _RIGHT_ARM
    + tuple(JointSpec(f"left_{j.name}", _mirror(j.axis), j.range_deg) for j in _RIGHT_ARM)
)
"""Every hinge; the names are :data:`ergosim.posture.HUMAN_JOINTS` (as a set; order is the kinematic tree)."""

_BY_NAME = {j.name: j for j in JOINT_SPECS}


def joint_spec(name: str) -> JointSpec:
    """The hinge spec of a canonical joint name (KeyError if unknown)."""
    return _BY_NAME[name]

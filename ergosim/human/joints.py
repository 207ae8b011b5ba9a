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

Besides the 22 posture hinges, the body stands: :data:`STANCE_SPECS` are the pelvis's step and turn on the
floor and the knees' flexion (:data:`ergosim.posture.STANCE`), and :data:`DRIVEN_SPECS` are the joints that
follow the knee and the ankle (the pelvis moving over the feet, the hips, the left leg) so that both feet
stay flat where they stand (:mod:`ergosim.human.legs`). Knee flexion 0..135 deg is AAOS's active range;
ankle dorsiflexion -25..40 deg is the weight-bearing range with the heel down (the lunge test reaches about
40 deg, Bennell et al. 1998, Aust J Physiother 44:175; leaning the shank back beyond 25 deg with flat feet
is assumed to be out of balance before it is out of range); hip flexion -30..160 deg covers AAOS's hip
extension 30 deg and a deep squat. The stance may move 0.6 m and turn 120 deg either way (the cell's
standing area is tighter, :mod:`ergosim.worker.stance`).
"""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["JointSpec", "JOINT_SPECS", "STANCE_SPECS", "DRIVEN_SPECS", "joint_spec"]


class JointSpec(NamedTuple):
    """One joint: name, axis of the right (or midline) side, range ([deg] for a hinge, [m] for a slide)."""

    name: str
    axis: tuple[float, float, float]
    range_deg: tuple[float, float]
    kind: str = "hinge"


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
"""Every posture hinge; the names are :data:`ergosim.posture.HUMAN_JOINTS` (as a set; order is the kinematic
tree)."""

STANCE_SPECS: tuple[JointSpec, ...] = (
    JointSpec("pelvis_x", (1, 0, 0), (-0.6, 0.6), "slide"),
    JointSpec("pelvis_y", (0, 1, 0), (-0.6, 0.6), "slide"),
    JointSpec("pelvis_rotation", (0, 0, 1), (-120.0, 120.0)),
    JointSpec("knee_flexion", (0, 1, 0), (0.0, 135.0)),  # the right knee; positive: the shank swings back
    JointSpec("ankle_dorsiflexion", (0, -1, 0), (-25.0, 40.0)),  # the right ankle; positive: shank forward
)
"""The stance joints, named as :data:`ergosim.posture.STANCE` (knee_flexion is the right knee's hinge)."""

DRIVEN_SPECS: tuple[JointSpec, ...] = (
    JointSpec("pelvis_shift", (1, 0, 0), (-0.5, 0.5), "slide"),
    JointSpec("pelvis_drop", (0, 0, -1), (0.0, 0.8), "slide"),
    JointSpec("hip_flexion", (0, -1, 0), (-30.0, 160.0)),
    JointSpec("left_hip_flexion", (0, -1, 0), (-30.0, 160.0)),
    JointSpec("left_knee_flexion", (0, 1, 0), (0.0, 135.0)),
    JointSpec("left_ankle_dorsiflexion", (0, -1, 0), (-25.0, 40.0)),
)
"""Joints set from ``knee_flexion`` and ``ankle_dorsiflexion`` (never chosen on their own): the pelvis
moves (``pelvis_shift`` forward, ``pelvis_drop`` down) to where the two-link leg puts the hip over the flat
foot, the hip flexes by the knee angle less the shank's lean so the pelvis stays upright, and the left leg
mirrors the right (:mod:`ergosim.human.legs`)."""

_BY_NAME = {j.name: j for j in JOINT_SPECS + STANCE_SPECS + DRIVEN_SPECS}


def joint_spec(name: str) -> JointSpec:
    """The spec of a joint of the human by name (KeyError if unknown)."""
    return _BY_NAME[name]

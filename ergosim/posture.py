"""Canonical upper-body joint angles: the contract between motion capture, the human model and RULA.

A *posture* maps canonical names to angles in **degrees**: a float for one frame, or a numpy array of
shape (n,) for a trajectory of n frames. The RULA input is the 14 names in :data:`ANGLE_NAMES` (trunk,
neck and the dominant, right, arm). The human model has one hinge per name, in radians, with the same
sign; the left arm repeats the arm names with the prefix ``left_``.

Body frame: x forward, y to the person's left, z up (right-handed), the person standing upright.

=====================  =============================================================================
name                   positive direction (0 = anatomical neutral: upright, arms hanging, palms in)
=====================  =============================================================================
trunk_flexion          bending forward (about +y at the lumbar joint); negative = extension
trunk_lateral_bend     bending to the right (about +x)
trunk_rotation         twisting to the left (about +z)
neck_flexion           chin towards chest (about +y at C7); negative = extension
neck_lateral_bend      ear towards the right shoulder (about +x)
neck_rotation          looking to the left (about +z)
shoulder_elevation     shrugging: the clavicle raised at the sternoclavicular joint (>= 0)
shoulder_flexion       arm raised forward (sagittal plane); negative = extension (arm behind)
shoulder_abduction     arm raised sideways, away from the body; negative = adduction across the body
shoulder_rotation      internal (medial) rotation of the upper arm about its long axis
elbow_flexion          0 = straight arm, positive = flexed (about 0..145)
forearm_pronation      pronation; 0 = mid-position (thumb up), negative = supination
wrist_flexion          palmar flexion; negative = extension (dorsiflexion)
wrist_deviation        ulnar deviation; negative = radial deviation
=====================  =============================================================================

For the left arm the same names carry the same *anatomical* meaning (``left_shoulder_abduction`` > 0 is
the left arm away from the body), so the joint axes are mirrored, not the signs.

The worker also stands: :data:`STANCE` is where the pelvis stands and turns on the floor, in the worker's
frame (the cell's worker position and facing), and how far the knees bend. RULA does not score it; it
comes with every motion beside the posture, as a suit's pelvis position and knee angles do.

=====================  =============================================================================
pelvis_x               [m] forward step of the stance (the feet, and the pelvis above them when the legs are
                       straight) from the worker's position
pelvis_y               [m] step to the left
pelvis_rotation        [deg] the whole body turned to the left (feet, pelvis and all above)
knee_flexion           [deg] both knees, 0 = straight
ankle_dorsiflexion     [deg] both shanks leaning forward over the flat feet; negative leans them back, which
                       moves the hips back behind the feet (a stoop); with the knees it sets where the
                       pelvis is (:mod:`ergosim.human.legs`)
=====================  =============================================================================
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TypeAlias

import numpy as np

__all__ = [
    "TRUNK",
    "NECK",
    "ARM",
    "ANGLE_NAMES",
    "LEFT_ARM",
    "HUMAN_JOINTS",
    "STANCE",
    "KWEAR_JOINTS",
    "Posture",
    "neutral_posture",
    "posture_to_array",
    "array_to_posture",
]

TRUNK = ("trunk_flexion", "trunk_lateral_bend", "trunk_rotation")
NECK = ("neck_flexion", "neck_lateral_bend", "neck_rotation")
ARM = (
    "shoulder_flexion",
    "shoulder_abduction",
    "shoulder_rotation",
    "shoulder_elevation",
    "elbow_flexion",
    "forearm_pronation",
    "wrist_flexion",
    "wrist_deviation",
)
ANGLE_NAMES: tuple[str, ...] = TRUNK + NECK + ARM
"""The RULA input: trunk, neck and the dominant (right) arm, 14 names."""

LEFT_ARM: tuple[str, ...] = tuple(f"left_{n}" for n in ARM)
HUMAN_JOINTS: tuple[str, ...] = ANGLE_NAMES + LEFT_ARM
"""Every posture hinge of the kinematic human, in this order (22)."""

STANCE: tuple[str, ...] = ("pelvis_x", "pelvis_y", "pelvis_rotation", "knee_flexion", "ankle_dorsiflexion")
"""How the worker stands (5): where the feet stand [m, m], the body's turn [deg], knee flexion and the shanks'
lean over the feet [deg]."""

KWEAR_JOINTS = ("shoulder", "elbow", "wrist", "trunk", "neck")
"""Monitored joints i of the Kinematic Wear index (paper eq. 3), in the order of every (m,) array."""

Posture: TypeAlias = Mapping[str, float | np.ndarray]


def neutral_posture() -> dict[str, float]:
    """All canonical angles at 0 deg (upright, arms hanging)."""
    return {n: 0.0 for n in ANGLE_NAMES}


def posture_to_array(posture: Posture, names: tuple[str, ...] = ANGLE_NAMES) -> np.ndarray:
    """Stack a posture into shape (n_frames, len(names)) [deg]; a scalar posture gives n_frames = 1."""
    cols = [np.atleast_1d(np.asarray(posture[n], dtype=float)) for n in names]
    return np.stack(np.broadcast_arrays(*cols), axis=-1)


def array_to_posture(angles: np.ndarray, names: tuple[str, ...] = ANGLE_NAMES) -> dict[str, np.ndarray]:
    """Inverse of :func:`posture_to_array`: (n_frames, len(names)) [deg] -> name -> (n_frames,)."""
    angles = np.asarray(angles, dtype=float)
    if angles.shape[-1] != len(names):
        raise ValueError(f"expected {len(names)} angle columns, got shape {angles.shape}")
    return {n: angles[..., i] for i, n in enumerate(names)}

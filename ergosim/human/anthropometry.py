"""Segment lengths of the human upper body from stature (published proportions).

Proportions are fractions of stature H from Drillis & Contini (1966), as tabulated in D. A. Winter,
*Biomechanics and Motor Control of Human Movement* (4th ed., 2009, Fig. 4.1): hip (greater trochanter)
0.530 H, shoulder 0.818 H, eye 0.936 H, knee 0.285 H, ankle 0.039 H, shoulder width 0.259 H, hip width
0.191 H, chest width 0.174 H, upper arm 0.186 H, forearm 0.146 H, hand 0.108 H. Where the table has no
landmark (the lumbosacral joint, C7, the sternoclavicular joint, the grasp point, segment radii) the value is
a documented approximation listed in :data:`PROPORTIONS` and in models/humanoid_upper/README.md.

A subject may scale individual segments on top of stature (``scale={"upper_arm": 1.05}``); keys are
:data:`SEGMENT_SCALES`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from ergosim.errors import ConfigError

__all__ = ["PROPORTIONS", "SEGMENT_SCALES", "Segments", "segment_lengths"]

PROPORTIONS: dict[str, float] = {
    # Drillis & Contini (1966) via Winter (2009), fractions of stature.
    "hip_height": 0.530,
    "shoulder_height": 0.818,
    "eye_height": 0.936,
    "knee_height": 0.285,
    "ankle_height": 0.039,
    "shoulder_width": 0.259,
    "hip_width": 0.191,
    "chest_width": 0.174,
    "upper_arm": 0.186,
    "forearm": 0.146,
    "hand": 0.108,
    "foot": 0.152,
    # Approximations (not in the table): lumbosacral joint above the hip-joint centre, C7 above the
    # glenohumeral level, the eyes in front of C7, the glenohumeral centre 1 cm (0.006 H) medial of the
    # acromion, the sternoclavicular joint 1.2 % H off the midline, 2 % H in front and 1 % H below the
    # glenohumeral level.
    "lumbar_above_hip": 0.045,
    "c7_above_shoulder": 0.020,
    "eye_forward": 0.050,
    "glenohumeral_medial": 0.006,
    "sc_lateral": 0.012,
    "sc_forward": 0.020,
    "sc_below": 0.010,
}

SEGMENT_SCALES = ("trunk", "neck", "shoulder_width", "upper_arm", "forearm", "hand", "legs")
"""Names a subject may scale individually (multipliers on the stature-derived length, 0.7..1.3)."""


@dataclass(frozen=True)
class Segments:
    """Segment lengths and joint offsets of one person [m], in the standing neutral posture.

    Heights are above the floor; lateral offsets are half-widths (positive to either side).
    """

    stature: float
    hip_height: float  # hip-joint centre = pelvis body origin
    lumbar_above_hip: float  # lumbosacral (L5/S1) joint, origin of the trunk hinges
    lumbar_to_c7: float  # trunk length: L5/S1 to C7 (origin of the neck hinges)
    c7_to_shoulder: float  # C7 above the glenohumeral level
    c7_to_eye: float  # eye height above C7
    eye_forward: float  # eyes in front of C7
    head_top_above_eye: float
    shoulder_half_width: float  # glenohumeral centre off the midline
    sc_lateral: float
    sc_forward: float
    sc_below: float  # sternoclavicular joint below the glenohumeral level
    upper_arm: float  # glenohumeral to elbow
    forearm: float  # elbow to wrist
    hand: float  # wrist to fingertip
    hip_half_width: float
    chest_half_width: float
    thigh: float
    shank: float
    foot: float

    @property
    def shoulder_height(self) -> float:
        """Glenohumeral centre above the floor [m]."""
        return self.hip_height + self.lumbar_above_hip + self.lumbar_to_c7 - self.c7_to_shoulder

    @property
    def arm_reach(self) -> float:
        """Glenohumeral centre to the grasp point with the arm straight [m]."""
        return self.upper_arm + self.forearm + 0.5 * self.hand


def segment_lengths(stature: float = 1.75, scale: Mapping[str, float] | None = None) -> Segments:
    """Segment lengths [m] for a person of ``stature`` [m], optionally with per-segment multipliers."""
    if not 1.2 <= float(stature) <= 2.3:
        raise ConfigError(f"stature {stature} m is outside 1.2..2.3 m", where="human stature")
    s = dict.fromkeys(SEGMENT_SCALES, 1.0)
    for key, value in (scale or {}).items():
        if key not in s:
            raise ConfigError(f"unknown segment scale {key!r}; expected one of {', '.join(SEGMENT_SCALES)}",
                              where="human scale")
        if not 0.7 <= float(value) <= 1.3:
            raise ConfigError(f"segment scale {key}={value} is outside 0.7..1.3", where="human scale")
        s[key] = float(value)
    h = float(stature)
    p = PROPORTIONS
    hip = p["hip_height"] * h * s["legs"]
    lumbar = p["lumbar_above_hip"] * h * s["trunk"]
    shoulder_rel = (p["shoulder_height"] - p["hip_height"] - p["lumbar_above_hip"]) * h * s["trunk"]
    c7_sh = p["c7_above_shoulder"] * h * s["neck"]
    c7_eye = (p["eye_height"] - p["shoulder_height"] - p["c7_above_shoulder"]) * h * s["neck"]
    return Segments(
        stature=h,
        hip_height=hip,
        lumbar_above_hip=lumbar,
        lumbar_to_c7=shoulder_rel + c7_sh,
        c7_to_shoulder=c7_sh,
        c7_to_eye=c7_eye,
        eye_forward=p["eye_forward"] * h * s["neck"],
        head_top_above_eye=(1.0 - p["eye_height"]) * h * s["neck"],
        shoulder_half_width=(0.5 * p["shoulder_width"] - p["glenohumeral_medial"]) * h * s["shoulder_width"],
        sc_lateral=p["sc_lateral"] * h * s["shoulder_width"],
        sc_forward=p["sc_forward"] * h,
        sc_below=p["sc_below"] * h,
        upper_arm=p["upper_arm"] * h * s["upper_arm"],
        forearm=p["forearm"] * h * s["forearm"],
        hand=p["hand"] * h * s["hand"],
        hip_half_width=0.5 * p["hip_width"] * h,
        chest_half_width=0.5 * p["chest_width"] * h * s["shoulder_width"],
        thigh=(p["hip_height"] - p["knee_height"]) * h * s["legs"],
        shank=(p["knee_height"] - p["ankle_height"]) * h * s["legs"],
        foot=p["foot"] * h,
    )

"""RULA per-part scores (McAtamney & Corlett 1993) and the angle thresholds of its adjustments.

Angles in degrees with the sign conventions of :mod:`ergosim.posture`. A boundary angle belongs to the
lower (less risky) band: a score rises only when a threshold is strictly exceeded. The functions use
operators only, so the same code scores Python floats (one frame, fast) and numpy arrays (n frames,
vectorised); a NaN angle compares False, and :func:`ergosim.ergonomics.rula.rula` masks such frames.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "RulaThresholds",
    "upper_arm_score",
    "lower_arm_score",
    "wrist_score",
    "wrist_twist_score",
    "neck_score",
    "trunk_score",
]


@dataclass(frozen=True)
class RulaThresholds:
    """Angles [deg] at which RULA's qualitative adjustments apply (strictly beyond the value).

    RULA names these conditions without angles; see docs/ergonomics.md for the choice of each default.
    """

    raised: float = 10.0
    """shoulder_elevation above this: shoulder raised, +1 upper arm."""
    abducted: float = 20.0
    """shoulder_abduction above this: upper arm abducted, +1 upper arm."""
    across_midline: float = 10.0
    """shoulder_abduction below minus this (adduction across the body): +1 lower arm."""
    out_to_side: float = 45.0
    """shoulder_abduction above this: hand working out to the side, +1 lower arm."""
    wrist_neutral: float = 5.0
    """|wrist_flexion| up to this is neutral (wrist 1); measured angles are never exactly 0."""
    wrist_deviated: float = 10.0
    """|wrist_deviation| above this: wrist bent from the midline, +1 wrist."""
    twist_end: float = 60.0
    """|forearm_pronation| above this (of about 80 deg either way): twist near end of range, twist 2."""
    neck_extension: float = 5.0
    """neck_flexion below minus this: neck in extension (neck 4); smaller extension counts as 0..10 deg."""
    neck_twisted: float = 10.0
    """|neck_rotation| above this: +1 neck."""
    neck_side_bent: float = 10.0
    """|neck_lateral_bend| above this: +1 neck."""
    trunk_upright: float = 5.0
    """|trunk_flexion| up to this is upright (trunk 1); extension beyond it scores 2."""
    trunk_twisted: float = 10.0
    """|trunk_rotation| above this: +1 trunk."""
    trunk_side_bent: float = 10.0
    """|trunk_lateral_bend| above this: +1 trunk."""


_DEFAULT = RulaThresholds()


def upper_arm_score(flexion, abduction=0.0, elevation=0.0, supported=False, th: RulaThresholds = _DEFAULT):
    """Upper arm 1..6: flexion bands -20/20/45/90 deg (extension beyond 20 scores 2), +1 raised,
    +1 abducted, -1 arm supported (never below 1)."""
    f = flexion
    s = 1 + (f > 20.0) + (f > 45.0) + (f > 90.0) + (f < -20.0) + (elevation > th.raised) \
        + (abduction > th.abducted)
    return s - (supported & (s > 1))


def lower_arm_score(elbow_flexion, abduction=0.0, th: RulaThresholds = _DEFAULT):
    """Lower arm 1..3: 60..100 deg flexion scores 1, otherwise 2; +1 across the midline or out to the side."""
    e, a = elbow_flexion, abduction
    return 1 + ((e < 60.0) | (e > 100.0)) + ((a < -th.across_midline) | (a > th.out_to_side))


def wrist_score(flexion, deviation=0.0, th: RulaThresholds = _DEFAULT):
    """Wrist 1..4: neutral 1, up to 15 deg flexion/extension 2, beyond 3; +1 radial/ulnar deviation."""
    a = abs(flexion)
    return 1 + (a > th.wrist_neutral) + (a > 15.0) + (abs(deviation) > th.wrist_deviated)


def wrist_twist_score(pronation, th: RulaThresholds = _DEFAULT):
    """Wrist twist 1..2: 2 near the end of the pronation/supination range."""
    return 1 + (abs(pronation) > th.twist_end)


def neck_score(flexion, lateral_bend=0.0, rotation=0.0, th: RulaThresholds = _DEFAULT):
    """Neck 1..6: 0..10 deg 1, 10..20 deg 2, beyond 20 deg 3, extension 4; +1 twisted, +1 side-bent."""
    f = flexion
    ext = f < -th.neck_extension
    base = 1 + 3 * ext + (f > 10.0) + (f > 20.0)  # ext and f > 10 never hold together
    return base + (abs(rotation) > th.neck_twisted) + (abs(lateral_bend) > th.neck_side_bent)


def trunk_score(flexion, lateral_bend=0.0, rotation=0.0, th: RulaThresholds = _DEFAULT):
    """Trunk 1..6: upright 1, up to 20 deg 2, 20..60 deg 3, beyond 60 deg 4 (extension 2); +1 twisted,
    +1 side-bent."""
    f = flexion
    base = 1 + (abs(f) > th.trunk_upright) + (f > 20.0) + (f > 60.0)
    return base + (abs(rotation) > th.trunk_twisted) + (abs(lateral_bend) > th.trunk_side_bent)

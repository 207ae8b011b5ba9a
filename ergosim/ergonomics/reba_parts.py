"""REBA per-part scores and the load, coupling and activity scores (Hignett & McAtamney 2000).

Angles in degrees with the sign conventions of :mod:`ergosim.posture`. As for RULA, a boundary angle
belongs to the lower (less risky) band: a score rises only when its threshold is strictly exceeded. The
functions use operators only, so the same code scores Python floats and (n,) numpy arrays.

Group A: trunk 1..5, neck 1..3, legs 1..4. Group B: upper arm 1..6, lower arm 1..2, wrist 1..3.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "RebaThresholds",
    "COUPLINGS",
    "POWER_GRIP_MM",
    "trunk_score",
    "neck_score",
    "legs_score",
    "upper_arm_score",
    "lower_arm_score",
    "wrist_score",
    "load_score",
    "coupling_score",
    "grip_coupling",
]


@dataclass(frozen=True)
class RebaThresholds:
    """Angles [deg] at which REBA's qualitative conditions apply (strictly beyond the value).

    REBA publishes the flexion bands in degrees (fixed here) but states "upright", "twisted", "side
    flexed", "abducted", "rotated", "raised" and "deviated" in words. The defaults equal RULA's choices
    (:class:`~ergosim.ergonomics.rula_parts.RulaThresholds`, docs/ergonomics.md) so the two indices read a
    posture alike; ``arm_rotated`` is REBA's own (assumed, see docs/ergonomics.md).
    """

    trunk_upright: float = 5.0
    """|trunk_flexion| up to this is upright (trunk 1)."""
    trunk_twisted: float = 10.0
    """|trunk_rotation| above this: +1 trunk (twisted or side flexed, at most +1)."""
    trunk_side_bent: float = 10.0
    """|trunk_lateral_bend| above this: +1 trunk (twisted or side flexed, at most +1)."""
    neck_extension: float = 5.0
    """neck_flexion below minus this: neck in extension (neck 2)."""
    neck_twisted: float = 10.0
    """|neck_rotation| above this: +1 neck (twisted or side flexed, at most +1)."""
    neck_side_bent: float = 10.0
    """|neck_lateral_bend| above this: +1 neck."""
    raised: float = 10.0
    """shoulder_elevation above this: shoulder raised, +1 upper arm."""
    abducted: float = 20.0
    """shoulder_abduction above this: upper arm abducted, +1 upper arm (abducted or rotated, at most +1)."""
    arm_rotated: float = 45.0
    """|shoulder_rotation| above this: upper arm rotated, +1 upper arm (abducted or rotated, at most +1)."""
    wrist_deviated: float = 10.0
    """|wrist_deviation| above this: wrist deviated, +1 wrist (deviated or twisted, at most +1)."""
    wrist_twisted: float = 60.0
    """|forearm_pronation| above this: wrist twisted, +1 wrist (RULA's twist near the end of its range)."""


_DEFAULT = RebaThresholds()


def trunk_score(flexion, lateral_bend=0.0, rotation=0.0, th: RebaThresholds = _DEFAULT):
    """Trunk 1..5: upright 1; 0-20 deg flexion or extension 2; 20-60 deg flexion or > 20 deg extension 3;
    > 60 deg flexion 4; +1 if twisted or side flexed."""
    f = flexion
    a = abs(f)
    base = 1 + (a > th.trunk_upright) + (a > 20.0) + (f > 60.0)
    return base + ((abs(rotation) > th.trunk_twisted) | (abs(lateral_bend) > th.trunk_side_bent))


def neck_score(flexion, lateral_bend=0.0, rotation=0.0, th: RebaThresholds = _DEFAULT):
    """Neck 1..3: 0-20 deg flexion 1; > 20 deg flexion or in extension 2; +1 if twisted or side flexed."""
    f = flexion
    base = 1 + ((f > 20.0) | (f < -th.neck_extension))
    return base + ((abs(rotation) > th.neck_twisted) | (abs(lateral_bend) > th.neck_side_bent))


def legs_score(knee_flexion=0.0, bilateral=True):
    """Legs 1..4: bilateral weight bearing, walking or sitting 1, unilateral or unstable 2; +1 if the
    knee(s) flex 30-60 deg, +2 beyond 60 deg (``knee_flexion`` [deg], the more flexed knee)."""
    k = knee_flexion
    return 2 - bilateral + (k > 30.0) + (k > 60.0)


def upper_arm_score(flexion, abduction=0.0, rotation=0.0, elevation=0.0, supported=False,
                    th: RebaThresholds = _DEFAULT):
    """Upper arm 1..6: 20 deg extension to 20 deg flexion 1; > 20 deg extension or 20-45 deg flexion 2;
    45-90 deg 3; > 90 deg 4; +1 abducted or rotated; +1 shoulder raised; -1 supported, leaning or gravity
    assisted (never below 1)."""
    f = flexion
    s = 1 + (f > 20.0) + (f > 45.0) + (f > 90.0) + (f < -20.0) + (elevation > th.raised) \
        + ((abduction > th.abducted) | (abs(rotation) > th.arm_rotated))
    return s - (supported & (s > 1))


def lower_arm_score(elbow_flexion):
    """Lower arm 1..2: 60-100 deg flexion 1, below 60 or above 100 deg 2 (REBA adds no adjustment)."""
    e = elbow_flexion
    return 1 + ((e < 60.0) | (e > 100.0))


def wrist_score(flexion, deviation=0.0, pronation=0.0, th: RebaThresholds = _DEFAULT):
    """Wrist 1..3: 0-15 deg flexion/extension 1, beyond 2; +1 if deviated or twisted."""
    return 1 + (abs(flexion) > 15.0) + ((abs(deviation) > th.wrist_deviated)
                                        | (abs(pronation) > th.wrist_twisted))


def load_score(mass_kg, shock=False):
    """Load/force 0..3 from the mass handled [kg]: < 5 kg 0, 5-10 kg 1, > 10 kg 2; +1 for a shock or a
    rapid build-up of force. 5 kg exactly scores 1 and 10 kg exactly 1 (the published bands "5-10 kg")."""
    m = mass_kg
    return 1 * (m >= 5.0) + (m > 10.0) + shock  # 1 * : numpy adds two bool arrays as a logical or


COUPLINGS: dict[str, int] = {"good": 0, "fair": 1, "poor": 2, "unacceptable": 3}
"""REBA's coupling levels: good (well-fitting handle, mid-range power grip), fair (hand hold acceptable
but not ideal, or coupling acceptable via another part of the body), poor (hand hold not acceptable
although possible), unacceptable (awkward, unsafe grip, no handles)."""

POWER_GRIP_MM: tuple[float, float] = (20.0, 50.0)
"""Widths [mm] a hand closes round in a mid-range power grip (assumed: handle-design guides put the best
power-grip diameter at about 30-40 mm; below about 20 mm the part is pinched, above about 50 mm the hand
cannot close round it)."""


def coupling_score(coupling: str) -> int:
    """0..3 from a coupling level name (:data:`COUPLINGS`); ValueError names the choices."""
    try:
        return COUPLINGS[coupling]
    except KeyError:
        raise ValueError(f"coupling must be one of {', '.join(COUPLINGS)}, got {coupling!r}") from None


def grip_coupling(width_m: float) -> str:
    """The coupling a part's grip gives by default, from the width the hand closes across [m]: "good"
    within :data:`POWER_GRIP_MM` (a mid-range power grip), else "fair" (pinched, or held flat)."""
    lo, hi = POWER_GRIP_MM
    return "good" if lo <= width_m * 1000.0 <= hi else "fair"

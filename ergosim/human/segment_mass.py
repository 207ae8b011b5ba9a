"""Segment masses and centres of mass of the kinematic human, from de Leva (1996).

P. de Leva, "Adjustments to Zatsiorsky-Seluyanov's segment inertia parameters", J Biomech 29(9):1223-1230,
1996, Table 4 (males; 10 of the paper's 12 subjects were men): mass as a share of body mass, and the
centre of mass as a share of the segment's length from its proximal end point.

=================  ==========  ====================  ==================================================
segment            mass [%]    CM [% from proximal]  end points (de Leva) -> in this model
=================  ==========  ====================  ==================================================
head + neck        6.94        50.02 from VERT       vertex to C7 -> the ``human_head`` body
upper trunk        15.96       50.66 from CERV       C7 to xiphoid -> ``human_torso``
middle trunk       16.33       45.02 from XYPH       xiphoid to navel -> ``human_torso``
lower trunk        11.17       61.15 from OMPH       navel to mid-hip -> ``human_pelvis``
upper arm          2.71        57.72 from SJC        shoulder to elbow joint centre
forearm            1.62        45.74 from EJC        elbow to wrist joint centre
hand               0.61        79.00 from WJC        wrist to 3rd metacarpale
thigh              14.16       40.95 from HJC        hip to knee joint centre
shank              4.33        44.59 from KJC        knee to lateral malleolus
foot               1.37        44.15 from HEEL       heel to toe tip
=================  ==========  ====================  ==================================================

The trunk's three parts keep de Leva's lengths in proportion (upper 242.1, middle 215.5, lower 145.7 mm of
a 1741 mm man) between this model's navel and C7; the navel sits 0.0837 H above the hip joint centres
(de Leva's lower trunk length over his stature). The hand's 3rd metacarpale lies 0.458 of the hand's
length (wrist to fingertip, 0.108 H) from the wrist (de Leva's 86.2 mm hand over Drillis & Contini's
0.108 H of 1.741 m). The clavicles carry a nominal 1 g (their mass is in the upper trunk). Only where the
centre of mass is matters to the twin (the balance of :mod:`ergosim.worker.balance`); the whole body's
mass is 24 kg/m² times stature squared (*assumed*: a body mass index of 24, near the European adult mean)
and each segment's inertia is that of a uniform rod of its length (*assumed*; the kinematic human never
needs it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ergosim.human.anthropometry import Segments

__all__ = ["MASS_SHARE", "CM_SHARE", "BMI", "body_mass", "segment_inertials"]

MASS_SHARE = {"head": 0.0694, "upper_trunk": 0.1596, "middle_trunk": 0.1633, "lower_trunk": 0.1117,
              "upper_arm": 0.0271, "forearm": 0.0162, "hand": 0.0061, "thigh": 0.1416, "shank": 0.0433,
              "foot": 0.0137}
"""de Leva (1996) Table 4, males: share of body mass."""
CM_SHARE = {"head": 0.5002, "upper_trunk": 0.5066, "middle_trunk": 0.4502, "lower_trunk": 0.6115,
            "upper_arm": 0.5772, "forearm": 0.4574, "hand": 0.7900, "thigh": 0.4095, "shank": 0.4459,
            "foot": 0.4415}
"""de Leva (1996) Table 4, males: centre of mass from the proximal end point, share of the length."""
BMI = 24.0
"""kg/m^2 (assumed): body mass = BMI x stature^2."""
_TRUNK_MM = (242.1, 215.5, 145.7)  # upper, middle, lower trunk lengths of de Leva's male [mm]
_NAVEL = 145.7 / 1741.0  # navel above the hip joint centres, share of stature
_MET3 = 86.2 / (0.108 * 1741.0)  # 3rd metacarpale from the wrist, share of the hand (wrist to fingertip)


def body_mass(stature: float) -> float:
    """Body mass [kg] of a person of ``stature`` [m] (:data:`BMI`)."""
    return BMI * stature * stature


def _rod(mass: float, length: float) -> tuple[float, float, float]:
    i = mass * length * length / 12.0 + 1e-6
    return (i, i, 1e-3 * mass * length * length + 1e-6)


def segment_inertials(s: Segments) -> dict[str, tuple[tuple[float, float, float], float, tuple]]:
    """Per body of the MJCF (``pelvis``, ``torso``, ``head``, ``clavicle``, ``upper_arm``, ``forearm``,
    ``hand``, ``thigh``, ``shank``, ``foot``): (centre of mass (3,) in the body's frame [m], mass [kg],
    diagonal inertia (3,) [kg m^2])."""
    m = body_mass(s.stature)
    h = s.stature
    out = {}
    navel = _NAVEL * h  # above the hip joint centres = the pelvis body's origin
    out["pelvis"] = ((0.0, 0.0, navel * (1.0 - CM_SHARE["lower_trunk"])), MASS_SHARE["lower_trunk"] * m,
                     _rod(MASS_SHARE["lower_trunk"] * m, navel))
    # the torso body's origin is the lumbosacral joint; from the navel to C7, upper and middle trunk
    z_navel, z_c7 = navel - s.lumbar_above_hip, s.lumbar_to_c7
    up, mid, _ = _TRUNK_MM
    z_xyph = z_c7 - (z_c7 - z_navel) * up / (up + mid)
    m_up, m_mid = MASS_SHARE["upper_trunk"] * m, MASS_SHARE["middle_trunk"] * m
    z_up = z_c7 - CM_SHARE["upper_trunk"] * (z_c7 - z_xyph)
    z_mid = z_xyph - CM_SHARE["middle_trunk"] * (z_xyph - z_navel)
    out["torso"] = ((0.0, 0.0, (m_up * z_up + m_mid * z_mid) / (m_up + m_mid)), m_up + m_mid,
                    _rod(m_up + m_mid, z_c7 - z_navel))
    head_len = s.c7_to_eye + s.head_top_above_eye  # C7 to the vertex
    out["head"] = ((0.004 * h, 0.0, head_len * CM_SHARE["head"]), MASS_SHARE["head"] * m,
                   _rod(MASS_SHARE["head"] * m, head_len))
    out["clavicle"] = ((0.0, 0.0, 0.0), 1e-3, (1e-6, 1e-6, 1e-6))
    for name, length in (("upper_arm", s.upper_arm), ("forearm", s.forearm), ("thigh", s.thigh),
                         ("shank", s.shank)):
        mass = MASS_SHARE[name] * m
        out[name] = ((0.0, 0.0, -CM_SHARE[name] * length), mass, _rod(mass, length))
    hand = MASS_SHARE["hand"] * m
    out["hand"] = ((0.0, 0.0, -CM_SHARE["hand"] * _MET3 * s.hand), hand, _rod(hand, s.hand))
    foot = MASS_SHARE["foot"] * m
    heel, length = -0.25 * s.foot, s.foot
    ankle_z = s.hip_height - s.thigh - s.shank
    out["foot"] = ((heel + CM_SHARE["foot"] * length, 0.0, -0.5 * ankle_z), foot, _rod(foot, length))
    return out

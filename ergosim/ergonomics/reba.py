"""REBA (Hignett & McAtamney 2000, Applied Ergonomics 31:201-205) from canonical joint angles.

Input is a *posture* (:mod:`ergosim.posture`): canonical angle name -> degrees, a float for one frame or
an (n,) array for n frames (vectorised). Group A (trunk, neck, legs) goes through Table A and gains the
load/force score (score A); group B (upper arm, lower arm, wrist of the dominant arm) goes through Table B
and gains the coupling score (score B); Table C of scores A and B plus the activity score is the REBA
score, 1..15, and its action level 0..4.

What angles cannot show is passed as keyword arguments, scalar or per frame: ``load_kg`` (the mass
handled, the part's mass while the hand holds it), ``shock``, ``coupling`` (0..3, from the part's grip:
:func:`~ergosim.ergonomics.reba_parts.grip_coupling`), ``activity`` (0..3), ``legs_bilateral`` and
``arm_supported``.

Legs. REBA's legs score reads the knees: +1 for 30-60 deg of flexion, +2 beyond. The more flexed of the
posture's :data:`KNEE_ANGLES` is used; **a posture without knee angles is scored with straight knees**
(the kinematic worker of this release stands on locked knees), so legs = 1 standing on both feet, 2 with
``legs_bilateral=False``.

Scores are floats holding integers; a frame with a non-finite angle has ``valid == False`` and NaN in
every score.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from ergosim.ergonomics.reba_parts import (
    RebaThresholds,
    legs_score,
    load_score,
    lower_arm_score,
    neck_score,
    trunk_score,
    upper_arm_score,
    wrist_score,
)
from ergosim.ergonomics.reba_tables import TABLE_A, TABLE_B, TABLE_C, risk_level
from ergosim.ergonomics.scores import score_index
from ergosim.posture import ANGLE_NAMES, array_to_posture

__all__ = [
    "REBA_INPUTS",
    "KNEE_ANGLES",
    "REBA_PARTS",
    "REBA_JOINTS",
    "RebaResult",
    "RebaThresholds",
    "reba",
    "reba_table_a",
    "reba_table_b",
    "reba_table_c",
    "reba_part_scores",
    "reba_frames",
]

REBA_INPUTS: tuple[str, ...] = (
    "trunk_flexion", "trunk_lateral_bend", "trunk_rotation",
    "neck_flexion", "neck_lateral_bend", "neck_rotation",
    "shoulder_flexion", "shoulder_abduction", "shoulder_rotation", "shoulder_elevation",
    "elbow_flexion", "forearm_pronation", "wrist_flexion", "wrist_deviation",
)
"""The canonical angles REBA reads (all 14 of :data:`ergosim.posture.ANGLE_NAMES`)."""

KNEE_ANGLES: tuple[str, ...] = ("knee_flexion", "left_knee_flexion")
"""Knee flexion angles [deg, 0 = straight] the legs score reads when the posture has them."""

REBA_JOINTS: tuple[str, ...] = ("shoulder", "elbow", "wrist", "trunk", "neck", "legs")
"""Joints of a KWear index driven by REBA part scores: the RULA-driven index's five, and the legs."""


class RebaResult(NamedTuple):
    """REBA scores of one frame (floats) or of n frames ((n,) float arrays); NaN where not ``valid``.

    Part scores ``trunk`` 1..5, ``neck`` 1..3, ``legs`` 1..4, ``upper_arm`` 1..6, ``lower_arm`` 1..2,
    ``wrist`` 1..3; ``table_a``/``table_b`` the posture scores; ``load`` 0..3 and ``score_a`` = table_a
    + load; ``coupling`` 0..3 and ``score_b`` = table_b + coupling; ``table_c`` 1..12; ``activity`` 0..3;
    ``score`` = table_c + activity (1..15); ``action_level`` 0..4; ``valid`` False for a NaN frame.
    """

    upper_arm: float | np.ndarray
    lower_arm: float | np.ndarray
    wrist: float | np.ndarray
    neck: float | np.ndarray
    trunk: float | np.ndarray
    legs: float | np.ndarray
    table_a: float | np.ndarray
    load: float | np.ndarray
    score_a: float | np.ndarray
    table_b: float | np.ndarray
    coupling: float | np.ndarray
    score_b: float | np.ndarray
    table_c: float | np.ndarray
    activity: float | np.ndarray
    score: float | np.ndarray
    action_level: float | np.ndarray
    valid: bool | np.ndarray


REBA_PARTS: tuple[str, ...] = RebaResult._fields[:6]
"""REBA's body-part scores in :class:`RebaResult` order: upper_arm, lower_arm, wrist, neck, trunk, legs."""

_DEFAULT = RebaThresholds()




def reba_table_a(trunk, neck, legs):
    """Posture score A (1..9) from trunk 1..5, neck 1..3, legs 1..4."""
    return TABLE_A[score_index("trunk", trunk, 5), score_index("neck", neck, 3), score_index("legs", legs, 4)]


def reba_table_b(upper_arm, lower_arm, wrist):
    """Posture score B (1..9) from upper arm 1..6, lower arm 1..2, wrist 1..3."""
    return TABLE_B[score_index("upper_arm", upper_arm, 6), score_index("lower_arm", lower_arm, 2),
                   score_index("wrist", wrist, 3)]


def reba_table_c(score_a, score_b):
    """Score C (1..12) from score A and score B (each >= 1; 12 is the table's last row and column)."""
    a = np.minimum(np.asarray(score_a), 12)
    b = np.minimum(np.asarray(score_b), 12)
    return TABLE_C[score_index("score_a", a, 12), score_index("score_b", b, 12)]


def reba_part_scores(result: RebaResult, out: np.ndarray | None = None) -> np.ndarray:
    """KWear inputs from a REBA result: (..., 6) floats in :data:`REBA_JOINTS` order (shoulder = upper arm,
    elbow = lower arm, wrist, trunk, neck, legs); NaN where the frame is not valid."""
    parts = (result.upper_arm, result.lower_arm, result.wrist, result.trunk, result.neck, result.legs)
    if out is None:
        return np.stack(np.broadcast_arrays(*(np.asarray(p, dtype=float) for p in parts)), axis=-1)
    for i, p in enumerate(parts):
        out[..., i] = p
    return out


def _flag(name: str, value, lo: int, hi: int) -> np.ndarray:
    v = np.asarray(value)
    i = v.astype(np.int64)
    if np.any(i != v) or np.any((i < lo) | (i > hi)):
        raise ValueError(f"{name} must be an integer {lo}..{hi} (scalar or per frame), got {value!r}")
    return i


def reba(posture: Mapping, *, load_kg=0.0, shock=False, coupling=0, activity=0, legs_bilateral=True,
         arm_supported=False, thresholds: RebaThresholds = _DEFAULT) -> RebaResult:
    """REBA of one frame or of n frames.

    posture: canonical angle name -> degrees, floats or (n,) arrays (:data:`REBA_INPUTS`; optionally
    :data:`KNEE_ANGLES`). load_kg: mass handled [kg] (>= 0); shock: a shock or rapid build-up of force;
    coupling: 0..3 (good, fair, poor, unacceptable); activity: 0..3 (+1 each: a part held static > 1 min,
    small-range actions repeated > 4/min, rapid large changes of posture or an unstable base). All scalar
    or (n,). Returns a :class:`RebaResult` of floats (all-scalar input) or (n,) arrays.
    """
    try:
        raw = [np.asarray(posture[n], dtype=float) for n in REBA_INPUTS]
    except KeyError:
        missing = [n for n in REBA_INPUTS if n not in posture]
        raise ValueError(f"posture lacks canonical angle(s) {missing}; REBA needs {list(REBA_INPUTS)}") \
            from None
    knees = [np.asarray(posture[n], dtype=float) for n in KNEE_ANGLES if n in posture]
    load = np.asarray(load_kg, dtype=float)
    if not np.all(load >= 0):
        raise ValueError(f"load_kg must be >= 0 kg, got {load_kg!r}")
    cpl, act = _flag("coupling", coupling, 0, 3), _flag("activity", activity, 0, 3)
    th = thresholds
    tf, tl, tr, nf, nl, nr, sf, sab, srot, se, ef, fp, wf, wd = raw
    knee = np.maximum.reduce(knees) if knees else 0.0
    trunk = trunk_score(tf, tl, tr, th)
    neck = neck_score(nf, nl, nr, th)
    legs = legs_score(knee, np.asarray(legs_bilateral, dtype=bool))
    ua = upper_arm_score(sf, sab, srot, se, np.asarray(arm_supported, dtype=bool), th)
    la = lower_arm_score(ef)
    wr = wrist_score(wf, wd, fp, th)
    parts = [np.asarray(p, dtype=np.int64) for p in (ua, la, wr, neck, trunk, legs)]
    valid = np.ones((), dtype=bool)
    for x in (*raw, *knees):  # the loop is over angle names, never over frames
        valid = valid & np.isfinite(x)
    shape = np.broadcast_shapes(*(p.shape for p in parts), valid.shape, load.shape, cpl.shape, act.shape,
                                np.shape(shock))
    ua, la, wr, neck, trunk, legs = (np.broadcast_to(p, shape) for p in parts)
    ta = TABLE_A[trunk - 1, neck - 1, legs - 1]
    ld = np.broadcast_to(load_score(load, np.asarray(shock, dtype=bool)), shape)
    sa = ta + ld
    tb = TABLE_B[ua - 1, la - 1, wr - 1]
    sb = tb + cpl
    tc = TABLE_C[np.minimum(sa, 12) - 1, np.minimum(sb, 12) - 1]
    score = tc + act
    valid = np.broadcast_to(valid, shape)
    out = []
    for s in (ua, la, wr, neck, trunk, legs, ta, ld, sa, tb, cpl, sb, tc, act, score, risk_level(score)):
        f = np.broadcast_to(s, shape).astype(float)
        f[~valid] = np.nan
        out.append(float(f) if not shape else f)
    return RebaResult(*out, valid=bool(valid) if not shape else valid.copy())


def reba_frames(angles, load_kg=0.0, coupling=0, knees=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """REBA of n measured frames in one vectorised call, for a risk index's feature stream.

    angles: (n, >= 14) [deg], the first 14 columns in :data:`ergosim.posture.ANGLE_NAMES` order; knees:
    optional (n, k) knee flexion angles [deg] (:data:`KNEE_ANGLES`); load_kg, coupling: scalars or (n,).
    Returns part scores (n, 6) in :data:`REBA_PARTS` order, REBA scores (n,) and the KWear inputs (n, 6)
    in :data:`REBA_JOINTS` order; a row with a NaN angle is NaN in all three.
    """
    a = np.asarray(angles, dtype=float)
    posture = array_to_posture(a[:, :len(ANGLE_NAMES)])
    if knees is not None:
        k = np.asarray(knees, dtype=float).reshape(len(a), -1)
        posture.update({name: k[:, i] for i, name in enumerate(KNEE_ANGLES[:k.shape[1]])})
    res = reba(posture, load_kg=np.broadcast_to(load_kg, (len(a),)),
               coupling=np.broadcast_to(coupling, (len(a),)))
    parts = np.stack([np.asarray(getattr(res, p), dtype=float) for p in REBA_PARTS], axis=-1)
    return parts.reshape(len(a), len(REBA_PARTS)), np.asarray(res.score, dtype=float).reshape(len(a)), \
        reba_part_scores(res).reshape(len(a), len(REBA_JOINTS))

"""RULA (McAtamney & Corlett 1993) from canonical joint angles: per-part scores, Tables A-C, grand score.

Input is a *posture* (:mod:`ergosim.posture`): canonical angle name -> degrees, a float for one frame or an
(n,) array for n frames (vectorised; no Python loop over frames). Sign conventions are those of
:mod:`ergosim.posture` (flexion positive, extension negative). A boundary angle belongs to the *lower*
(less risky) band: a score rises only when its threshold is strictly exceeded, e.g. upper arm flexion of
exactly 45 deg scores 2, 45.001 deg scores 3. Adjustment thresholds (abducted, raised, twisted, ...) are
the fields of :class:`RulaThresholds`; docs/ergonomics.md gives each value's source.

Scores are returned as floats holding integers. A frame with a non-finite angle (a mocap dropout) has
``valid == False`` and NaN in every score, so it cannot pass silently as a low score.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ergosim.ergonomics.rula_tables import TABLE_A, TABLE_B, TABLE_C

__all__ = [
    "RulaThresholds",
    "RulaResult",
    "RULA_INPUTS",
    "rula",
    "table_a",
    "table_b",
    "table_c",
    "action_level",
    "upper_arm_score",
    "lower_arm_score",
    "wrist_score",
    "wrist_twist_score",
    "neck_score",
    "trunk_score",
]

RULA_INPUTS: tuple[str, ...] = (
    "trunk_flexion", "trunk_lateral_bend", "trunk_rotation",
    "neck_flexion", "neck_lateral_bend", "neck_rotation",
    "shoulder_flexion", "shoulder_abduction", "shoulder_elevation",
    "elbow_flexion", "forearm_pronation", "wrist_flexion", "wrist_deviation",
)
"""The canonical angles RULA reads (``shoulder_rotation`` is not scored by RULA)."""


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


class RulaResult(NamedTuple):
    """RULA scores of one frame (floats) or of n frames ((n,) float arrays); NaN where not ``valid``.

    ``score_a``/``score_b``: Tables A/B; ``score_c``/``score_d``: those plus muscle use and force/load;
    ``grand``: Table C, 1..7; ``action_level``: 1..4; ``valid``: bool, False for frames with a NaN angle.
    """

    upper_arm: float | np.ndarray
    lower_arm: float | np.ndarray
    wrist: float | np.ndarray
    wrist_twist: float | np.ndarray
    neck: float | np.ndarray
    trunk: float | np.ndarray
    legs: float | np.ndarray
    score_a: float | np.ndarray
    score_b: float | np.ndarray
    score_c: float | np.ndarray
    score_d: float | np.ndarray
    grand: float | np.ndarray
    action_level: float | np.ndarray
    valid: bool | np.ndarray


# -- per-part scores --
# Written with operators only, so the same code scores Python floats (one frame, fast) and numpy arrays
# (n frames, vectorised). Angles in degrees; NaN compares False and the caller masks such frames.
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


# -- tables --
def _index(name: str, value, hi: int) -> np.ndarray:
    """Validate integer scores 1..hi and return zero-based int indices."""
    v = np.asarray(value)
    i = v.astype(np.int64) if v.dtype.kind in "iub" else np.rint(v).astype(np.int64)
    if not (np.all(i == v) and np.all((i >= 1) & (i <= hi))):
        raise ValueError(f"{name} must be an integer score 1..{hi}, got {value!r}")
    return i - 1


def table_a(upper_arm, lower_arm, wrist, wrist_twist):
    """Posture score A (1..9) from upper arm 1..6, lower arm 1..3, wrist 1..4, wrist twist 1..2."""
    return TABLE_A[_index("upper_arm", upper_arm, 6), _index("lower_arm", lower_arm, 3),
                   _index("wrist", wrist, 4), _index("wrist_twist", wrist_twist, 2)]


def table_b(neck, trunk, legs):
    """Posture score B (1..9) from neck 1..6, trunk 1..6, legs 1..2."""
    return TABLE_B[_index("neck", neck, 6), _index("trunk", trunk, 6), _index("legs", legs, 2)]


def table_c(score_a, score_b):
    """Grand score 1..7 from score C (>= 1, clamped at 8) and score D (>= 1, clamped at 7).

    The arguments are the arm/wrist and neck/trunk/leg scores *after* muscle use and force/load
    (RULA's scores C and D); with neither adjustment they equal Table A's and Table B's results.
    """
    c = np.minimum(np.asarray(score_a), 8)
    d = np.minimum(np.asarray(score_b), 7)
    return TABLE_C[_index("score_c", c, 8), _index("score_d", d, 7)]


def action_level(grand):
    """RULA action level 1..4 from the grand score 1..7 (1-2 -> 1, 3-4 -> 2, 5-6 -> 3, 7 -> 4)."""
    return (np.asarray(grand) + 1) // 2


# -- whole posture --
def _flag(name: str, value, lo: int, hi: int):
    if type(value) in (int, bool):  # the common scalar case, checked without numpy
        if not lo <= value <= hi:
            raise ValueError(f"{name} must be an integer {lo}..{hi}, got {value!r}")
        return int(value)
    v = np.asarray(value)
    i = v.astype(np.int64)
    if np.any(i != v) or np.any((i < lo) | (i > hi)):
        raise ValueError(f"{name} must be an integer {lo}..{hi} (scalar or per frame), got {value!r}")
    return i


def _is_scalar(x) -> bool:
    # np.ndim costs about a microsecond per call; plain types are decided without it.
    return type(x) in _PLAIN or isinstance(x, np.generic) or (isinstance(x, np.ndarray) and x.ndim == 0)


_PLAIN = (float, int, bool)


def rula(posture: Mapping, *, legs_supported=True, arm_supported=False, muscle_use=0, force_load=0,
         thresholds: RulaThresholds = _DEFAULT) -> RulaResult:
    """RULA of one frame or of n frames.

    posture: canonical angle name -> degrees, floats or (n,) arrays (see :data:`RULA_INPUTS`).
    legs_supported / arm_supported: bools (scalar or (n,)) for what angles cannot show.
    muscle_use: 0/1 (static > 1 min or repeated > 4/min); force_load: 0..3 (rula.md); scalar or (n,).
    Returns a :class:`RulaResult` of floats (all-scalar input) or (n,) arrays; NaN where not ``valid``.
    """
    try:
        raw = [posture[n] for n in RULA_INPUTS]
    except KeyError:
        missing = [n for n in RULA_INPUTS if n not in posture]
        raise ValueError(f"posture lacks canonical angle(s) {missing}; RULA needs {list(RULA_INPUTS)}") \
            from None
    if "shoulder_rotation" in posture:  # not scored, but a NaN there still marks a dropout frame
        raw.append(posture["shoulder_rotation"])
    extra = _flag("muscle_use", muscle_use, 0, 1) + _flag("force_load", force_load, 0, 3)
    flags = (legs_supported, arm_supported, extra)
    if all(map(_is_scalar, raw)) and all(map(_is_scalar, flags)):
        return _rula_frame([float(x) for x in raw], bool(legs_supported), bool(arm_supported), int(extra),
                           thresholds)
    vals = [np.asarray(x, dtype=float) for x in raw]
    scores = _scores(vals, np.asarray(legs_supported, dtype=bool), np.asarray(arm_supported, dtype=bool),
                     np.asarray(extra), thresholds)
    valid = np.isfinite(vals[0])
    for x in vals[1:]:  # the loop is over the angle names, never over frames
        valid = valid & np.isfinite(x)
    shape = np.broadcast_shapes(*(np.shape(s) for s in scores), np.shape(valid))
    valid = np.broadcast_to(valid, shape)
    out = []
    for s in scores:
        f = np.broadcast_to(s, shape).astype(float)
        f[~valid] = np.nan
        out.append(f)
    return RulaResult(*out, valid=valid.copy())


def _parts(a, legs_supported, arm_supported, th: RulaThresholds) -> tuple:
    """The seven part scores from the angles in :data:`RULA_INPUTS` order (floats or arrays alike)."""
    tf, tl, tr, nf, nl, nr, sf, sab, se, ef, fp, wf, wd = a[:13]
    return (upper_arm_score(sf, sab, se, arm_supported, th), lower_arm_score(ef, sab, th),
            wrist_score(wf, wd, th), wrist_twist_score(fp, th), neck_score(nf, nl, nr, th),
            trunk_score(tf, tl, tr, th), 2 - legs_supported)


def _scores(a, legs_supported, arm_supported, extra, th: RulaThresholds) -> tuple:
    """All 13 scores of :class:`RulaResult` (without ``valid``) for (n,) angle arrays."""
    ua, la, wr, wt, nk, tr, lg = parts = _parts(a, legs_supported, arm_supported, th)
    sa = TABLE_A[ua - 1, la - 1, wr - 1, wt - 1]
    sb = TABLE_B[nk - 1, tr - 1, lg - 1]
    sc = sa + extra
    sd = sb + extra
    grand = TABLE_C[np.minimum(sc, 8) - 1, np.minimum(sd, 7) - 1]
    return (*parts, sa, sb, sc, sd, grand, (grand + 1) // 2)


_LIST_A, _LIST_B, _LIST_C = TABLE_A.tolist(), TABLE_B.tolist(), TABLE_C.tolist()


def _rula_frame(a: list[float], legs_supported: bool, arm_supported: bool, extra: int,
                th: RulaThresholds) -> RulaResult:
    """One frame on Python floats and nested lists: the per-tick path, without numpy's per-call overhead."""
    if not all(map(math.isfinite, a)):
        return _INVALID
    ua, la, wr, wt, nk, tr, lg = parts = _parts(a, legs_supported, arm_supported, th)
    sa = _LIST_A[ua - 1][la - 1][wr - 1][wt - 1]
    sb = _LIST_B[nk - 1][tr - 1][lg - 1]
    sc, sd = sa + extra, sb + extra
    grand = _LIST_C[min(sc, 8) - 1][min(sd, 7) - 1]
    return RulaResult(*map(float, (*parts, sa, sb, sc, sd, grand, (grand + 1) // 2)), valid=True)


_INVALID = RulaResult(*([math.nan] * 13), valid=False)

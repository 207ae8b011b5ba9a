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
from typing import NamedTuple

import numpy as np

from ergosim.ergonomics.rula_parts import (
    RulaThresholds,
    lower_arm_score,
    neck_score,
    trunk_score,
    upper_arm_score,
    wrist_score,
    wrist_twist_score,
)
from ergosim.ergonomics.rula_tables import TABLE_A, TABLE_B, TABLE_C
from ergosim.ergonomics.scores import score_index

__all__ = [
    "RulaThresholds",
    "RulaResult",
    "RULA_INPUTS",
    "RULA_PARTS",
    "rula",
    "table_a",
    "table_b",
    "table_c",
    "action_level",
    "part_scores",
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


RULA_PARTS: tuple[str, ...] = RulaResult._fields[:7]
"""RULA's body-part scores, in :class:`RulaResult` order: upper_arm, lower_arm, wrist, wrist_twist, neck,
trunk, legs."""


# -- tables --


def table_a(upper_arm, lower_arm, wrist, wrist_twist):
    """Posture score A (1..9) from upper arm 1..6, lower arm 1..3, wrist 1..4, wrist twist 1..2."""
    return TABLE_A[score_index("upper_arm", upper_arm, 6), score_index("lower_arm", lower_arm, 3),
                   score_index("wrist", wrist, 4), score_index("wrist_twist", wrist_twist, 2)]


def table_b(neck, trunk, legs):
    """Posture score B (1..9) from neck 1..6, trunk 1..6, legs 1..2."""
    return TABLE_B[score_index("neck", neck, 6), score_index("trunk", trunk, 6), score_index("legs", legs, 2)]


def table_c(score_a, score_b):
    """Grand score 1..7 from score C (>= 1, clamped at 8) and score D (>= 1, clamped at 7).

    The arguments are the arm/wrist and neck/trunk/leg scores *after* muscle use and force/load
    (RULA's scores C and D); with neither adjustment they equal Table A's and Table B's results.
    """
    c = np.minimum(np.asarray(score_a), 8)
    d = np.minimum(np.asarray(score_b), 7)
    return TABLE_C[score_index("score_c", c, 8), score_index("score_d", d, 7)]


def action_level(grand):
    """RULA action level 1..4 from the grand score 1..7 (1-2 -> 1, 3-4 -> 2, 5-6 -> 3, 7 -> 4)."""
    return (np.asarray(grand) + 1) // 2


def part_scores(result: RulaResult, out: np.ndarray | None = None) -> np.ndarray:
    """KWear inputs G_i (paper eq. 3) from a RULA result: (..., 5) floats in ``posture.KWEAR_JOINTS`` order
    (shoulder = upper arm, elbow = lower arm, wrist, trunk, neck); NaN where the frame is not valid.
    ``out``: optional (..., 5) buffer to fill, for the per-tick path."""
    parts = (result.upper_arm, result.lower_arm, result.wrist, result.trunk, result.neck)
    if out is None:
        return np.stack(np.broadcast_arrays(*(np.asarray(p, dtype=float) for p in parts)), axis=-1)
    for i, p in enumerate(parts):
        out[..., i] = p
    return out


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

"""RULA: tables cell by cell against the published tables, every band edge, adjustments, NaN frames,
vectorised == per frame, ranges and monotonicity (hypothesis)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ergosim.ergonomics import part_scores
from ergosim.ergonomics.rula import (
    RULA_INPUTS,
    RulaThresholds,
    action_level,
    rula,
    table_a,
    table_b,
    table_c,
)
from ergosim.posture import ANGLE_NAMES, neutral_posture

# Reference tables typed from shared/reference/rula.md (McAtamney & Corlett 1993), independently of the
# module's layout: Table A per upper arm "LA1 | LA2 | LA3", each cell four wrist pairs (twist 1, twist 2).
REF_A = {
    1: "12 22 23 33 | 22 22 33 33 | 23 33 33 44",
    2: "23 33 34 44 | 33 33 34 44 | 34 44 44 55",
    3: "33 44 44 55 | 34 44 44 55 | 44 44 45 55",
    4: "44 44 45 55 | 44 44 45 55 | 44 45 55 66",
    5: "55 55 56 67 | 56 66 67 77 | 66 67 77 78",
    6: "77 77 78 89 | 88 88 89 99 | 99 99 99 99",
}
REF_B = {  # neck -> trunk 1..6 pairs (legs 1, legs 2)
    1: "13 23 34 55 66 77",
    2: "23 23 45 55 67 77",
    3: "33 34 45 56 67 77",
    4: "55 56 67 77 77 88",
    5: "77 77 78 88 88 88",
    6: "88 88 88 89 99 99",
}
REF_C = """
1 2 3 3 4 5 5
2 2 3 4 4 5 5
3 3 3 4 4 5 6
3 3 3 4 5 6 6
4 4 4 5 6 7 7
4 4 5 6 6 7 7
5 5 6 6 7 7 7
5 5 6 7 7 7 7
"""


def posture(**angles: float) -> dict[str, float]:
    p = neutral_posture()
    p["elbow_flexion"] = 80.0  # lower arm 1 unless a test says otherwise
    p.update(angles)
    return p


# -- tables -----------------------------------------------------------------------------------------------
def test_table_a_cell_by_cell():
    n = 0
    for ua, row in REF_A.items():
        for la, cell in enumerate(row.split("|"), start=1):
            for wr, pair in enumerate(cell.split(), start=1):
                for wt, digit in enumerate(pair, start=1):
                    assert table_a(ua, la, wr, wt) == int(digit), (ua, la, wr, wt)
                    n += 1
    assert n == 6 * 3 * 4 * 2


def test_table_b_cell_by_cell():
    n = 0
    for neck, row in REF_B.items():
        for trunk, pair in enumerate(row.split(), start=1):
            for legs, digit in enumerate(pair, start=1):
                assert table_b(neck, trunk, legs) == int(digit), (neck, trunk, legs)
                n += 1
    assert n == 72


def test_table_c_cell_by_cell_and_clamping():
    ref = [[int(x) for x in line.split()] for line in REF_C.strip().splitlines()]
    for c, d in itertools.product(range(1, 13), range(1, 12)):
        assert table_c(c, d) == ref[min(c, 8) - 1][min(d, 7) - 1], (c, d)
    assert table_c(1, 1) == 1 and table_c(8, 7) == 7 and table_c(12, 3) == 6


def test_tables_vectorised_and_validated():
    ua, la, wr, wt = np.meshgrid(np.arange(1, 7), np.arange(1, 4), np.arange(1, 5), np.arange(1, 3))
    got = table_a(ua.ravel(), la.ravel(), wr.ravel(), wt.ravel())
    assert [table_a(*x) for x in zip(ua.ravel(), la.ravel(), wr.ravel(), wt.ravel())] == got.tolist()
    assert table_a(2.0, 1.0, 3.0, 2.0) == 4  # float scores holding integers are accepted
    for bad in [(0, 1, 1, 1), (7, 1, 1, 1), (1, 4, 1, 1), (1, 1, 5, 1), (1, 1, 1, 3), (1.5, 1, 1, 1)]:
        with pytest.raises(ValueError):
            table_a(*bad)
    with pytest.raises(ValueError):
        table_b(1, 7, 1)
    with pytest.raises(ValueError):
        table_c(0, 1)


def test_action_levels():
    assert [int(action_level(g)) for g in range(1, 8)] == [1, 1, 2, 2, 3, 3, 4]


# -- band edges, case by case (a boundary angle belongs to the lower band) --------------------------------
EDGES = [
    # (angles, part, expected)
    ({"shoulder_flexion": 0.0}, "upper_arm", 1),
    ({"shoulder_flexion": 20.0}, "upper_arm", 1),
    ({"shoulder_flexion": 20.01}, "upper_arm", 2),
    ({"shoulder_flexion": 45.0}, "upper_arm", 2),
    ({"shoulder_flexion": 45.01}, "upper_arm", 3),
    ({"shoulder_flexion": 90.0}, "upper_arm", 3),
    ({"shoulder_flexion": 90.01}, "upper_arm", 4),
    ({"shoulder_flexion": 170.0}, "upper_arm", 4),
    ({"shoulder_flexion": -20.0}, "upper_arm", 1),
    ({"shoulder_flexion": -20.01}, "upper_arm", 2),
    ({"shoulder_flexion": -50.0}, "upper_arm", 2),
    ({"shoulder_abduction": 20.0}, "upper_arm", 1),
    ({"shoulder_abduction": 20.01}, "upper_arm", 2),
    ({"shoulder_elevation": 10.0}, "upper_arm", 1),
    ({"shoulder_elevation": 10.01}, "upper_arm", 2),
    ({"shoulder_flexion": 100.0, "shoulder_abduction": 30.0, "shoulder_elevation": 20.0}, "upper_arm", 6),
    ({"elbow_flexion": 60.0}, "lower_arm", 1),
    ({"elbow_flexion": 59.99}, "lower_arm", 2),
    ({"elbow_flexion": 100.0}, "lower_arm", 1),
    ({"elbow_flexion": 100.01}, "lower_arm", 2),
    ({"elbow_flexion": 0.0}, "lower_arm", 2),
    ({"elbow_flexion": 140.0}, "lower_arm", 2),
    ({"shoulder_abduction": -10.0}, "lower_arm", 1),
    ({"shoulder_abduction": -10.01}, "lower_arm", 2),
    ({"shoulder_abduction": 45.0}, "lower_arm", 1),
    ({"shoulder_abduction": 45.01}, "lower_arm", 2),
    ({"elbow_flexion": 120.0, "shoulder_abduction": -30.0}, "lower_arm", 3),
    ({"wrist_flexion": 0.0}, "wrist", 1),
    ({"wrist_flexion": 5.0}, "wrist", 1),
    ({"wrist_flexion": -5.0}, "wrist", 1),
    ({"wrist_flexion": 5.01}, "wrist", 2),
    ({"wrist_flexion": -5.01}, "wrist", 2),
    ({"wrist_flexion": 15.0}, "wrist", 2),
    ({"wrist_flexion": -15.0}, "wrist", 2),
    ({"wrist_flexion": 15.01}, "wrist", 3),
    ({"wrist_flexion": -15.01}, "wrist", 3),
    ({"wrist_deviation": 10.0}, "wrist", 1),
    ({"wrist_deviation": 10.01}, "wrist", 2),
    ({"wrist_deviation": -10.01}, "wrist", 2),
    ({"wrist_flexion": -40.0, "wrist_deviation": 20.0}, "wrist", 4),
    ({"forearm_pronation": 60.0}, "wrist_twist", 1),
    ({"forearm_pronation": 60.01}, "wrist_twist", 2),
    ({"forearm_pronation": -60.0}, "wrist_twist", 1),
    ({"forearm_pronation": -60.01}, "wrist_twist", 2),
    ({"neck_flexion": 0.0}, "neck", 1),
    ({"neck_flexion": 10.0}, "neck", 1),
    ({"neck_flexion": 10.01}, "neck", 2),
    ({"neck_flexion": 20.0}, "neck", 2),
    ({"neck_flexion": 20.01}, "neck", 3),
    ({"neck_flexion": -5.0}, "neck", 1),
    ({"neck_flexion": -5.01}, "neck", 4),
    ({"neck_flexion": -30.0}, "neck", 4),
    ({"neck_rotation": 10.0}, "neck", 1),
    ({"neck_rotation": -10.01}, "neck", 2),
    ({"neck_lateral_bend": 10.01}, "neck", 2),
    ({"neck_flexion": -30.0, "neck_rotation": 30.0, "neck_lateral_bend": -30.0}, "neck", 6),
    ({"trunk_flexion": 0.0}, "trunk", 1),
    ({"trunk_flexion": 5.0}, "trunk", 1),
    ({"trunk_flexion": 5.01}, "trunk", 2),
    ({"trunk_flexion": 20.0}, "trunk", 2),
    ({"trunk_flexion": 20.01}, "trunk", 3),
    ({"trunk_flexion": 60.0}, "trunk", 3),
    ({"trunk_flexion": 60.01}, "trunk", 4),
    ({"trunk_flexion": -5.0}, "trunk", 1),
    ({"trunk_flexion": -5.01}, "trunk", 2),
    ({"trunk_rotation": 10.0}, "trunk", 1),
    ({"trunk_rotation": 10.01}, "trunk", 2),
    ({"trunk_lateral_bend": -10.01}, "trunk", 2),
    ({"trunk_flexion": 80.0, "trunk_rotation": -20.0, "trunk_lateral_bend": 20.0}, "trunk", 6),
]


@pytest.mark.parametrize(("angles", "part", "expected"), EDGES, ids=[f"{p}-{a}" for a, p, _ in EDGES])
def test_band_edge(angles, part, expected):
    res = rula(posture(**angles))
    assert getattr(res, part) == expected
    assert res.valid


def test_flags_for_what_angles_cannot_show():
    p = posture(shoulder_flexion=50.0)
    assert rula(p).upper_arm == 3 and rula(p, arm_supported=True).upper_arm == 2
    assert rula(posture(), arm_supported=True).upper_arm == 1  # never below 1
    assert rula(p).legs == 1 and rula(p, legs_supported=False).legs == 2
    base = rula(p)
    for muscle, force in [(1, 0), (0, 3), (1, 3)]:
        r = rula(p, muscle_use=muscle, force_load=force)
        assert r.score_c == base.score_a + muscle + force and r.score_d == base.score_b + muscle + force
        assert r.grand == table_c(r.score_c, r.score_d) >= base.grand
    with pytest.raises(ValueError):
        rula(p, force_load=4)
    with pytest.raises(ValueError):
        rula(p, muscle_use=0.5)


def test_worked_example():
    # UA: 50 deg flexion (3) + abducted 30 deg (+1) = 4; LA: elbow 110 (2); wrist 10 deg (2); twist 1
    # -> Table A[4][2][2][1] = 4; neck 15 (2), trunk 30 (3), legs 1 -> Table B = 4;
    # muscle use +1 -> C = 5, D = 5 -> grand 6, action level 3.
    p = posture(shoulder_flexion=50.0, shoulder_abduction=30.0, elbow_flexion=110.0, wrist_flexion=10.0,
                neck_flexion=15.0, trunk_flexion=30.0)
    r = rula(p, muscle_use=1)
    assert (r.upper_arm, r.lower_arm, r.wrist, r.wrist_twist) == (4, 2, 2, 1)
    assert (r.neck, r.trunk, r.legs) == (2, 3, 1)
    assert (r.score_a, r.score_b, r.score_c, r.score_d, r.grand, r.action_level) == (4, 4, 5, 5, 6, 3)
    assert part_scores(r).tolist() == [4.0, 2.0, 2.0, 3.0, 2.0]


def test_thresholds_are_configurable():
    p = posture(shoulder_abduction=30.0)
    assert rula(p).upper_arm == 2
    assert rula(p, thresholds=RulaThresholds(abducted=45.0)).upper_arm == 1


def test_missing_angle_is_a_clear_error():
    p = posture()
    del p["neck_rotation"]
    with pytest.raises(ValueError, match="neck_rotation"):
        rula(p)


# -- dropouts ---------------------------------------------------------------------------------------------
def test_nan_frames_are_flagged_not_scored():
    r = rula(posture(wrist_flexion=math.nan))
    assert r.valid is False
    assert all(math.isnan(getattr(r, f)) for f in r._fields if f != "valid")
    assert np.isnan(part_scores(r)).all()
    angles = {n: np.zeros(4) for n in ANGLE_NAMES}
    angles["elbow_flexion"] = np.full(4, 80.0)
    angles["trunk_flexion"] = np.array([0.0, np.nan, 30.0, 0.0])
    angles["shoulder_rotation"] = np.array([0.0, 0.0, 0.0, np.nan])  # not scored, still a dropout
    r = rula(angles)
    assert r.valid.tolist() == [True, False, True, False]
    g = part_scores(r)
    assert g.shape == (4, 5)
    assert np.isnan(g[[1, 3]]).all() and np.isfinite(g[[0, 2]]).all()
    assert g[2, 3] == 3.0 and r.grand[0] == 1.0


# -- properties -------------------------------------------------------------------------------------------
ANGLE = st.floats(-180.0, 180.0, allow_nan=False)
RANGES = {"upper_arm": (1, 6), "lower_arm": (1, 3), "wrist": (1, 4), "wrist_twist": (1, 2), "neck": (1, 6),
          "trunk": (1, 6), "legs": (1, 2), "score_a": (1, 9), "score_b": (1, 9), "grand": (1, 7),
          "action_level": (1, 4)}


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(ANGLE, min_size=14, max_size=14), min_size=1, max_size=12),
       st.lists(st.booleans(), min_size=4, max_size=4), st.integers(0, 1), st.integers(0, 3))
def test_vectorised_equals_per_frame(frames, flags, muscle, force):
    arr = np.array(frames)
    legs = np.resize(flags, len(arr)).astype(bool)
    arm = ~legs
    vec = rula({n: arr[:, i] for i, n in enumerate(ANGLE_NAMES)}, legs_supported=legs, arm_supported=arm,
               muscle_use=muscle, force_load=force)
    for k, row in enumerate(arr):
        one = rula(dict(zip(ANGLE_NAMES, row.tolist())), legs_supported=bool(legs[k]),
                   arm_supported=bool(arm[k]), muscle_use=muscle, force_load=force)
        assert tuple(float(getattr(vec, f)[k]) for f in one._fields[:-1]) == one[:-1]
    for f, (lo, hi) in RANGES.items():
        v = getattr(vec, f)
        assert np.all((v >= lo) & (v <= hi)) and np.all(v == np.round(v)), f


def _scan(name: str, lo: float, hi: float, part: str) -> np.ndarray:
    values = np.linspace(lo, hi, 721)
    p = {n: np.full_like(values, v) for n, v in posture().items()}
    p[name] = values
    return getattr(rula(p), part)


@pytest.mark.parametrize(("name", "part"), [
    ("shoulder_flexion", "upper_arm"), ("wrist_flexion", "wrist"), ("forearm_pronation", "wrist_twist"),
    ("trunk_flexion", "trunk"), ("neck_flexion", "neck"), ("shoulder_elevation", "upper_arm"),
    ("wrist_deviation", "wrist"), ("neck_rotation", "neck"), ("neck_lateral_bend", "neck"),
    ("trunk_rotation", "trunk"), ("trunk_lateral_bend", "trunk"),
])
def test_monotone_away_from_neutral(name, part):
    """Within the band structure a score never falls as a joint moves further from neutral (flexion side)."""
    up = _scan(name, 0.0, 180.0, part)
    assert np.all(np.diff(up) >= 0) and up[-1] > up[0]
    if name not in ("shoulder_elevation", "neck_flexion"):  # neck extension jumps to 4, tested above
        down = _scan(name, 0.0, -180.0, part)
        assert np.all(np.diff(down) >= 0) and down[-1] > down[0]


def test_elbow_band_is_a_valley():
    s = _scan("elbow_flexion", 0.0, 150.0, "lower_arm")
    e = np.linspace(0.0, 150.0, 721)
    assert np.all(s[(e >= 60) & (e <= 100)] == 1) and np.all(s[(e < 60) | (e > 100)] == 2)


def test_inputs_listed():
    assert set(RULA_INPUTS) == set(ANGLE_NAMES) - {"shoulder_rotation"}

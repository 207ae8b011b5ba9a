"""REBA: Tables A, B and C cell by cell against the published tables (Hignett & McAtamney 2000), every
band edge, every adjustment, load, coupling and activity, NaN frames, vectorised == per frame."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ergosim.ergonomics.reba import (
    REBA_INPUTS,
    REBA_PARTS,
    RebaThresholds,
    reba,
    reba_frames,
    reba_part_scores,
    reba_table_a,
    reba_table_b,
    reba_table_c,
)
from ergosim.ergonomics.reba_parts import coupling_score, grip_coupling, load_score
from ergosim.ergonomics.reba_tables import RISK_LEVELS, risk_level
from ergosim.posture import ANGLE_NAMES, neutral_posture

# Typed from the published tables, independently of the module's arrays. Table A: for each neck score a
# block of rows trunk 1..5, each row legs 1..4.
REF_A = {
    1: ["1234", "2345", "2456", "3567", "4678"],
    2: ["1234", "3456", "4567", "5678", "6789"],
    3: ["3356", "4567", "5678", "6789", "7899"],
}
# Table B: for each lower arm score a block of rows upper arm 1..6, each row wrist 1..3.
REF_B = {
    1: ["122", "123", "345", "455", "678", "788"],
    2: ["123", "234", "455", "567", "788", "899"],
}
# Table C: rows score A 1..12, columns score B 1..12.
REF_C = """
1 1 1 2 3 3 4 5 6 7 7 7
1 2 2 3 4 4 5 6 6 7 7 8
2 3 3 3 4 5 6 7 7 8 8 8
3 4 4 4 5 6 7 8 8 9 9 9
4 4 4 5 6 7 8 8 9 9 9 9
6 6 6 7 8 8 9 9 10 10 10 10
7 7 7 8 9 9 9 10 10 11 11 11
8 8 8 9 10 10 10 10 10 11 11 11
9 9 9 10 10 10 11 11 11 12 12 12
10 10 10 11 11 11 11 12 12 12 12 12
11 11 11 11 12 12 12 12 12 12 12 12
12 12 12 12 12 12 12 12 12 12 12 12
"""


def posture(**angles: float) -> dict[str, float]:
    p = neutral_posture()
    p["elbow_flexion"] = 80.0  # lower arm 1 unless a test says otherwise
    p.update(angles)
    return p


# -- tables -----------------------------------------------------------------------------------------------
def test_table_a_cell_by_cell():
    n = 0
    for neck, rows in REF_A.items():
        for trunk, row in enumerate(rows, start=1):
            for legs, digit in enumerate(row, start=1):
                assert reba_table_a(trunk, neck, legs) == int(digit), (trunk, neck, legs)
                n += 1
    assert n == 5 * 3 * 4


def test_table_b_cell_by_cell():
    n = 0
    for lower, rows in REF_B.items():
        for upper, row in enumerate(rows, start=1):
            for wrist, digit in enumerate(row, start=1):
                assert reba_table_b(upper, lower, wrist) == int(digit), (upper, lower, wrist)
                n += 1
    assert n == 6 * 2 * 3


def test_table_c_cell_by_cell_and_clamping():
    ref = [[int(x) for x in line.split()] for line in REF_C.strip().splitlines()]
    n = 0
    for a, b in itertools.product(range(1, 13), range(1, 13)):
        assert reba_table_c(a, b) == ref[a - 1][b - 1], (a, b)
        n += 1
    assert n == 144
    assert reba_table_c(15, 3) == 12 and reba_table_c(1, 14) == 7


def test_tables_validated():
    for bad in [(0, 1, 1), (6, 1, 1), (1, 4, 1), (1, 1, 5), (1.5, 1, 1)]:
        with pytest.raises(ValueError):
            reba_table_a(*bad)
    for bad in [(7, 1, 1), (1, 3, 1), (1, 1, 4)]:
        with pytest.raises(ValueError):
            reba_table_b(*bad)
    with pytest.raises(ValueError):
        reba_table_c(0, 1)


def test_risk_levels():
    assert [int(risk_level(s)) for s in range(1, 16)] == [0, 1, 1, 2, 2, 2, 2, 3, 3, 3, 4, 4, 4, 4, 4]
    assert RISK_LEVELS[0][0] == "negligible" and RISK_LEVELS[4] == ("very high", "necessary now")


# -- band edges (a boundary angle belongs to the lower band) -----------------------------------------------
EDGES = [
    ({"trunk_flexion": 0.0}, "trunk", 1),
    ({"trunk_flexion": 5.0}, "trunk", 1),
    ({"trunk_flexion": 5.01}, "trunk", 2),
    ({"trunk_flexion": 20.0}, "trunk", 2),
    ({"trunk_flexion": 20.01}, "trunk", 3),
    ({"trunk_flexion": 60.0}, "trunk", 3),
    ({"trunk_flexion": 60.01}, "trunk", 4),
    ({"trunk_flexion": -5.01}, "trunk", 2),
    ({"trunk_flexion": -20.0}, "trunk", 2),
    ({"trunk_flexion": -20.01}, "trunk", 3),
    ({"trunk_flexion": -80.0}, "trunk", 3),
    ({"trunk_rotation": 10.0}, "trunk", 1),
    ({"trunk_rotation": 10.01}, "trunk", 2),
    ({"trunk_lateral_bend": -10.01}, "trunk", 2),
    ({"trunk_flexion": 80.0, "trunk_rotation": 20.0, "trunk_lateral_bend": 20.0}, "trunk", 5),  # +1 at most
    ({"neck_flexion": 0.0}, "neck", 1),
    ({"neck_flexion": 20.0}, "neck", 1),
    ({"neck_flexion": 20.01}, "neck", 2),
    ({"neck_flexion": -5.0}, "neck", 1),
    ({"neck_flexion": -5.01}, "neck", 2),
    ({"neck_rotation": 10.01}, "neck", 2),
    ({"neck_lateral_bend": -10.01}, "neck", 2),
    ({"neck_flexion": 40.0, "neck_rotation": 30.0, "neck_lateral_bend": 30.0}, "neck", 3),
    ({"knee_flexion": 30.0}, "legs", 1),
    ({"knee_flexion": 30.01}, "legs", 2),
    ({"knee_flexion": 60.0}, "legs", 2),
    ({"knee_flexion": 60.01}, "legs", 3),
    ({"knee_flexion": 10.0, "left_knee_flexion": 70.0}, "legs", 3),  # the more flexed knee
    ({"shoulder_flexion": 20.0}, "upper_arm", 1),
    ({"shoulder_flexion": 20.01}, "upper_arm", 2),
    ({"shoulder_flexion": 45.0}, "upper_arm", 2),
    ({"shoulder_flexion": 45.01}, "upper_arm", 3),
    ({"shoulder_flexion": 90.0}, "upper_arm", 3),
    ({"shoulder_flexion": 90.01}, "upper_arm", 4),
    ({"shoulder_flexion": -20.0}, "upper_arm", 1),
    ({"shoulder_flexion": -20.01}, "upper_arm", 2),
    ({"shoulder_abduction": 20.01}, "upper_arm", 2),
    ({"shoulder_rotation": 45.0}, "upper_arm", 1),
    ({"shoulder_rotation": -45.01}, "upper_arm", 2),
    ({"shoulder_abduction": 30.0, "shoulder_rotation": 60.0}, "upper_arm", 2),  # abducted or rotated: +1
    ({"shoulder_elevation": 10.01}, "upper_arm", 2),
    ({"shoulder_flexion": 100.0, "shoulder_abduction": 30.0, "shoulder_elevation": 20.0}, "upper_arm", 6),
    ({"elbow_flexion": 60.0}, "lower_arm", 1),
    ({"elbow_flexion": 59.99}, "lower_arm", 2),
    ({"elbow_flexion": 100.0}, "lower_arm", 1),
    ({"elbow_flexion": 100.01}, "lower_arm", 2),
    ({"elbow_flexion": 120.0, "shoulder_abduction": -30.0}, "lower_arm", 2),  # no midline adjustment
    ({"wrist_flexion": 15.0}, "wrist", 1),
    ({"wrist_flexion": -15.01}, "wrist", 2),
    ({"wrist_deviation": 10.01}, "wrist", 2),
    ({"forearm_pronation": 60.0}, "wrist", 1),
    ({"forearm_pronation": -60.01}, "wrist", 2),
    ({"wrist_flexion": 30.0, "wrist_deviation": 20.0, "forearm_pronation": 70.0}, "wrist", 3),
]


@pytest.mark.parametrize(("angles", "part", "expected"), EDGES, ids=[f"{p}-{a}" for a, p, _ in EDGES])
def test_band_edge(angles, part, expected):
    res = reba(posture(**angles))
    assert getattr(res, part) == expected
    assert res.valid


def test_legs_without_knees_assume_straight_knees():
    assert reba(posture()).legs == 1
    assert reba(posture(), legs_bilateral=False).legs == 2
    assert reba(posture(knee_flexion=70.0), legs_bilateral=False).legs == 4


def test_arm_supported_subtracts_one_never_below_one():
    assert reba(posture(shoulder_flexion=50.0), arm_supported=True).upper_arm == 2
    assert reba(posture(), arm_supported=True).upper_arm == 1


def test_load_coupling_activity():
    assert [int(load_score(m)) for m in (0.0, 4.99, 5.0, 10.0, 10.01, 30.0)] == [0, 0, 1, 1, 2, 2]
    assert load_score(6.0, shock=True) == 2
    assert [coupling_score(c) for c in ("good", "fair", "poor", "unacceptable")] == [0, 1, 2, 3]
    with pytest.raises(ValueError, match="coupling must be one of"):
        coupling_score("great")
    assert grip_coupling(0.03) == "good" and grip_coupling(0.008) == "fair" and grip_coupling(0.12) == "fair"
    p = posture(trunk_flexion=30.0, shoulder_flexion=50.0)
    base = reba(p)
    r = reba(p, load_kg=12.0, shock=True, coupling=2, activity=3)
    assert r.load == 3 and r.score_a == base.table_a + 3
    assert r.coupling == 2 and r.score_b == base.table_b + 2
    assert r.table_c == reba_table_c(r.score_a, r.score_b) and r.score == r.table_c + 3
    for bad in ({"coupling": 4}, {"activity": -1}, {"load_kg": -1.0}, {"activity": 0.5}):
        with pytest.raises(ValueError):
            reba(p, **bad)


def test_worked_example():
    # trunk 30 deg (3) twisted (+1) = 4; neck 25 deg (2); legs on both feet, knee 45 deg (+1) = 2
    # -> Table A[4][2][2] = 6; load 6 kg (+1) -> score A 7.
    # upper arm 50 deg (3) abducted (+1) = 4; lower arm 110 deg (2); wrist 20 deg (2) deviated (+1) = 3
    # -> Table B[4][2][3] = 7; coupling fair (+1) -> score B 8.
    # Table C[7][8] = 10; activity +1 -> REBA 11: very high risk, action level 4.
    p = posture(trunk_flexion=30.0, trunk_rotation=15.0, neck_flexion=25.0, knee_flexion=45.0,
                shoulder_flexion=50.0, shoulder_abduction=30.0, elbow_flexion=110.0, wrist_flexion=20.0,
                wrist_deviation=15.0)
    r = reba(p, load_kg=6.0, coupling=1, activity=1)
    assert (r.trunk, r.neck, r.legs, r.table_a, r.load, r.score_a) == (4, 2, 2, 6, 1, 7)
    assert (r.upper_arm, r.lower_arm, r.wrist, r.table_b, r.coupling, r.score_b) == (4, 2, 3, 7, 1, 8)
    assert (r.table_c, r.activity, r.score, r.action_level) == (10, 1, 11, 4)
    assert reba_part_scores(r).tolist() == [4.0, 2.0, 3.0, 4.0, 2.0, 2.0]


def test_thresholds_are_configurable():
    p = posture(shoulder_rotation=50.0)
    assert reba(p).upper_arm == 2
    assert reba(p, thresholds=RebaThresholds(arm_rotated=60.0)).upper_arm == 1


def test_missing_angle_is_a_clear_error():
    p = posture()
    del p["shoulder_rotation"]
    with pytest.raises(ValueError, match="shoulder_rotation"):
        reba(p)


def test_nan_frames_are_flagged_not_scored():
    r = reba(posture(wrist_flexion=math.nan))
    assert r.valid is False and all(math.isnan(getattr(r, f)) for f in r._fields if f != "valid")
    angles = {n: np.zeros(3) for n in ANGLE_NAMES}
    angles["elbow_flexion"] = np.full(3, 80.0)
    angles["knee_flexion"] = np.array([0.0, np.nan, 0.0])
    angles["trunk_flexion"] = np.array([0.0, 0.0, np.nan])
    r = reba(angles)
    assert r.valid.tolist() == [True, False, False]
    assert np.isnan(reba_part_scores(r)[1:]).all() and r.score[0] == 1.0


ANGLE = st.floats(-180.0, 180.0, allow_nan=False)
RANGES = {"upper_arm": (1, 6), "lower_arm": (1, 2), "wrist": (1, 3), "neck": (1, 3), "trunk": (1, 5),
          "legs": (1, 4), "table_a": (1, 9), "table_b": (1, 9), "table_c": (1, 12), "score": (1, 15),
          "action_level": (0, 4)}


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(ANGLE, min_size=15, max_size=15), min_size=1, max_size=12),
       st.integers(0, 3), st.integers(0, 3), st.floats(0.0, 20.0))
def test_vectorised_equals_per_frame(frames, coupling, activity, load):
    arr = np.array(frames)
    names = (*ANGLE_NAMES, "knee_flexion")
    vec = reba({n: arr[:, i] for i, n in enumerate(names)}, coupling=coupling, activity=activity,
               load_kg=load)
    for k, row in enumerate(arr):
        one = reba(dict(zip(names, row.tolist())), coupling=coupling, activity=activity, load_kg=load)
        assert tuple(float(getattr(vec, f)[k]) for f in one._fields[:-1]) == one[:-1]
    for f, (lo, hi) in RANGES.items():
        v = getattr(vec, f)
        assert np.all((v >= lo) & (v <= hi)) and np.all(v == np.round(v)), f


def test_inputs_listed():
    assert set(REBA_INPUTS) == set(ANGLE_NAMES)


def test_frames_match_reba_per_frame():
    rng = np.random.default_rng(0)
    a = rng.uniform(-60, 120, (40, 14))
    a[5, 3] = np.nan
    knees = rng.uniform(0, 90, (40, 1))
    load = rng.uniform(0, 12, 40)
    parts, score, g = reba_frames(a, load, 1, knees=knees)
    for k in range(40):
        p = dict(zip(ANGLE_NAMES, a[k].tolist()), knee_flexion=float(knees[k, 0]))
        one = reba(p, load_kg=float(load[k]), coupling=1)
        if k == 5:
            assert np.isnan(parts[k]).all() and np.isnan(score[k]) and np.isnan(g[k]).all()
            continue
        assert parts[k].tolist() == [getattr(one, n) for n in REBA_PARTS] and score[k] == one.score
        assert g[k].tolist() == reba_part_scores(one).tolist()

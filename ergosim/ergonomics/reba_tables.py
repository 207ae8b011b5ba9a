"""The three REBA lookup tables (Hignett & McAtamney 2000, Applied Ergonomics 31:201-205, Tables A-C).

Indices are zero-based scores: ``TABLE_A[trunk - 1, neck - 1, legs - 1]``,
``TABLE_B[upper_arm - 1, lower_arm - 1, wrist - 1]``, ``TABLE_C[min(score_a, 12) - 1, min(score_b, 12) - 1]``.
Score A is Table A plus the load/force score, score B is Table B plus the coupling score; the REBA score is
Table C plus the activity score (1..15).
"""

from __future__ import annotations

import numpy as np

__all__ = ["TABLE_A", "TABLE_B", "TABLE_C", "RISK_LEVELS", "risk_level"]


def _rows(text: str) -> np.ndarray:
    return np.array([[int(c) for c in row.split()] for row in text.strip().splitlines()], dtype=np.int64)


# Rows: trunk 1..5; columns: neck 1 (legs 1..4) | neck 2 (legs 1..4) | neck 3 (legs 1..4).
_A = _rows("""
1 2 3 4  1 2 3 4  3 3 5 6
2 3 4 5  3 4 5 6  4 5 6 7
2 4 5 6  4 5 6 7  5 6 7 8
3 5 6 7  5 6 7 8  6 7 8 9
4 6 7 8  6 7 8 9  7 8 9 9
""")
TABLE_A: np.ndarray = _A.reshape(5, 3, 4)
"""(5, 3, 4) posture score A [trunk, neck, legs], values 1..9."""

# Rows: upper arm 1..6; columns: lower arm 1 (wrist 1..3) | lower arm 2 (wrist 1..3).
_B = _rows("""
1 2 2  1 2 3
1 2 3  2 3 4
3 4 5  4 5 5
4 5 5  5 6 7
6 7 8  7 8 8
7 8 8  8 9 9
""")
TABLE_B: np.ndarray = _B.reshape(6, 2, 3)
"""(6, 2, 3) posture score B [upper arm, lower arm, wrist], values 1..9."""

# Rows: score A 1..12; columns: score B 1..12.
TABLE_C: np.ndarray = _rows("""
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
""")
"""(12, 12) score C [score A 1..12, score B 1..12], values 1..12."""

for _t in (TABLE_A, TABLE_B, TABLE_C):
    _t.setflags(write=False)

RISK_LEVELS: dict[int, tuple[str, str]] = {
    0: ("negligible", "none necessary"),
    1: ("low", "may be necessary"),
    2: ("medium", "necessary"),
    3: ("high", "necessary soon"),
    4: ("very high", "necessary now"),
}
"""REBA action level 0..4 -> (risk level, action): REBA score 1, 2-3, 4-7, 8-10, 11-15."""


def risk_level(score):
    """REBA action level 0..4 from the REBA score 1..15 (1 -> 0, 2-3 -> 1, 4-7 -> 2, 8-10 -> 3, 11+ -> 4);
    scalar or array."""
    s = np.asarray(score)
    return (s >= 2).astype(np.int64) + (s >= 4) + (s >= 8) + (s >= 11)

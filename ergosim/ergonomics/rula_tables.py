"""The three RULA lookup tables (McAtamney & Corlett 1993, Tables A, B and C) as integer numpy arrays.

Indices are zero-based scores: ``TABLE_A[upper_arm - 1, lower_arm - 1, wrist - 1, wrist_twist - 1]``,
``TABLE_B[neck - 1, trunk - 1, legs - 1]``, ``TABLE_C[min(score_c, 8) - 1, min(score_d, 7) - 1]``.
Vectorised lookups are plain fancy indexing into these arrays.
"""

from __future__ import annotations

import numpy as np

__all__ = ["TABLE_A", "TABLE_B", "TABLE_C", "ACTION_LEVELS"]


def _pairs(rows: str) -> np.ndarray:
    """Parse rows of two-digit cells ("12 22 ...", one digit per twist/legs column) into an int array."""
    return np.array([[[int(c) for c in cell] for cell in row.split()] for row in rows.strip().splitlines()],
                    dtype=np.int64)


# Rows: upper arm 1..6 x lower arm 1..3; cells: wrist 1..4; digits: wrist twist 1, 2.
_A = _pairs("""
12 22 23 33
22 22 33 33
23 33 33 44
23 33 34 44
33 33 34 44
34 44 44 55
33 44 44 55
34 44 44 55
44 44 45 55
44 44 45 55
44 44 45 55
44 45 55 66
55 55 56 67
56 66 67 77
66 67 77 78
77 77 78 89
88 88 89 99
99 99 99 99
""")
TABLE_A: np.ndarray = _A.reshape(6, 3, 4, 2)
"""(6, 3, 4, 2) posture score A [upper arm, lower arm, wrist, wrist twist], values 1..9."""

# Rows: neck 1..6; cells: trunk 1..6; digits: legs 1, 2.
TABLE_B: np.ndarray = _pairs("""
13 23 34 55 66 77
23 23 45 55 67 77
33 34 45 56 67 77
55 56 67 77 77 88
77 77 78 88 88 88
88 88 88 89 99 99
""")
"""(6, 6, 2) posture score B [neck, trunk, legs], values 1..9."""

TABLE_C: np.ndarray = np.array([
    [1, 2, 3, 3, 4, 5, 5],
    [2, 2, 3, 4, 4, 5, 5],
    [3, 3, 3, 4, 4, 5, 6],
    [3, 3, 3, 4, 5, 6, 6],
    [4, 4, 4, 5, 6, 7, 7],
    [4, 4, 5, 6, 6, 7, 7],
    [5, 5, 6, 6, 7, 7, 7],
    [5, 5, 6, 7, 7, 7, 7],
], dtype=np.int64)
"""(8, 7) grand score [score C 1..8+, score D 1..7+], values 1..7."""

for _t in (TABLE_A, TABLE_B, TABLE_C):
    _t.setflags(write=False)

ACTION_LEVELS: dict[int, str] = {
    1: "acceptable", 2: "acceptable",
    3: "investigate further", 4: "investigate further",
    5: "investigate further and change soon", 6: "investigate further and change soon",
    7: "investigate and change immediately",
}
"""RULA action level wording per grand score 1..7."""

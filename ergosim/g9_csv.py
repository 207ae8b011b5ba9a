"""The CSV text ``np.savetxt(table, fmt="%.9g", delimiter=",")`` writes, built by numpy in bulk.

savetxt formats row by row in Python (about 0.2 us a value: an hour's ticks.csv takes half a second).
Here a value whose 9-digit rounding prints in fixed notation (decimal exponent -4..8, as %g decides) is
rounded by numpy, exactly: with ``e`` its decimal exponent, ``|x| * 10**(8 - e)`` multiplies by an exact
power of ten (at most 10^14), so the product is correctly rounded (error below 6e-8 under 1e9) and its
nearest integer is the correctly rounded 9-digit significand %g prints, unless the product lies within
1e-6 of a half. Those ties and near-ties, and the values %g prints in exponent notation, go through
Python's ``"%.9g"`` itself. NaN and inf print as Python prints them ("nan", "inf", "-inf").

Each value's text is laid out in a cell of four 8-byte words with NUL wherever savetxt writes nothing,
each word looked up in a table, and the NULs are dropped at the end::

    sign "0." and up to 3 zeros (exponent < 0) | d0 . d1 . d2 | d3 . d4 . d5 | d6 . d7 . d8 separator

A digit group's word is one of 16 variants of its 3 digits: how many it keeps (digits after the last
non-zero fraction digit are dropped) and whether the point follows one of them (after the last integer
digit, if a fraction follows).
"""

from __future__ import annotations

import numpy as np

__all__ = ["g9_csv"]

_P10 = 10.0 ** np.arange(16)  # exact in binary64 up to 10^22
_TRAILING_ZEROS = np.array([3] + [len(s) - len(s.rstrip("0")) for s in (f"{k:03d}" for k in range(1, 1000))])
_NEAR_HALF = 1e-6  # far above the 6e-8 rounding error of the scaled product
_CELL = 32  # bytes: four words
_NUL = 0
_BATCH = 1 << 15  # values formatted at once


def _word(text: str) -> int:
    """The uint64 whose little-endian bytes are ``text`` (up to 8 characters, NUL where empty)."""
    return int.from_bytes(text.encode().replace(b" ", b"\0").ljust(8, b"\0"), "little")


# Prefix word of sign (0/1) and exponent x10 (-4..8): index 16 * sign + x10 + 4.
_PREFIX = np.array([_word(("-" if neg else " ") + ("0." + "0" * (-x - 1) if x < 0 else ""))
                    for neg in (0, 1) for x in range(-4, 12)], dtype="<u8")
# Group word of (kept digits 0..3, point after digit 0..2 or 3 = none) and the group's value g (0..999):
# index 1000 * (4 * kept + point) + g.
_GROUP = np.array([_word("".join(d + ("." if i == point else " ") for i, d in enumerate(f"{g:03d}"[:kept])))
                   for kept in range(4) for point in range(4) for g in range(1000)], dtype="<u8")


def _significand(ax: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(m, x10, exact) of non-negative ``ax``: where ``exact``, ``ax`` rounded to 9 significant digits is
    ``m * 10**(x10 - 8)`` with ``1e8 <= m < 1e9`` (float64 holding an integer; m = 0 for zero), printed by
    %.9g in fixed notation (-4 <= x10 <= 8), and numpy's rounding is the correct one."""
    zero, finite = ax == 0, np.isfinite(ax)
    ax = np.where(finite & ~zero, ax, 1.0)
    e = np.floor(np.log10(ax))  # a guess: may be off by one near a power of ten
    np.clip(e, -6, 9, out=e)
    e = e.astype(np.int64)
    s = ax * _P10[np.clip(8 - e, 0, 15)]
    # Both sets are found before either is moved: a value that is still out of range stays inexact.
    for off, wrong in ((1, np.flatnonzero(s >= 1e9)), (-1, np.flatnonzero(s < 1e8))):
        e[wrong] += off
        s[wrong] = ax[wrong] * _P10[np.clip(8 - e[wrong], 0, 15)]
    m = np.rint(s)
    frac = s - np.floor(s)
    exact = (s >= 1e8) & (s < 1e9) & (np.abs(frac - 0.5) >= _NEAR_HALF) & (e >= -6) & (e <= 8) & finite
    up = m >= 1e9  # 999999999.5 and above round to the next decade
    x10 = e + up
    m[up] = 1e8
    exact &= (x10 >= -4) & (x10 <= 8)
    exact |= zero
    m[zero] = 0.0
    x10[zero] = 0
    return m, x10, exact


def _cells(x: np.ndarray) -> np.ndarray:
    """(n, 32) bytes: the cells of the values ``x`` (n,), the last byte (the separator) left NUL."""
    m, x10, exact = _significand(np.abs(x))
    m = np.where(exact, m, 0.0)
    x10 = np.where(exact, x10, 0)
    # m's three 3-digit groups (exact: the quotients of integers below 1e9 by 1e3 and 1e6 floor correctly)
    thousands = np.floor(m / 1e3)
    groups = [np.floor(m / 1e6), thousands - 1e3 * np.floor(m / 1e6), m - 1e3 * thousands]
    groups = [g.astype(np.int64) for g in groups]
    hi, mid, lo = groups
    # index of the last non-zero digit (-1 for zero), and of the last digit printed
    last = 8 - np.where(lo != 0, _TRAILING_ZEROS[lo], np.where(mid != 0, 3 + _TRAILING_ZEROS[mid],
                                                                 6 + _TRAILING_ZEROS[hi]))
    kept = np.maximum(last, x10) + 1
    point = np.where((x10 >= 0) & (last > x10), x10, -9)  # no point: far from every group
    words = np.empty((len(x), 4), "<u8")
    words[:, 0] = _PREFIX[16 * np.signbit(x) + x10 + 4]
    for k, g in enumerate(groups):
        at = point - 3 * k
        variant = 4 * np.clip(kept - 3 * k, 0, 3) + np.where((at >= 0) & (at <= 2), at, 3)
        words[:, k + 1] = _GROUP[1000 * variant + g]
    cell = words.view(np.uint8)
    special = np.flatnonzero(~exact)
    if len(special):
        # NaN, inf, exponent notation, ties and near-ties: Python's own formatting (Python prints every NaN
        # "nan", whatever its sign bit)
        text = b"".join(("%.9g" % v).encode().ljust(_CELL, b"\0") for v in x[special].tolist())
        cell[special] = np.frombuffer(text, np.uint8).reshape(len(special), _CELL)
    return cell


def g9_csv(table: np.ndarray) -> bytes:
    """The bytes ``np.savetxt(buf, table, fmt="%.9g", delimiter=",")`` writes for a (rows, cols) float
    ``table``: one line per row, values separated by commas, each line ending in a newline."""
    a = np.asarray(table, dtype=float)
    if a.ndim != 2:
        raise ValueError(f"expected a (rows, cols) table, got shape {a.shape}")
    rows, cols = a.shape
    if cols == 0:
        return b"\n" * rows
    step = max(1, _BATCH // cols)  # rows per batch: its temporaries stay in the cache
    parts = []
    for r in range(0, rows, step):
        cell = _cells(a[r:r + step].ravel()).reshape(-1, cols, _CELL)
        cell[:, :, -1] = ord(",")
        cell[:, -1, -1] = ord("\n")
        parts.append(cell.tobytes().translate(None, b"\0"))
    return b"".join(parts)

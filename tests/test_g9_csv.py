"""The bulk "%.9g" CSV writer gives exactly the bytes of np.savetxt, value by value."""

from __future__ import annotations

import io

import numpy as np
import pytest

from ergosim.g9_csv import g9_csv


def _savetxt(table: np.ndarray) -> bytes:
    buf = io.StringIO()
    np.savetxt(buf, table, fmt="%.9g", delimiter=",")
    return buf.getvalue().encode()


EDGES = [
    0.0, -0.0, np.nan, -np.nan, np.inf, -np.inf, 1.0, -1.0, 7.0, 0.05, 0.1, 0.15, 3600.0, 1e-5, -1e-5, 1e-4,
    9.99999999e-5, 9.999999995e-5, 9.9999999949e-5, 0.00009999999996, 1.00000000049e-4, 999999999.0,
    999999999.4, 999999999.5, 999999998.5, 1e9, 1e9 + 1, 123456789.5, 123456788.5, 99999999.995, 1e8 - 0.5,
    0.5, 1.5, 2.5, 0.125, 1e300, -1e-300, 5e-324, -5e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
    12345.6789012345, -0.000574999999, 7.30104375e-05, 0.9999999999999731, float(np.nextafter(1.0, 0.0)),
    1e15, 1e16, 123456789012.0, 0.001, 0.0001234567891, 1 / 3, 2 / 3, 89.99999999, 90.0, -179.9999999995,
]


def test_edge_values_one_per_row_and_in_a_row():
    edges = np.array(EDGES)
    for table in (edges[:, None], edges[None, :], np.tile(edges, (3, 1))):
        assert g9_csv(table) == _savetxt(table)


@pytest.mark.parametrize("seed", [0, 1])
def test_random_values_of_every_magnitude(seed):
    rng = np.random.default_rng(seed)
    n = 60_000
    digits = rng.integers(10**8, 10**9, n)
    exp10 = rng.integers(-7, 11, n).astype(float)
    parts = [
        rng.standard_normal(n) * 10.0 ** rng.uniform(-8, 12, n),  # every exponent, both notations
        np.round(rng.uniform(-180, 180, n), 6),  # BVH-like angles
        rng.integers(-3, 10, n).astype(float),  # scores, flags
        (digits + 0.5) * 10.0 ** (exp10 - 8),  # halves: ties or within an ulp of one
        np.nextafter((digits + 0.5) * 10.0 ** (exp10 - 8), 0.0),
        10.0 ** exp10 * (1 - 1e-16 * rng.integers(0, 3, n)),  # around powers of ten
        rng.integers(0, 2**64 - 1, n, dtype=np.uint64).view(np.float64),  # any bit pattern
    ]
    table = np.concatenate(parts).reshape(-1, 30)
    assert g9_csv(table) == _savetxt(table)


def test_shapes():
    assert g9_csv(np.empty((0, 4))) == _savetxt(np.empty((0, 4))) == b""
    assert g9_csv(np.empty((2, 0))) == _savetxt(np.empty((2, 0)))
    big = np.arange(100_003.0).reshape(-1, 1) / 7.0  # more rows than one batch, and a partial last batch
    assert g9_csv(big) == _savetxt(big)
    with pytest.raises(ValueError, match="rows, cols"):
        g9_csv(np.zeros(3))

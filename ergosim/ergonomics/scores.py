"""Validated look-ups of integer scores, shared by the RULA and REBA tables."""

from __future__ import annotations

import numpy as np

__all__ = ["score_index"]


def score_index(name: str, value, hi: int) -> np.ndarray:
    """Zero-based int indices of integer scores ``value`` in 1..``hi`` (scalar or array; floats holding
    integers are accepted); ValueError naming ``name`` otherwise."""
    v = np.asarray(value)
    i = v.astype(np.int64) if v.dtype.kind in "iub" else np.rint(v).astype(np.int64)
    if not (np.all(i == v) and np.all((i >= 1) & (i <= hi))):
        raise ValueError(f"{name} must be an integer score 1..{hi}, got {value!r}")
    return i - 1

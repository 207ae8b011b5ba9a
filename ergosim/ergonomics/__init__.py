"""Ergonomic assessment (paper §4-5): RULA per body part, the Kinematic Wear index, its calibration,
risk indices and the hyper-arc cost model."""

from __future__ import annotations

import numpy as np

from ergosim.ergonomics.kwear import KWearParams, alpha_of, kwear_step, kwear_trajectory, predict
from ergosim.ergonomics.rula import RulaResult, RulaThresholds, rula, table_a, table_b, table_c

__all__ = [
    "RulaResult",
    "RulaThresholds",
    "rula",
    "table_a",
    "table_b",
    "table_c",
    "part_scores",
    "KWearParams",
    "kwear_step",
    "kwear_trajectory",
    "alpha_of",
    "predict",
]


def part_scores(result: RulaResult, out: np.ndarray | None = None) -> np.ndarray:
    """KWear inputs G_i (paper eq. 3) from a RULA result: (..., 5) floats in ``posture.KWEAR_JOINTS`` order
    (shoulder = upper arm, elbow = lower arm, wrist, trunk, neck); NaN where the frame is not valid."""
    parts = (result.upper_arm, result.lower_arm, result.wrist, result.trunk, result.neck)
    if out is None:
        return np.stack(np.broadcast_arrays(*(np.asarray(p, dtype=float) for p in parts)), axis=-1)
    for i, p in enumerate(parts):
        out[..., i] = p
    return out

"""The posture features the twin computes per measured frame for the risk indices that run.

RULA's part scores are always computed (they fill ``ticks.csv``'s ``rula_*`` columns and feed the paper's
KWear). When a run's modes use a REBA index, every measured segment is also scored with REBA
(:func:`~ergosim.ergonomics.reba.reba_frames`): the load is the mass in the worker's hand while it holds
the action's part (the part and whatever is seated in it, from the compiled scene) and the coupling that
part's grip gives (its ``coupling`` in the workcell file, else
:func:`~ergosim.ergonomics.reba_parts.grip_coupling` of its grip width); between the grasp and the
release only, 0 kg otherwise. Activity is 0 (the bundled actions last seconds; none repeats 4 times a
minute). The REBA columns are :data:`REBA_COLUMNS`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np

from ergosim.ergonomics.features import feature
from ergosim.ergonomics.reba import REBA_PARTS, reba_frames
from ergosim.ergonomics.reba_parts import coupling_score, grip_coupling

__all__ = ["REBA_COLUMNS", "Hold", "cell_hold", "FeatureScorer"]

REBA_COLUMNS: tuple[str, ...] = tuple(f"reba_{p}" for p in REBA_PARTS) + ("reba_score",)
"""The tick-log columns a REBA index adds: its part scores and the REBA score."""

Hold = Callable[[str], tuple[float, int]]
"""part -> (mass held [kg], REBA coupling score 0..3) while the worker holds it."""


def cell_hold(cell) -> Hold:
    """What the worker's hand carries when it takes ``part`` in ``cell`` as the scene stands: the mass of
    the part's assembly [kg] (its compiled body masses) and the coupling of the part's grip."""
    spec = cell.config

    def hold(part: str) -> tuple[float, int]:
        mass = float(sum(cell.model.body_mass[cell.model.body(p).id] for p in cell.assembly(part)))
        p = spec.part(part)
        return mass, coupling_score(p.coupling if p.coupling is not None else grip_coupling(p.grip_width))

    return hold


class FeatureScorer:
    """Scores measured frames with the extra features ``features`` (beyond RULA's): for REBA, the
    :data:`REBA_COLUMNS` per frame, its KWear inputs (n, 6) and its whole-body score."""

    def __init__(self, features: Iterable[str], hold: Hold | None = None) -> None:
        self.features = tuple(f for f in dict.fromkeys(features) if f != "rula")
        for f in self.features:
            feature(f)  # a ConfigError for an unknown feature
        self.hold = hold
        self.columns: tuple[str, ...] = REBA_COLUMNS if "reba" in self.features else ()

    def score(self, measured: np.ndarray, motion, acting: bool) -> tuple[np.ndarray, dict, dict]:
        """(extra columns (n, k), KWear inputs per feature (n, m), whole-body score per feature (n,)) of n
        measured frames (n, >= 14) [deg] of ``motion`` (an ActionMotion: its part, rate and grasp times)."""
        n = len(measured)
        extra, g, whole = np.empty((n, 0)), {}, {}
        if "reba" in self.features:
            load = np.zeros(n)
            coupling = 0
            if acting and self.hold is not None and np.isfinite(motion.t_grasp):
                mass, coupling = self.hold(motion.part)
                t = np.asarray(motion.t, dtype=float)
                release = motion.t_release if np.isfinite(motion.t_release) else np.inf
                load[(t >= motion.t_grasp) & (t < release)] = mass
            parts, score, g_reba = reba_frames(measured, load, coupling)
            extra = np.column_stack([parts, score])
            g["reba"], whole["reba"] = g_reba, score
        if "angles" in self.features:
            g["angles"] = np.asarray(measured, dtype=float)[:, :len(feature("angles").joints)]
        return extra, g, whole

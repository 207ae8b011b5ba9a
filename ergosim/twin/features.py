"""The posture features the twin computes per measured frame for the risk indices that run.

RULA's part scores are always computed (they fill ``ticks.csv``'s ``rula_*`` columns and feed the paper's
KWear). Every further feature a run's modes read is scored by its own hook
(:attr:`~ergosim.ergonomics.features.Feature.score`) on the measured frames, with the load in the worker's
hand: the mass of the action's part (and whatever is seated in it, from the compiled scene) while the
worker holds it, between the grasp and the release only, 0 kg otherwise, and the coupling that part's grip
gives (its ``coupling`` in the workcell file, else :func:`~ergosim.ergonomics.reba_parts.grip_coupling` of
its grip width). REBA's activity score is 0 (the bundled actions last seconds; none repeats 4 times a
minute).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np

from ergosim.ergonomics.features import REBA_COLUMNS, Frames, feature
from ergosim.ergonomics.reba_parts import coupling_score, grip_coupling

__all__ = ["REBA_COLUMNS", "Hold", "cell_hold", "FeatureScorer"]

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
    """Scores measured frames with the features ``features`` that have a score hook (every one but the
    track's own RULA): their tick-log columns, their KWear inputs and their whole-body scores."""

    def __init__(self, features: Iterable[str], hold: Hold | None = None) -> None:
        self.features = tuple(f for f in map(feature, dict.fromkeys(features)) if f.score is not None)
        self.hold = hold
        self.columns: tuple[str, ...] = tuple(c for f in self.features for c in f.columns)

    @classmethod
    def of(cls, features: Iterable[str], cell) -> FeatureScorer | None:
        """The scorer of ``features`` in ``cell`` (what the worker holds there), or None when none of them
        has a hook (RULA alone)."""
        scored = [f for f in dict.fromkeys(features) if feature(f).score is not None]
        return cls(scored, cell_hold(cell)) if scored else None

    def score(self, measured: np.ndarray, motion, acting: bool) -> tuple[np.ndarray, dict, dict]:
        """(extra columns (n, k), KWear inputs per feature (n, m), whole-body score per feature (n,)) of n
        measured frames (n, >= 14) [deg] of ``motion`` (an ActionMotion: its part, rate and grasp times)."""
        n = len(measured)
        load = np.zeros(n)
        coupling = 0
        if acting and self.hold is not None and np.isfinite(motion.t_grasp):
            mass, coupling = self.hold(motion.part)
            t = np.asarray(motion.t, dtype=float)
            release = motion.t_release if np.isfinite(motion.t_release) else np.inf
            load[(t >= motion.t_grasp) & (t < release)] = mass
        frames = Frames(measured, load, coupling)
        scores = {f.name: f.score(frames) for f in self.features}
        extra = np.column_stack([np.empty((n, 0)), *(s.columns for s in scores.values())])
        whole = {name: s.whole for name, s in scores.items() if s.whole is not None}
        return extra, {name: s.g for name, s in scores.items()}, whole

"""The posture features a risk index may read (the risk-index contract, :mod:`ergosim.ergonomics.risk_index`),
one registry of them.

A feature is what the twin computes from every measured mocap frame for an index: its columns (the index's
joints G_i), the whole-body score that a static baseline and the G(a_k) of an action use, and the tick-log
columns it adds. Its ``score`` hook turns n measured frames (:class:`Frames`) into those
(:class:`FeatureScores`); the twin calls it for every feature a run's modes read
(:class:`ergosim.twin.features.FeatureScorer`) and knows no feature by name. A new index with a feature of
its own is one module: :func:`register_feature` and the index (tests/extension_trunk.py).

==========  ==========================================================  ===========================
feature     columns (G_i per tick)                                      whole-body score
==========  ==========================================================  ===========================
``rula``    RULA part scores: shoulder (upper arm), elbow (lower arm),  RULA grand score, 1..7
            wrist, trunk, neck (:data:`~ergosim.posture.KWEAR_JOINTS`)
``reba``    REBA part scores: the same five and the legs                REBA score, 1..15
            (:data:`~ergosim.ergonomics.reba.REBA_JOINTS`)
``angles``  the 14 canonical joint angles [deg]                         none
            (:data:`~ergosim.posture.ANGLE_NAMES`)
==========  ==========================================================  ===========================

``rula`` has no hook: the worker's track scores RULA for every frame (the paper's KWear inputs and
ticks.csv's ``rula_*`` columns).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ergosim.ergonomics.reba import REBA_JOINTS, REBA_PARTS, reba_frames
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS
from ergosim.registry import Registry

__all__ = ["Feature", "Frames", "FeatureScores", "FEATURES", "feature", "register_feature", "REBA_COLUMNS"]

REBA_COLUMNS: tuple[str, ...] = tuple(f"reba_{p}" for p in REBA_PARTS) + ("reba_score",)
"""The tick-log columns the REBA feature adds: its part scores and the REBA score."""


@dataclass(frozen=True)
class Frames:
    """n measured frames of one action's motion: ``angles`` (n, >= 14) [deg], the first 14 in
    :data:`~ergosim.posture.ANGLE_NAMES` order (NaN rows: mocap dropouts); ``load`` (n,) the mass in the
    worker's hand [kg] (the part's assembly between the grasp and the release, 0 otherwise);
    ``coupling`` the REBA coupling score (0..3) of that part's grip."""

    angles: np.ndarray
    load: np.ndarray
    coupling: int


@dataclass(frozen=True)
class FeatureScores:
    """A feature's scores of n frames: ``g`` (n, m) the index's inputs G_i (:attr:`Feature.joints` order);
    ``columns`` (n, k) its tick-log columns (:attr:`Feature.columns`); ``whole`` (n,) its whole-body score,
    or None."""

    g: np.ndarray
    columns: np.ndarray
    whole: np.ndarray | None = None


@dataclass(frozen=True)
class Feature:
    """``name``; ``joints`` the columns of its per-tick row; ``whole`` the name of its whole-body score (None
    for raw angles); ``description`` in words; ``columns`` the tick-log columns it adds; ``score`` the hook
    that scores measured frames (None: the track's own RULA scores)."""

    name: str
    joints: tuple[str, ...]
    whole: str | None
    description: str
    columns: tuple[str, ...] = ()
    score: Callable[[Frames], FeatureScores] | None = None

    @property
    def extends_kwear(self) -> bool:
        """Its first joints are the paper's five (:data:`~ergosim.posture.KWEAR_JOINTS`): the worker's
        online KWear may run on it (RULA's, REBA's); an index on another feature runs beside that KWear."""
        return self.joints[:len(KWEAR_JOINTS)] == KWEAR_JOINTS


FEATURES: Registry[Feature] = Registry("posture feature", where="risk index")
"""The posture features by name (a risk index's ``features``)."""


def register_feature(f: Feature) -> None:
    """Make posture feature ``f`` available by name to the risk indices, in worker processes too."""
    FEATURES.register(f.name, f)


def feature(name: str) -> Feature:
    """The feature ``name``; ConfigError naming the choices."""
    return FEATURES.get(name)


def _reba(frames: Frames) -> FeatureScores:
    parts, score, g = reba_frames(frames.angles, frames.load, frames.coupling)
    return FeatureScores(g, np.column_stack([parts, score]), score)


def _angles(frames: Frames) -> FeatureScores:
    angles = np.asarray(frames.angles, dtype=float)
    return FeatureScores(angles[:, :len(ANGLE_NAMES)], np.empty((len(angles), 0)))


register_feature(Feature("rula", KWEAR_JOINTS, "rula_grand", "RULA part scores (McAtamney & Corlett 1993)"))
register_feature(Feature("reba", REBA_JOINTS, "reba_score", "REBA part scores with the legs (Hignett & "
                         "McAtamney 2000)", REBA_COLUMNS, _reba))
register_feature(Feature("angles", ANGLE_NAMES, None, "the canonical joint angles [deg]", score=_angles))

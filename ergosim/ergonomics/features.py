"""The posture features a risk index may read (the risk-index contract, :mod:`ergosim.ergonomics.risk_index`).

A feature is what the twin computes from every measured mocap frame for an index: its columns (the index's
joints G_i), and the whole-body score that a static baseline and the G(a_k) of an action use.

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
"""

from __future__ import annotations

from dataclasses import dataclass

from ergosim.ergonomics.reba import REBA_JOINTS
from ergosim.errors import ConfigError
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS

__all__ = ["Feature", "FEATURES", "feature"]


@dataclass(frozen=True)
class Feature:
    """``name``; ``joints`` the columns of its per-tick row; ``whole`` the name of its whole-body score (None
    for raw angles); ``description`` in words."""

    name: str
    joints: tuple[str, ...]
    whole: str | None
    description: str


FEATURES: dict[str, Feature] = {
    "rula": Feature("rula", KWEAR_JOINTS, "rula_grand", "RULA part scores (McAtamney & Corlett 1993)"),
    "reba": Feature("reba", REBA_JOINTS, "reba_score",
                    "REBA part scores with the legs (Hignett & McAtamney 2000)"),
    "angles": Feature("angles", ANGLE_NAMES, None, "the canonical joint angles [deg]"),
}


def feature(name: str) -> Feature:
    """The feature ``name``; ConfigError naming the choices."""
    try:
        return FEATURES[name]
    except KeyError:
        raise ConfigError(f"unknown posture feature {name!r}; features: {', '.join(FEATURES)}",
                          where="risk index") from None

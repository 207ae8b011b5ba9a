"""G(a_k): the RULA grand score of a whole action, the "standard method" applied offline (paper §7.1).

RULA scores a posture, not an action. McAtamney & Corlett (1993, §2 "Using RULA") have the observer choose
the posture *held for the greatest amount of the work cycle*, or the one where the highest loads occur. The
twin's actions carry light parts (force/load 0), so the first rule applies: G(a_k) is the grand score held
for the most time during the action, i.e. the mode of its per-tick grand scores, pooled over the recorded
executions (ties go to the higher score, the conservative reading). This one definition serves the static
RULA baseline's threshold test (§7.1, G_th = 0.8 G_max), the ``rula_g_by_action`` of summary.json and the
fidelity report.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

__all__ = ["action_grand_score", "most_loaded_joint"]


def action_grand_score(grand: np.ndarray | Iterable[np.ndarray]) -> float:
    """G(a_k) from per-tick grand scores: one (n,) array, or several executions' arrays pooled. NaN ticks
    (mocap dropouts) are ignored; NaN if no tick is valid."""
    if isinstance(grand, np.ndarray):
        pooled = grand.ravel()
    else:
        parts = [np.asarray(g, dtype=float).ravel() for g in grand]
        pooled = np.concatenate(parts) if parts else np.empty(0)
    pooled = pooled[np.isfinite(pooled)]
    if not pooled.size:
        return float("nan")
    values, counts = np.unique(pooled, return_counts=True)
    return float(values[np.flatnonzero(counts == counts.max())[-1]])


def most_loaded_joint(alpha: np.ndarray, joints: tuple[str, ...]) -> str:
    """The joint an action loads most: the largest KWear after one execution from zero wear, 1 - α_i
    (eq. 9; the paper's Fig. "KWear trend ... starting from zero initial conditions")."""
    return joints[int(np.argmax(1.0 - np.asarray(alpha, dtype=float)))]

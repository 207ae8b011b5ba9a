"""G(a_k): the RULA grand score of a whole action, the "standard method" applied offline (paper §7.1).

RULA scores a posture, not an action. McAtamney & Corlett (1993, §2 "Using RULA") have the observer choose
the posture *held for the greatest amount of the work cycle*, or the one where the highest loads occur.
Readings of that instruction, as rules over the per-tick grand scores of an action (:data:`G_RULES`):

- ``held-longest``: the score held for the most time (the mode; ties to the higher score);
- ``quarter``: the score reached or exceeded for at least a quarter of the action (the 75th percentile):
  the worst posture that still takes a good part of the action;
- ``held-1s``: the highest score held without a break for at least one second (the worst posture that
  is held, not merely passed through);
- ``worst``: the highest score at any moment (where the highest loads occur).

One rule, :data:`G_RULE`, serves both experiments: the static RULA baseline's threshold test (§7.1,
G_th = 0.8 G_max), the ``rula_g_by_action`` of summary.json and the fidelity report. Which rule matches the
paper's observers in both experiments is measured in docs/fidelity.md (:mod:`ergosim.fidelity.g_rules`).
Executions are scored separately and the median taken (pooled ticks for the two counting rules).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

__all__ = ["G_RULES", "G_RULE", "action_grand_score", "grand_scores_by_rule", "most_loaded_joint"]

G_RULES = ("held-longest", "quarter", "held-1s", "worst")
G_RULE = "held-1s"
"""The reading of RULA's instruction the twin uses (docs/fidelity.md: the one that fits both experiments)."""


def _executions(grand: np.ndarray | Iterable[np.ndarray]) -> list[np.ndarray]:
    arrays = [grand] if isinstance(grand, np.ndarray) else list(grand)
    return [np.asarray(g, dtype=float).ravel() for g in arrays]


def _held(g: np.ndarray, ticks: int) -> float:
    """The highest score held for ``ticks`` consecutive valid ticks (NaN ticks break a hold)."""
    best = np.nan
    for value in np.unique(g[np.isfinite(g)])[::-1]:
        run = 0
        for ok in g >= value:
            run = run + 1 if ok else 0
            if run >= ticks:
                return float(value)
        best = value
    return float(best) if np.isfinite(best) else float("nan")


def action_grand_score(grand: np.ndarray | Iterable[np.ndarray], rule: str = G_RULE,
                       dt: float = 0.05) -> float:
    """G(a_k) from per-tick grand scores: one (n,) array, or several executions' arrays; ``dt`` [s] the tick.
    NaN ticks (mocap dropouts) are ignored; NaN if no tick is valid."""
    if rule not in G_RULES:
        raise ValueError(f"unknown G rule {rule!r}; rules: {', '.join(G_RULES)}")
    runs = [g for g in _executions(grand) if np.isfinite(g).any()]
    if not runs:
        return float("nan")
    if rule in ("held-1s", "worst"):
        ticks = max(1, int(round(1.0 / dt)))
        per = [_held(g, ticks) if rule == "held-1s" else float(np.nanmax(g)) for g in runs]
        return float(np.median(per))
    pooled = np.concatenate(runs)
    pooled = pooled[np.isfinite(pooled)]
    if rule == "quarter":
        return float(np.percentile(pooled, 75.0, method="inverted_cdf"))
    values, counts = np.unique(pooled, return_counts=True)
    return float(values[np.flatnonzero(counts == counts.max())[-1]])


def grand_scores_by_rule(grand: np.ndarray | Iterable[np.ndarray], dt: float = 0.05) -> dict[str, float]:
    """G(a_k) under every rule of :data:`G_RULES`."""
    runs = _executions(grand)
    return {rule: action_grand_score(runs, rule, dt) for rule in G_RULES}


def most_loaded_joint(alpha: np.ndarray, joints: tuple[str, ...]) -> str:
    """The joint an action loads most: the largest KWear after one execution from zero wear, 1 - α_i
    (eq. 9; the paper's Fig. "KWear trend ... starting from zero initial conditions")."""
    return joints[int(np.argmax(1.0 - np.asarray(alpha, dtype=float)))]

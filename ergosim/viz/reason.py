"""One wording for why an action went to an agent, shared by the allocation log, the loop and the tests.

The human's hyper-arc cost jumps by Γ when a predicted KWear V̂_i(t_k+1) reaches its threshold V_th,i
(paper eq. 11), so the sentence names the joint that decides: the one that crosses its threshold by the
most, or, when none does, the one closest to it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ergosim.posture import KWEAR_JOINTS

__all__ = ["allocation_reason", "lookahead_reason"]


def allocation_reason(chosen: tuple[str, str], *, v_hat: Mapping[str, np.ndarray],
                      costs: Mapping[tuple[str, str], float], v_th: np.ndarray) -> str:
    """E.g. ``"a2 → robot: predicted shoulder KWear 0.83 ≥ V_th 0.80; cost robot 50.00 < worker 100.83"``.

    ``chosen``: (action, agent). ``v_hat``: action -> (5,) predicted KWear in ``KWEAR_JOINTS`` order (the
    worker doing that action). ``costs``: (action, agent) -> hyper-arc cost of the candidates.
    ``v_th``: (5,) thresholds.
    """
    action, agent = chosen
    parts = [_kwear_clause(v_hat.get(action), np.asarray(v_th, dtype=float))]
    parts.append(_cost_clause(action, agent, costs))
    return f"{action} → {agent}: " + "; ".join(p for p in parts if p)


def _kwear_clause(v: np.ndarray | None, v_th: np.ndarray) -> str:
    if v is None:
        return ""
    v = np.asarray(v, dtype=float)
    margin = v - v_th
    if not np.any(np.isfinite(margin)):
        return "no KWear prediction"
    i = int(np.nanargmax(margin))
    joint = KWEAR_JOINTS[i]
    if margin[i] >= 0:
        crossed = int(np.sum(margin >= 0))
        more = f" (+{crossed - 1} more joint{'s' if crossed > 2 else ''})" if crossed > 1 else ""
        return f"predicted {joint} KWear {v[i]:.2f} ≥ V_th {v_th[i]:.2f}{more}"
    return f"predicted KWear below V_th on every joint (closest: {joint} {v[i]:.2f} < {v_th[i]:.2f})"


def _cost_clause(action: str, agent: str, costs: Mapping[tuple[str, str], float]) -> str:
    mine = costs.get((action, agent))
    others = sorted((a, c) for (act, a), c in costs.items() if act == action and a != agent)
    if not others:
        return f"only {agent} can do {action}"
    if mine is None:
        return ""
    clauses = []
    for other, cost in others:
        op = "<" if mine < cost else ("=" if mine == cost else ">")
        clauses.append(f"cost {agent} {mine:.2f} {op} {other} {cost:.2f}")
    return ", ".join(clauses)


def lookahead_reason(action: str, agent: str, plan, cost: float, other: float, *, exact: bool,
                     gap: float) -> str:
    """E.g. ``"a2 → robot: starts the cheapest sequence a2·robot a3·human a4·human a5·human, 7.12 (exact);
    a2 by another agent: 7.40"``. ``plan``: (action, agent) pairs in order; ``other``: the cheapest sequence
    that gives ``action`` to another agent (NaN if not computed); ``gap``: how far the beam's sequence can be
    from the optimum."""
    steps = " ".join(f"{a}·{who}" for a, who in plan)
    quality = "exact" if exact else f"beam, within {gap:.2f} of the optimum"
    text = f"{action} → {agent}: starts the cheapest sequence {steps}, {cost:.2f} ({quality})"
    if np.isfinite(other):
        text += f"; {action} by another agent: {other:.2f}"
    return text

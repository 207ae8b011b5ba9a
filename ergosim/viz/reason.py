"""Why an action went to an agent, in words: the sentence the rerun recording and the video show.

The allocator records a decision's reason as data (:class:`~ergosim.twin.allocator.Decision` and its
:class:`~ergosim.twin.allocator.Basis`); :func:`reason_text` words it. The human's hyper-arc cost jumps by
Γ when a predicted KWear V̂_i(t_k+1) reaches its threshold V_th,i (paper eq. 11), so the sentence names the
joint that decides: the one that crosses its threshold by the most, or, when none does, the one closest to
it (:func:`allocation_reason`). A risk index may register its own wording (:func:`register_reason`); one
without words its decisions the same way against its thresholds.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

import numpy as np

from ergosim.ergonomics.reba import REBA_JOINTS
from ergosim.registry import Registry

if TYPE_CHECKING:  # only read: the simulation does not know its words
    from ergosim.twin.allocator import Decision

__all__ = ["allocation_reason", "reason_text", "register_reason", "REASONS"]

REASONS: Registry[Callable[[Decision], str]] = Registry("reason wording", where="reason")
"""The wording of a risk index's decisions, by the index's name: decision -> ``"a2 → robot: ..."``."""


def register_reason(index: str, words: Callable[[Decision], str]) -> None:
    """Word the decisions of risk index ``index`` with ``words(decision)`` (in worker processes too)."""
    REASONS.register(index, words)


def reason_text(d: Decision) -> str:
    """The sentence of decision ``d``: the risk index's wording (:data:`REASONS`; a threshold sentence
    like KWear's for an index without one), or ``"a2 → robot: r-only mode"`` for a mode without an index;
    then, in parallel execution, why an idle agent took a costlier plan or fetched a part early."""
    index = d.basis.index
    if index is None:
        text = f"{d.action} → {d.agent}: {d.basis.mode} mode"
    else:
        text = (REASONS[index] if index in REASONS else _threshold_reason)(d)
    if d.excess:
        text += f"; the {d.agent} is idle: best ready operation, plan +{d.excess:.2f}"
    if d.early:
        text += f"; fetches {d.part} while the rest goes on"
    return text


def _threshold_reason(d: Decision) -> str:
    """The predicted risk of each channel against its V_th (eq. 11), then the costs (KWear's wording)."""
    shape = np.asarray(d.v_hat[d.action]).shape
    return allocation_reason((d.action, d.agent), v_hat=d.v_hat, costs=d.costs,
                             v_th=np.broadcast_to(np.asarray(d.basis.v_th, dtype=float), shape))


def _rula_reason(d: Decision, score: str = "RULA") -> str:
    """The static RULA baseline (§7.1): G(a_k) against G_th, then the worker's and the cheapest robot's
    cost; ``score`` names the whole-body score (``REBA`` for the static REBA baseline)."""
    b, action = d.basis, d.action
    hc = d.costs.get((action, b.human))
    rc = min((d.costs[(action, r)] for r in b.robots if (action, r) in d.costs), default=float("nan"))
    th = float(np.max(b.v_th))
    vh = np.asarray(d.v_hat[action])
    rel = "≥" if vh[int(np.argmax(vh))] >= th else "<"
    return (f"{action} → {d.agent}: {score} G={vh[0] * b.scale:g} {rel} G_th {th * b.scale:g}"
            f" (human cost {hc:.2f}, robot cost {rc:.2f})")


def allocation_reason(chosen: tuple[str, str], *, v_hat: Mapping[str, np.ndarray],
                      costs: Mapping[tuple[str, str], float], v_th: np.ndarray) -> str:
    """E.g. ``"a2 → robot: predicted shoulder KWear 0.83 ≥ V_th 0.80; cost robot 50.00 < worker 100.83"``.

    ``chosen``: (action, agent). ``v_hat``: action -> (5,) predicted KWear in ``KWEAR_JOINTS`` order, or (6,)
    with the legs (KWear on REBA's part scores, ``REBA_JOINTS``), the worker doing that action. ``costs``:
    (action, agent) -> hyper-arc cost of the candidates. ``v_th``: thresholds of the same shape.
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
    joint = REBA_JOINTS[i]  # KWEAR_JOINTS, then the legs of KWear on REBA's part scores
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


register_reason("kwear", _threshold_reason)
register_reason("rula-static", _rula_reason)
register_reason("reba-static", lambda d: _rula_reason(d, "REBA"))

"""The role allocator of paper Fig. 1: risk prediction -> hyper-arc costs -> AO* -> next (action, agent).

Modes: ``hrc`` predicts KWear per candidate action (eq. 9) and prices the human's hyper-arcs with
eq. 10-11; ``rula`` uses the paper's static RULA baseline (a constant G(a_k) per action, §7.1); ``h-only``
and ``r-only`` prune the other agent's hyper-arcs (the paper's pruning, §2.2) and keep the task file's costs.
The risk index and the cost model live in :mod:`ergosim.ergonomics`; the search in :mod:`ergosim.planner`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from ergosim.ergonomics.cost import CostParams, risk_costs
from ergosim.ergonomics.risk_index import RiskIndex
from ergosim.planner import AndOrGraph
from ergosim.viz.reason import allocation_reason

__all__ = ["Decision", "Allocator"]


@dataclasses.dataclass(frozen=True)
class Decision:
    """What the allocator saw and chose at one decision point (sim time [s]).

    ``v_now`` (5,) KWear; ``v_hat``: action -> predicted risk (p,) of the index in use; ``costs``: the
    (action, agent) costs the planner got; ``had_choice``: more than one agent could take ``action``.
    """

    time: float
    repetition: int
    v_now: np.ndarray
    v_hat: Mapping[str, np.ndarray]
    costs: Mapping[tuple[str, str], float]
    action: str
    agent: str
    operation: str
    had_choice: bool
    reason: str

    def cost_of(self, agent: str) -> float:
        return float(self.costs.get((self.action, agent), np.nan))


class Allocator:
    """Decides the next (action, agent) for one worker and one robot on an AND/OR graph.

    ``index``: the risk index whose prediction sets the human's costs (KWear for ``hrc``, the static RULA
    index for ``rula``; unused by ``h-only``/``r-only``); ``cost``: Γ, V_th, c_r (eq. 10-11).
    """

    def __init__(self, graph: AndOrGraph, mode: str, *, index: RiskIndex | None, cost: CostParams | None,
                 planner: str = "fast") -> None:
        self.graph = graph
        self.mode = mode
        self.index = index
        self.cost = cost
        self.planner = planner
        kinds = {a.name: a.kind for a in graph.agents}
        self.human = next(n for n, k in kinds.items() if k == "human")
        self.robot = next(n for n, k in kinds.items() if k == "robot")
        self.allowed: dict[str, set[str]] = {}
        for op in graph.operations:
            self.allowed.setdefault(op.action, set()).update(op.agents)
        self.base_pruned = self._mode_pruning()
        self._action_of = {op.name: op.action for op in graph.operations}

    def _mode_pruning(self) -> set[tuple[str, str]]:
        pruned: set[tuple[str, str]] = set()
        for action, agents in self.allowed.items():
            if self.mode == "h-only":
                pruned.update((action, a) for a in agents if a != self.human)
            elif self.mode == "r-only" and self.robot in agents:
                pruned.add((action, self.human))
        return pruned

    def decide(self, v_now: np.ndarray, done: list[str], pruned: set[tuple[str, str]], time: float,
               repetition: int) -> Decision | None:
        done_actions = {self._action_of[o] for o in done}
        remaining = [a for a in self.graph.actions if a not in done_actions]
        if not remaining:
            return None
        costs: dict[tuple[str, str], float] = {}
        v_hat: dict[str, np.ndarray] = {}
        if self.mode in ("hrc", "rula"):
            v_hat = {a: self.index.predict(a) for a in remaining}
            costs = risk_costs(self.index, remaining, self.human, [self.robot], self.cost)
        cut = self.base_pruned | pruned
        step = self.graph.plan(done=done, costs=costs, pruned=cut, planner=self.planner).next
        if step is None:
            return None
        agents = self.allowed[step.action] - {a for (act, a) in cut if act == step.action}
        return Decision(
            time=time, repetition=repetition, v_now=np.array(v_now), v_hat=v_hat, costs=costs,
            action=step.action, agent=step.agent, operation=step.operation, had_choice=len(agents) > 1,
            reason=self.reason(step.action, step.agent, v_hat, costs),
        )

    def reason(self, action: str, agent: str, v_hat, costs) -> str:
        """Why ``agent`` got ``action``, in words.

        E.g. "a2 → robot: predicted shoulder KWear 0.83 ≥ V_th 0.8 (human cost 101.9, robot cost 2.50)".
        """
        if self.mode in ("h-only", "r-only"):
            return f"{action} → {agent}: {self.mode} mode"
        hc, rc = costs.get((action, self.human)), costs.get((action, self.robot))
        th = float(np.max(self.cost.v_th))
        vh = np.asarray(v_hat[action])
        i = int(np.argmax(vh))
        rel = "≥" if vh[i] >= th else "<"
        if self.mode == "rula":
            g_max = self.index.g_max
            return (f"{action} → {agent}: RULA G={vh[0] * g_max:g} {rel} G_th {th * g_max:g}"
                    f" (human cost {hc:.2f}, robot cost {rc:.2f})")
        return allocation_reason((action, agent), v_hat=v_hat, costs=costs,
                                 v_th=np.broadcast_to(np.asarray(self.cost.v_th, dtype=float), vh.shape))

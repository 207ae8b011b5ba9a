"""The role allocator of paper Fig. 1: risk prediction -> hyper-arc costs -> AO* -> next (action, agent).

Modes: ``hrc`` predicts KWear per candidate action (eq. 9) and prices the human's hyper-arcs with
eq. 10-11; ``rula`` uses the paper's static RULA baseline (a constant G(a_k) per action); ``h-only`` and
``r-only`` prune the other agent's hyper-arcs (the paper's pruning, §2.2) and keep the task file's costs.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from ergosim.ergonomics.kwear import predict
from ergosim.planner import AndOrGraph

__all__ = ["Decision", "Allocator", "human_cost"]


def human_cost(v_hat: np.ndarray, v_th: float | np.ndarray, gamma: float) -> np.ndarray:
    """Eq. 10-11: Σ_i γ_i with γ_i = V̂_i, plus Γ where V̂_i ≥ V_th,i. ``v_hat`` (..., m) -> (...)."""
    v_hat = np.asarray(v_hat, dtype=float)
    return (v_hat + gamma * (v_hat >= v_th)).sum(axis=-1)


@dataclasses.dataclass(frozen=True)
class Decision:
    """What the allocator saw and chose at one decision point (sim time [s])."""

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

    ``alphas``: calibrated α_k (5,) per action (eq. 9); ``rula_g``: G(a_k) per action for the static
    baseline. ``online_weight`` > 0 blends the α observed in each executed action into α_k (§5, last
    paragraph): α_k ← (1 − w) α_k + w α_observed.
    """

    def __init__(self, graph: AndOrGraph, mode: str, *, robot_cost: float, gamma: float, v_th: float,
                 alphas: Mapping[str, np.ndarray] | None = None, rula_g: Mapping[str, float] | None = None,
                 rula_threshold: float = 7.2, rula_g_max: float = 9.0, planner: str = "fast",
                 online_weight: float = 0.0) -> None:
        self.graph = graph
        self.mode = mode
        kinds = {a.name: a.kind for a in graph.agents}
        self.human = next(n for n, k in kinds.items() if k == "human")
        self.robot = next(n for n, k in kinds.items() if k == "robot")
        self.robot_cost = float(robot_cost)
        self.gamma = float(gamma)
        self.v_th = v_th
        self.alphas = {a: np.asarray(v, dtype=float).copy() for a, v in (alphas or {}).items()}
        self.rula_g = dict(rula_g or {})
        self.rula_threshold = float(rula_threshold)
        self.rula_g_max = float(rula_g_max)
        self.planner = planner
        self.online_weight = float(online_weight)
        self.allowed: dict[str, set[str]] = {}
        for op in graph.operations:
            self.allowed.setdefault(op.action, set()).update(op.agents)
        self.base_pruned = self._mode_pruning()
        self._v_start: np.ndarray | None = None

    def _mode_pruning(self) -> set[tuple[str, str]]:
        pruned: set[tuple[str, str]] = set()
        for action, agents in self.allowed.items():
            if self.mode == "h-only":
                pruned.update((action, a) for a in agents if a != self.human)
            elif self.mode == "r-only" and self.robot in agents:
                pruned.add((action, self.human))
        return pruned

    def costs(self, v_now: np.ndarray, actions) -> tuple[dict, dict]:
        """Hyper-arc costs per (action, agent) for the candidate ``actions``, and V̂ per action."""
        v_hat: dict[str, np.ndarray] = {}
        costs: dict[tuple[str, str], float] = {}
        if self.mode == "hrc":
            for a in actions:
                v_hat[a] = predict(v_now, self.alphas[a])
                costs[(a, self.human)] = float(human_cost(v_hat[a], self.v_th, self.gamma))
                costs[(a, self.robot)] = self.robot_cost
        elif self.mode == "rula":
            for a in actions:
                g = self.rula_g[a]
                # Same shape as eq. 11: a normalised risk below the threshold, + Γ at or above it (§7.1).
                penalty = self.gamma if g >= self.rula_threshold else 0.0
                costs[(a, self.human)] = g / self.rula_g_max + penalty
                costs[(a, self.robot)] = self.robot_cost
        return costs, v_hat

    def decide(self, v_now: np.ndarray, done: list[str], pruned: set[tuple[str, str]], time: float,
               repetition: int) -> Decision | None:
        remaining = [a for a in self.graph.actions if a not in {self.graph.operation(o).action for o in done}]
        if not remaining:
            return None
        costs, v_hat = self.costs(v_now, remaining)
        cut = self.base_pruned | pruned
        plan = self.graph.plan(done=done, costs=costs, pruned=cut, planner=self.planner)
        step = plan.next
        if step is None:
            return None
        agents = self.allowed[step.action] - {a for (act, a) in cut if act == step.action}
        decision = Decision(
            time=time, repetition=repetition, v_now=np.array(v_now), v_hat=v_hat, costs=costs,
            action=step.action, agent=step.agent, operation=step.operation,
            had_choice=len(agents) > 1, reason=self.reason(step.action, step.agent, v_hat, costs),
        )
        self._v_start = np.array(v_now)
        return decision

    def reason(self, action: str, agent: str, v_hat, costs) -> str:
        """Why ``agent`` got ``action``, in words (used by the allocation log)."""
        from ergosim.posture import KWEAR_JOINTS  # noqa: PLC0415 - tiny, avoids a cycle in docs builds

        if self.mode in ("h-only", "r-only"):
            return f"{action} → {agent}: {self.mode} mode"
        hc, rc = costs.get((action, self.human)), costs.get((action, self.robot))
        if self.mode == "rula":
            g = self.rula_g[action]
            rel = "≥" if g >= self.rula_threshold else "<"
            return f"{action} → {agent}: RULA G={g:g} {rel} G_th {self.rula_threshold:g}"
        vh = v_hat[action]
        i = int(np.argmax(vh))
        rel = "≥" if vh[i] >= self.v_th else "<"
        return (f"{action} → {agent}: predicted {KWEAR_JOINTS[i]} KWear {vh[i]:.2f} {rel} V_th {self.v_th:g}"
                f" (human cost {hc:.2f}, robot cost {rc:.2f})")

    def observe(self, decision: Decision, plant) -> None:
        """After a completed action: the online α update of §5, if enabled, for the human's actions."""
        if self.online_weight <= 0 or decision.agent != self.human or self._v_start is None:
            return
        v0, v1 = self._v_start, plant.v
        with np.errstate(divide="ignore", invalid="ignore"):
            observed = np.where(1 - v0 > 1e-9, (1 - v1) / (1 - v0), 1.0)
        w = self.online_weight
        self.alphas[decision.action] = (1 - w) * self.alphas[decision.action] + w * np.clip(observed, 0, 1)

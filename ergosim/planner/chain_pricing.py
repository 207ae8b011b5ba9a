"""Pricing partial sequences for the look-ahead searches, many at once: the wear chain as array steps.

A *pricing* turns a partial sequence of hyper-arcs into a row of state arrays (cost so far first) and
prices one more step for many rows at once, so the beam advances a whole level with a few numpy calls.

- :class:`SequentialPricing`: one agent at a time (the paper's execution, Algorithm 2). State: cost, the
  worker's V (p,), the time since the repetition's start. A worker step wears (eq. 9), a robot step rests
  the worker over its duration (eq. 5).
- :class:`~ergosim.planner.lookahead_team.TeamPricing` (parallel execution) keeps agent clocks instead.

Both give :meth:`Pricing.estimate`: the order-free cost of the actions still needed (each at its cheapest
agent, the paper's prices eq. 9-11), from the row's V (the beam's ranking) or from the lowest V the row can
still reach (an admissible bound for branch and bound and for the beam's reported gap).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from ergosim.errors import ConfigError
from ergosim.planner.transitions import Transitions, transitions
from ergosim.planner.wear_chain import WearModel, next_cost

__all__ = ["Pricing", "SequentialPricing"]


class Pricing:
    """The model's arrays in the graph's action and agent order, and the (action, agent) pairs this call
    allows (the graph's hyper-arcs minus ``pruned``)."""

    def __init__(self, graph, model: WearModel, pruned: Iterable[tuple[str, str]] = ()) -> None:
        self.view: Transitions = transitions(graph)
        self.graph = graph
        try:
            acts = np.array([model.action_index[a] for a in graph.actions], dtype=np.int64)
            agents = np.array([model.agent_index[a.name] for a in graph.agents], dtype=np.int64)
        except KeyError as err:
            raise ConfigError(f"the wear model has no {err.args[0]!r} of task {graph.name!r}",
                              where="lookahead") from None
        self.model = model
        self.alpha = model.alpha[acts]
        self.duration = model.duration[np.ix_(acts, agents)]
        self.rest_s = model.rest[np.ix_(acts, agents)]
        self.cost = np.repeat(model.agent_cost[agents][None, :], len(acts), axis=0)
        """(A, N) the price of a robot's step (c_r; a pricing may override pairs for its call)."""
        found = np.flatnonzero(agents == model.human)
        self.human = int(found[0]) if len(found) else -1
        self.k = model.rest_rate
        self.allowed = self.view.allowed.copy()
        act_of = {a: i for i, a in enumerate(graph.actions)}
        agent_of = {a.name: i for i, a in enumerate(graph.agents)}
        for key in pruned:
            if not (isinstance(key, tuple) and len(key) == 2 and key[0] in act_of and key[1] in agent_of):
                raise ConfigError(f"pruned pairs are known (action, agent) pairs, got {key!r}",
                                  where="pruned")
            self.allowed[act_of[key[0]], agent_of[key[1]]] = False
        self.derive()

    def derive(self) -> None:
        """The per-call summaries of the arrays (again after a pricing overrides some of them)."""
        self.unpruned = bool(np.array_equal(self.allowed, self.view.allowed))
        robots = self.allowed.copy()
        if self.human >= 0:
            robots[:, self.human] = False
        self.robot_min = np.where(robots, self.cost, np.inf).min(axis=1, initial=np.inf)
        self.human_ok = (self.allowed[:, self.human] if self.human >= 0
                         else np.zeros(len(self.allowed), dtype=bool))
        self.min_duration = np.where(self.allowed, self.duration, np.inf).min(axis=1, initial=np.inf)
        self.min_duration[~np.isfinite(self.min_duration)] = 0.0
        self.max_rest = np.where(robots, self.rest_s, 0.0).max(axis=1, initial=0.0)

    def children(self, cid: int):
        """The allowed ready (operation, agent) pairs of configuration ``cid``: (op, action, agent, next,
        next is complete, actions needed after)."""
        s = self.view.successors(cid)
        if self.unpruned:
            return s.op, s.action, s.agent, s.next, s.done, s.need
        keep = self.allowed[s.action, s.agent]
        return s.op[keep], s.action[keep], s.agent[keep], s.next[keep], s.done[keep], s.need[keep]

    def order_free(self, v: np.ndarray) -> np.ndarray:
        """The paper's prices (eq. 9-11) of every action from wear ``v`` (n, p) -> (n, A): Σ_i V̂_i is
        p − α·(1 − V), a matrix product; the Γ terms are counted only where some V̂_i can reach V_th."""
        w = 1.0 - v
        out = self.alpha.shape[1] - w @ self.alpha.T
        th = self.model.v_th
        if np.any(1.0 - self.alpha.min(axis=0) * w.min(axis=0) >= th):
            over = (1.0 - self.alpha[None] * w[:, None, :]) >= th
            out += self.model.cost.gamma * over.sum(axis=2)
        return out

    def needed_cost(self, need: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Σ over the needed actions (n, A) of the cheaper of the worker (order-free, from ``v`` (n, p))
        and the cheapest robot -> (n,)."""
        human = np.where(self.human_ok[None], self.order_free(v), np.inf)
        each = np.minimum(human, self.robot_min[None])
        return np.where(need, each, 0.0).sum(axis=1)

    def time_terms(self, t0: np.ndarray, t1: np.ndarray) -> np.ndarray:
        """The takt and time terms of going from predicted end ``t0`` to ``t1`` [s from the repetition's
        start] (n,)."""
        m = self.model
        over = m.takt_weight * (np.maximum(0.0, t1 - m.takt) - np.maximum(0.0, t0 - m.takt))
        return over + m.time_weight * (t1 - t0)

    # the interface of a pricing: start, step, estimate, dominance
    def start(self, v0, elapsed: float) -> tuple[np.ndarray, ...]:
        raise NotImplementedError

    def step(self, state, op, action, agent):
        """(state of the children, price of each step, its predicted start [s])."""
        raise NotImplementedError

    def estimate(self, state, need: np.ndarray, *, lowest: bool) -> np.ndarray:
        raise NotImplementedError

    def end_wear(self, state) -> np.ndarray:
        """(n, p) the worker's V when the repetition of each (complete) sequence ends."""
        raise NotImplementedError

    def terminal(self, state) -> np.ndarray:
        """What a complete sequence adds for the wear it leaves
        (:func:`~ergosim.planner.wear_chain.next_cost`)."""
        return next_cost(self.model, self.end_wear(state))

    def dominance(self, state) -> np.ndarray | None:
        """(n, m) keys such that a row no greater in every key and in cost can do no worse from the same
        configuration; None when no such order holds (no pruning by dominance)."""
        return None


class SequentialPricing(Pricing):
    """One agent at a time. State: (cost, V (n, p), time since the repetition's start (n,))."""

    def start(self, v0, elapsed: float):
        return np.zeros(1), np.asarray(v0, dtype=float)[None, :], np.array([float(elapsed)])

    def step(self, state, op, action, agent):
        g, v, t = state
        human = agent == self.human
        v_hat = 1.0 - self.alpha[action] * (1.0 - v)
        rested = v * np.exp(-self.k * self.rest_s[action, agent])[:, None]
        v_new = np.where(human[:, None], v_hat, rested)
        price = np.where(human, self.model.price(v_hat), self.cost[action, agent])
        t_new = t + self.duration[action, agent]
        return (g + price + self.time_terms(t, t_new), v_new, t_new), price, t

    def estimate(self, state, need, *, lowest: bool):
        if not self.view.action_once:
            return np.zeros(len(need))
        _, v, t = state
        if lowest:  # the worker rests at most while a robot does every needed action it may do (eq. 5)
            v = v * np.exp(-self.k * (need * self.max_rest).sum(axis=1))[:, None]
        return (self.needed_cost(need, v) + self.time_terms(t, t + (need * self.min_duration).sum(axis=1))
                + next_cost(self.model, v))

    def end_wear(self, state):
        return state[1]

    def dominance(self, state):
        _, v, t = state
        return np.column_stack([v, t])

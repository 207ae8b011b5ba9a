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

from abc import ABC, abstractmethod
from collections.abc import Iterable

import numpy as np

from ergosim.errors import ConfigError
from ergosim.planner.pilot import pilot_table
from ergosim.planner.transitions import Transitions, transitions
from ergosim.planner.wear_chain import WearModel

__all__ = ["Pricing", "SequentialPricing"]


class Pricing(ABC):
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
        robot = np.nanmin(model.agent_cost) if np.isfinite(model.agent_cost).any() else np.inf
        self.next_cap = np.where(model.robot_ok[acts], robot, np.inf)
        self.next_alpha = self.alpha.sum(axis=0)
        self.next_flat = float(self.alpha.size)
        """Σ_a α_a (p,) and A·p: the next repetition's order-free price, Σ_a Σ_i (1 − α_a,i (1 − V_i)), is
        ``next_flat − next_alpha·(1 − V)`` when the worker does every action."""
        """(A,) what the next repetition pays at most per action (its cheapest robot, where one may do it)."""
        self.duration = model.duration[np.ix_(acts, agents)]
        self.rest_s = model.rest[np.ix_(acts, agents)]
        self.leave = model.leave[np.ix_(acts, agents)]
        self.cost = np.repeat(model.agent_cost[agents][None, :], len(acts), axis=0)
        """(A, N) the price of a robot's step (c_r; a pricing may override pairs for its call)."""
        found = np.flatnonzero(agents == model.human)
        self.human = int(found[0]) if len(found) else -1
        self.k = model.rest_rate
        self.pilot = None
        """The beam's per-configuration table for this call (:func:`~ergosim.planner.pilot.pilot_table`)."""
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
        self.robot_duration = np.where(robots, self.duration, np.inf).min(axis=1, initial=np.inf)
        self.robot_duration[~np.isfinite(self.robot_duration)] = 0.0

    def children(self, cid: int) -> tuple[np.ndarray, np.ndarray]:
        """The allowed ready (operation, agent) pairs of configuration ``cid``: their
        :attr:`~ergosim.planner.transitions.Successors.table` (6, k) and the actions needed after each
        (k, A)."""
        s = self.view.successors(cid)
        if self.unpruned:
            return s.table, s.need
        keep = self.allowed[s.action, s.agent]
        return s.table[:, keep], s.need[keep]

    def expand(self, cids: list[int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The children of every configuration in ``cids``, joined: the index in ``cids`` of each one's
        parent (n,), their tables (6, n) and needs (n, A) as :meth:`children`."""
        parts = [self.children(c) for c in cids]
        parent = np.repeat(np.arange(len(cids)), [p[0].shape[1] for p in parts])
        return parent, np.concatenate([p[0] for p in parts], axis=1), np.concatenate([p[1] for p in parts])

    def order_free(self, v: np.ndarray, gamma: bool = True) -> np.ndarray:
        """The paper's prices (eq. 9-11) of every action from wear ``v`` (n, p) -> (n, A): Σ_i V̂_i is
        p − α·(1 − V), a matrix product; the Γ terms are counted only where some V̂_i can reach V_th (and
        not at all with ``gamma`` False)."""
        w = 1.0 - v
        out = self.alpha.shape[1] - w @ self.alpha.T
        th = self.model.v_th
        if gamma and np.any(1.0 - self.alpha.min(axis=0) * w.min(axis=0) >= th):
            over = (1.0 - self.alpha[None] * w[:, None, :]) >= th
            out += self.model.cost.gamma * over.sum(axis=2)
        return out

    def needed_cost(self, need: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Σ over the needed actions (n, A) of the cheaper of the worker (order-free, from ``v`` (n, p))
        and the cheapest robot -> (n,)."""
        human = np.where(self.human_ok[None], self.order_free(v), np.inf)
        each = np.minimum(human, self.robot_min[None])
        return np.where(need, each, 0.0).sum(axis=1)

    def chain_bound(self, need: np.ndarray, v: np.ndarray, longest: np.ndarray) -> np.ndarray:
        """A lower bound (n,) on the wear and robot cost of completing each row that sees the chain grow.

        If the worker does m of the r needed actions, its k-th one leaves at least ρ_m·V''_k, where V''_k =
        1 − (1 − V)·Π(the k largest α of the needed actions it may do, per joint) is the chain without rest
        (the product of any k α is at most that of the k largest) and ρ_m = e^{−(r/C)·T_m} its rest over
        at most T_m = ``longest[:, r − m]`` seconds (a wear step after a rest leaves at least ρ times what it
        leaves without it, eq. 5 and 9). Priced on Σ_i V̂_i (the Γ terms dropped), plus the r − m cheapest
        robot costs and the next repetition's price of ρ_m·V''_m, minimised over the m the pairs allow.
        ``longest`` (n, A + 1): column j bounds the worker's rest when robots do j of the needed actions."""
        n, n_a = need.shape
        worker = need & self.human_ok[None]
        alpha = np.where(worker[:, :, None], self.alpha[None], -1.0)
        alpha = -np.sort(-alpha, axis=1)
        prod = np.cumprod(np.where(alpha < 0, 1.0, alpha), axis=1)  # (n, A, p): rank k = index k - 1
        v2 = 1.0 - (1.0 - v[:, None, :]) * prod
        linear = np.concatenate([np.zeros((n, 1)), np.cumsum(v2.sum(axis=2), axis=1)], axis=1)  # by m
        r = need.sum(axis=1)
        robot_cost = np.sort(np.where(need & np.isfinite(self.robot_min)[None], self.robot_min[None], np.inf),
                             axis=1)
        cheapest = np.concatenate([np.zeros((n, 1)), np.cumsum(robot_cost, axis=1)], axis=1)  # by robot count
        m = np.arange(n_a + 1)[None, :]
        robots = np.clip(r[:, None] - m, 0, n_a)
        rho = np.exp(-self.k * np.take_along_axis(longest, robots, axis=1))
        ok = (m <= worker.sum(axis=1)[:, None]) & (m <= r[:, None]) & np.isfinite(
            np.take_along_axis(cheapest, robots, axis=1))
        total = rho * linear + np.take_along_axis(cheapest, robots, axis=1)
        if self.model.next_weight:
            last = np.concatenate([v[:, None, :], v2], axis=1)  # V'' after m worker actions
            after = self.next_cost((rho[:, :, None] * last).reshape(-1, v.shape[1]), gamma=False)
            after = after.reshape(n, n_a + 1)
            total = total + after
        return np.where(ok, total, np.inf).min(axis=1)

    def time_terms(self, t0: np.ndarray, t1: np.ndarray) -> np.ndarray:
        """The takt and time terms of going from predicted end ``t0`` to ``t1`` [s from the repetition's
        start] (n,)."""
        m = self.model
        over = m.takt_weight * (np.maximum(0.0, t1 - m.takt) - np.maximum(0.0, t0 - m.takt))
        return over + m.time_weight * (t1 - t0) if m.time_weight else over  # t1 >= t0: the same bits

    # the interface of a pricing: start, step, estimate, dominance
    @abstractmethod
    def start(self, v0, elapsed: float) -> tuple[np.ndarray, ...]:
        """The state of the empty sequence from wear ``v0`` at ``elapsed`` [s] into the repetition."""

    @abstractmethod
    def step(self, state, op, action, agent):
        """(state of the children, price of each step, its predicted start [s])."""

    @abstractmethod
    def estimate(self, state, need: np.ndarray, *, lowest: bool, cids=None) -> np.ndarray:
        """What completing each row costs at least (``lowest``) or about (the beam's ranking; ``cids``: the
        rows' configuration ids)."""

    @abstractmethod
    def end_wear(self, state) -> np.ndarray:
        """(n, p) the worker's V when the repetition of each (complete) sequence ends."""

    def terminal(self, state) -> np.ndarray:
        """What a complete sequence adds for the wear it leaves
        (:func:`~ergosim.planner.wear_chain.next_cost`)."""
        return self.next_cost(self.end_wear(state))

    def next_cost(self, v: np.ndarray, gamma: bool = True) -> np.ndarray:
        """:func:`~ergosim.planner.wear_chain.next_cost` of wear ``v`` (n, p) with the matrix product of
        :meth:`order_free` (without the Γ terms if ``gamma`` is False: a lower value)."""
        if self.model.next_weight == 0:
            return np.zeros(len(v))
        prices = self.order_free(v, gamma)
        return self.model.next_weight * np.minimum(prices, self.next_cap[None]).sum(axis=1)

    def dominance(self, state) -> np.ndarray | None:
        """(n, m) keys such that a row no greater in every key and in cost can do no worse from the same
        configuration; None when no such order holds (no pruning by dominance)."""
        return None


class SequentialPricing(Pricing):
    """One agent at a time. State: (cost, V (n, p), time since the repetition's start (n,))."""

    def derive(self) -> None:
        super().derive()
        self.rest_factor = np.exp(-self.k * self.rest_s)
        """(A, N) what a step's rest multiplies V by (eq. 5)."""

    def start(self, v0, elapsed: float):
        return np.zeros(1), np.asarray(v0, dtype=float)[None, :], np.array([float(elapsed)])

    def step(self, state, op, action, agent):
        g, v, t = state
        human = agent == self.human
        v_hat = 1.0 - self.alpha[action] * (1.0 - v)
        rested = v * self.rest_factor[action, agent][:, None]
        v_new = np.where(human[:, None], v_hat, rested)
        price = np.where(human, self.model.price(v_hat), self.cost[action, agent])
        t_new = t + self.duration[action, agent]
        return (g + price + self.time_terms(t, t_new), v_new, t_new), price, t

    def estimate(self, state, need, *, lowest: bool, cids=None):
        """``lowest``: the admissible bound of :meth:`Pricing.chain_bound` (the worker rests only while
        robots act, at most their longest rests) or the order-free bound priced at the lowest wear
        reachable, whichever is higher. Else the beam's guess (:mod:`ergosim.planner.pilot`) for rows in
        configurations ``cids``."""
        if not self.view.action_once:
            return np.zeros(len(need))
        _, v, t = state
        if not lowest:
            return pilot_table(self).estimate(self, cids, need, v, t)
        rests = np.sort(np.where(need, self.max_rest[None], 0.0), axis=1)[:, ::-1]
        longest = np.concatenate([np.zeros((len(v), 1)), np.cumsum(rests, axis=1)], axis=1)
        chain = self.chain_bound(need, v, longest)
        low = v * np.exp(-self.k * longest[:, -1])[:, None]
        flat = self.needed_cost(need, low) + self.next_cost(low)
        return np.maximum(chain, flat) + self.time_terms(t, t + (need * self.min_duration).sum(axis=1))

    def end_wear(self, state):
        return state[1]

    def dominance(self, state):
        _, v, t = state
        return np.column_stack([v, t])

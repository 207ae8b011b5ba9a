"""The look-ahead planner: the next (action, agent) is the first step of the cheapest *sequence*.

The paper's AO* (§3) minimises Σ hyper-arc costs over plan trees, with every cost fixed for the call. The
look-ahead prices a plan along its execution order (:mod:`ergosim.planner.wear_chain`: each worker action
from the wear the earlier steps leave, recovery while a robot acts, the takt), so it searches sequences of
ready hyper-arcs from the current configuration to the full assembly (:mod:`ergosim.planner.transitions`).

Two searches, one contract (:class:`LookaheadPlan`):

- **exact** (depth-first branch and bound) when the remaining plan has at most ``exact_sequences``
  sequences (its free-order groups are small) and the search completes within ``max_expansions``
  expansions. Two pruning rules, both exact: a partial
  sequence whose cost plus an admissible bound (below) reaches the best complete one is cut; and one that
  reaches a configuration already reached with no more cost, no more wear on any joint and no later time is
  cut (every later price is non-decreasing in V and in time: eq. 9 and eq. 5 are monotone in V, eq. 11 in
  V̂, the takt term in time).
- **beam** otherwise: a breadth-first search that keeps, after each step, the ``beam_width`` partial
  sequences with the least cost plus the cost of a concrete completion that sees the chain grow (robots
  first on the actions that wear most, then the worker least wear first:
  :meth:`~ergosim.planner.chain_pricing.SequentialPricing.pilot`), one per configuration. It returns the
  cheapest complete sequence it kept.

**How far the beam can be from the optimum.** Every sequence costs at least ``lower_bound``: the order-free
plan (each needed action at its cheapest agent) priced at the lowest wear the worker can still reach,
V·e^{−(r/C)·T}, T the longest rest the remaining robot actions allow (eq. 5), plus the least takt and time
terms. The plan returned costs ``cost``; the optimum lies in [lower_bound, cost], so the beam is at most
``cost − lower_bound`` (:attr:`LookaheadPlan.gap`) from it. Each decision reports both. A priori the gap is
at most Σ over the needed actions of (price at the highest wear the plan can reach − price at the lowest),
since every sequence is priced between those two order-free sums. Measured against the exact search on
random graphs (``tests/test_planner_lookahead.py``, docs/allocation_modes.md) the beam is usually exact.

Tie-breaking: among sequences of equal cost (within :func:`~ergosim.planner.bottom_up.tolerance`) the one
found first in (cost, action name, agent name) order of the children wins, costs compared to
``REL_TOL`` (two robot actions in a row cost the same in either order, up to rounding): results depend
neither on hash order nor on the order of the task file.
Only action-once tasks (:class:`~ergosim.planner.transitions.Transitions`) get the bound and the beam's
estimate; on other graphs both are 0, so the exact search is plain enumeration and the beam ranks by cost
so far.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner.bottom_up import REL_TOL, tolerance
from ergosim.planner.chain_pricing import Pricing, SequentialPricing
from ergosim.planner.plan import PlanStep
from ergosim.planner.wear_chain import WearModel

__all__ = ["SearchLimits", "LookaheadPlan", "lookahead_plan", "search_sequences", "SequenceSearch"]


@dataclass(frozen=True)
class SearchLimits:
    """When the look-ahead searches exactly: the remaining plan has at most ``exact_sequences`` sequences
    (orders × agents; the corner joint has 96, the gearbox 768) and branch and bound finishes within
    ``max_expansions`` partial sequences; the beam's width otherwise. Assumed values: exact on every bundled
    task, within the 5 ms decision budget on ``sequential:21`` (``scripts/bench_planner.py --lookahead``)."""

    exact_sequences: int = 20_000
    max_expansions: int = 200_000
    beam_width: int = 6

    def __post_init__(self) -> None:
        for name in ("exact_sequences", "max_expansions", "beam_width"):
            value = getattr(self, name)
            low = 0 if name == "exact_sequences" else 1
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                raise ConfigError(f"{name} must be a whole number >= {low}, got {value!r}",
                                  where=f"SearchLimits.{name}")


@dataclass(frozen=True)
class LookaheadPlan:
    """The cheapest sequence found: ``steps`` in execution order (each :class:`PlanStep` with its chained
    price), ``cost`` (wear_chain's total), ``lower_bound`` on every sequence's cost, ``exact`` (the optimum,
    proven), ``expanded`` partial sequences priced."""

    steps: tuple[PlanStep, ...]
    cost: float
    lower_bound: float
    exact: bool
    expanded: int
    starts: tuple[float, ...] = ()
    """Each step's predicted start [s from the repetition's start]."""

    @property
    def next(self) -> PlanStep | None:
        return self.steps[0] if self.steps else None

    @property
    def gap(self) -> float:
        """How much the optimum can be below ``cost`` (0 when ``exact``)."""
        return 0.0 if self.exact else max(0.0, self.cost - self.lower_bound)


def _take(state, idx):
    return tuple(a[idx] for a in state)


class SequenceSearch:
    """The two searches over sequences of ready hyper-arcs, priced by a
    :class:`~ergosim.planner.chain_pricing.Pricing`. ``expanded`` counts the partial sequences priced."""

    def __init__(self, pricing: Pricing) -> None:
        self.pricing = pricing
        self.view = pricing.view
        self.expanded = 0

    def order(self, cost: np.ndarray, tie: np.ndarray) -> np.ndarray:
        """Indices of the children by cost (equal within ``REL_TOL``), then by ``tie``: their action,
        operation and agent names (:attr:`~ergosim.planner.transitions.Successors.tie`)."""
        scale = float(np.abs(cost).max(initial=1.0))
        if not math.isfinite(scale):
            scale = float(np.abs(cost[np.isfinite(cost)]).max(initial=1.0))
        level = np.round(cost / (REL_TOL * scale))  # ±inf stays ±inf
        return np.lexsort((tie, level))

    # ----------------------------------------------------------------------------------------- beam
    def beam(self, cid0: int, state0, width: int):
        """The cheapest complete sequence the beam keeps: (cost, [(op, agent, price, start)]) or None."""
        pricing = self.pricing
        cids = [cid0]
        state = state0
        levels: list[list] = []  # per step: [parent, op, agent, price, start, kept children]
        best = None
        while cids:
            parent, table, need = pricing.expand(cids)
            if not len(parent):
                break
            op, act, agent, nxt, done, tie = table
            self.expanded += len(op)
            child, price, start = pricing.step(_take(state, parent), op, act, agent)
            levels.append([parent, op, agent, price, start, None])
            live: slice | np.ndarray = slice(None)  # every child, while none completes the assembly
            if done.any():
                idx = np.flatnonzero(done)
                total = child[0][idx] + pricing.terminal(_take(child, idx))
                k = int(self.order(total, tie[idx])[0])
                if best is None or total[k] < best[0] - tolerance(best[0]):
                    best = (float(total[k]), len(levels) - 1, int(idx[k]))
                live = np.flatnonzero(done == 0)
                if not len(live):
                    break
            ahead = _take(child, live)
            f = ahead[0] + pricing.estimate(ahead, need[live], lowest=False, cids=nxt[live])
            ranked = self.order(f, tie[live])
            keep = _first_per_key(ranked, nxt[live], width)  # one partial sequence per configuration
            if isinstance(live, np.ndarray):
                keep = live[keep]
            levels[-1][5] = keep
            cids, state = nxt[keep].tolist(), _take(child, keep)
        if best is None:
            return None
        _, level, i = best
        steps = []
        while True:
            parent, op, agent, price, start, _ = levels[level]
            steps.append((int(op[i]), int(agent[i]), float(price[i]), float(start[i])))
            if level == 0:
                break
            level -= 1
            i = int(levels[level][5][parent[i]])
        return best[0], steps[::-1]

    # ---------------------------------------------------------------------------------------- exact
    def exact(self, cid0: int, state0, incumbent, budget: int):
        """Branch and bound from ``incumbent`` (cost, steps) or None; returns (best, finished)."""
        self._best = incumbent
        self._budget = self.expanded + budget
        self._seen: dict[int, list[tuple[float, np.ndarray]]] = {}
        self._path: list[tuple[int, int, float, float]] = []
        try:
            self._dfs(cid0, state0)
        except _OutOfBudget:
            return self._best, False
        return self._best, True

    def _dominated(self, cid: int, g: float, key: np.ndarray) -> bool:
        seen = self._seen.setdefault(cid, [])
        tol = tolerance(g)
        for g0, k0 in seen:
            if g0 <= g + tol and bool(np.all(k0 <= key + 1e-12)):
                return True
        seen.append((g, key))
        return False

    def _dfs(self, cid: int, state) -> None:
        g = float(state[0][0])
        if self.view.complete(cid):
            g += float(self.pricing.terminal(state)[0])
            if self._best is None or g < self._best[0] - tolerance(self._best[0]):
                self._best = (g, list(self._path))
            return
        key = self.pricing.dominance(state)
        if key is not None and self._dominated(cid, g, key[0]):
            return
        table, need = self.pricing.children(cid)
        op, act, agent, nxt, _, tie = table
        n = len(op)
        if not n:
            return
        self.expanded += n
        if self.expanded > self._budget:
            raise _OutOfBudget
        child, price, start = self.pricing.step(_take(state, np.zeros(n, dtype=np.int64)), op, act, agent)
        bound = child[0] + self.pricing.estimate(child, need, lowest=True)
        for i in self.order(bound, tie).tolist():
            if self._best is not None and bound[i] >= self._best[0] - tolerance(self._best[0]):
                continue
            self._path.append((int(op[i]), int(agent[i]), float(price[i]), float(start[i])))
            self._dfs(int(nxt[i]), _take(child, slice(i, i + 1)))
            self._path.pop()


class _OutOfBudget(Exception):
    pass


def _first_per_key(ranked: np.ndarray, key: np.ndarray, count: int) -> np.ndarray:
    """The first ``count`` indices of ``ranked`` whose ``key`` is not that of an earlier one, in that order
    (a Python loop: the beam stops after a few of its ~100 children)."""
    seen: set[int] = set()
    out = []
    for i, k in zip(ranked.tolist(), key[ranked].tolist(), strict=True):
        if k not in seen:
            seen.add(k)
            out.append(i)
            if len(out) == count:
                break
    return np.array(out, dtype=np.int64)


def search_sequences(pricing: Pricing, cid0: int, state0, limits: SearchLimits) -> LookaheadPlan:
    """The cheapest sequence from configuration ``cid0`` (a :class:`~ergosim.planner.transitions.Transitions`
    id) and the pricing's start ``state0``: exact or beam as ``limits`` say (module docstring)."""
    view = pricing.view
    if view.complete(cid0):
        left = float(pricing.terminal(state0)[0])
        return LookaheadPlan((), left, left, True, 0)
    search = SequenceSearch(pricing)
    found = search.beam(cid0, state0, limits.beam_width)
    exact = False
    if found is None or view.sequences(cid0, limits.exact_sequences) <= limits.exact_sequences:
        # small free groups are searched exactly; a beam that dead-ends (OR branches) searches on
        found, exact = search.exact(cid0, state0, found, limits.max_expansions)
    if found is None:
        raise InfeasiblePlanError("no feasible plan: no sequence of allowed hyper-arcs completes the "
                                  "assembly", where=pricing.graph.source)
    cost, steps = found
    bound = cost if exact else min(cost, float(pricing.estimate(state0, view.needed(cid0)[None],
                                                                lowest=True)[0]))
    ops, agents = pricing.graph.operations, pricing.graph.agents
    plan = tuple(PlanStep(ops[k].name, ops[k].action, agents[j].name, price) for k, j, price, _ in steps)
    return LookaheadPlan(plan, float(cost), float(bound), exact, search.expanded,
                         tuple(start for *_, start in steps))


def lookahead_plan(graph, model: WearModel, v, *, done: Iterable[str] = (),
                   pruned: Iterable[tuple[str, str]] = (), elapsed: float = 0.0,
                   limits: SearchLimits = SearchLimits()) -> LookaheadPlan:
    """The cheapest sequence from the configuration after ``done`` to the full assembly, one agent at a time,
    priced by ``model`` from wear ``v`` (p,) at ``elapsed`` seconds into the repetition (module docstring).

    Raises:
        InfeasiblePlanError: no sequence completes the assembly with the pairs left after ``pruned``.
        ConfigError: bad ``done``/``pruned``, or a model without the task's actions or agents.
    """
    pricing = SequentialPricing(graph, model, pruned)
    cid0 = pricing.view.start(done)
    return search_sequences(pricing, cid0, pricing.start(v, elapsed), limits)

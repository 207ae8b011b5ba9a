"""The AND/OR graph of an assembly task with per-agent hyper-arcs (paper §2), and its planners' entry point.

Nodes are sub-assemblies (sets of parts); an operation joins two or more disjoint children into their
union, the father; each operation is duplicated once per agent allowed to do it, and each copy is a
hyper-arc with cost c_{h,w}. The root is the full assembly (configuration Θ_f); the leaves are the
parts (Θ_i). The graph holds exactly the nodes reachable from the root through the operations.

A graph is compiled once (:class:`~ergosim.planner.compiled.CompiledGraph`, frozen) and checked to have a
plan; :meth:`AndOrGraph.plan` then re-plans from any current configuration with any costs, which is the
call the twin makes after every completed action.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from ergosim.errors import ConfigError, InfeasiblePlanError
from ergosim.planner import bottom_up, call_inputs, diagnose, paper_search
from ergosim.planner.compiled import CompiledGraph
from ergosim.planner.plan import Plan, assemble_plan

__all__ = ["AndOrGraph", "PLANNERS"]

PLANNERS = ("fast", "paper")


class AndOrGraph(CompiledGraph):
    """An assembly task as an AND/OR graph: its compiled form
    (:class:`~ergosim.planner.compiled.CompiledGraph`, whose arguments it takes) with the planners on top.

    Raises:
        TaskFileError: a malformed operation.
        InfeasiblePlanError: the full assembly cannot be built from the parts (``"no feasible plan: ..."``).
    """

    def _check_compiled(self) -> None:
        """The full assembly can be built from the parts with the fixed costs."""
        config = np.array(self.leaves, dtype=np.int64)
        node_cost, _ = bottom_up.node_costs(self, config, self.layout.cost)
        if not np.isfinite(node_cost[self.root]):
            reason, op_name, part = diagnose.explain(self, config, self.layout.cost, node_cost)
            raise InfeasiblePlanError(f"no feasible plan: {reason}", where=self.where(op_name, part))

    def configuration(self, done: Iterable[str] = ()) -> tuple[tuple[str, ...], ...]:
        """The current configuration Θ after the operations ``done``: its sub-assemblies as part tuples."""
        return tuple(self.node_parts(n) for n in call_inputs.configuration(self, done))

    def plan(
        self,
        done: Iterable[str] = (),
        costs: Mapping[tuple[str, str], float] | None = None,
        pruned: Iterable[tuple[str, str]] = (),
        planner: str = "fast",
        *,
        added: Mapping[tuple[str, str], float] | None = None,
        time_budget: float | None = None,
        max_states: int | None = None,
    ) -> Plan:
        """Optimal plan from the configuration reached by ``done`` to the full assembly.

        Args:
            done: names of the operations already carried out (any order).
            costs: (action label, agent name) -> cost for this call, overriding the fixed cost of every
                hyper-arc of that action and agent.
            pruned: (action label, agent name) pairs whose hyper-arcs are removed for this call.
            added: (action label, agent name) -> a cost added to every hyper-arc of that action and agent
                after ``costs`` (e.g. ``w_time`` × expected duration).
            planner: ``"fast"`` (bottom-up dynamic programming on the graph) or ``"paper"`` (Algorithm 1,
                search over configurations). Both return an optimal plan.
            time_budget: seconds the ``paper`` search may take before raising
                :class:`~ergosim.planner.paper_search.SearchBudgetExceeded` (default: unlimited).
            max_states: configurations the ``paper`` search may create before raising
                :class:`~ergosim.planner.paper_search.SearchMemoryExceeded`, a ConfigError (default
                :data:`~ergosim.planner.limits.MAX_PAPER_STATES`).

        Raises:
            InfeasiblePlanError: ``"no feasible plan: <reason>"``.
            ConfigError: unknown operation/action/agent, inconsistent ``done``, bad cost.
        """
        if planner not in PLANNERS:
            raise ConfigError(f"unknown planner {planner!r}; expected one of {PLANNERS}", where="planner")
        config = call_inputs.configuration(self, done)
        cost = call_inputs.hyperarc_costs(self, costs, pruned, added)
        if planner == "fast":
            hyperarcs = bottom_up.solve(self, config, cost)
        else:
            hyperarcs = paper_search.solve(self, config, cost, time_budget=time_budget, max_states=max_states)
        return assemble_plan(self, hyperarcs, config, cost)

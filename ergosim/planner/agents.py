"""Agents and assembly operations: the two user-facing records an AND/OR graph is built from (paper §2.2)."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from ergosim.errors import shown

__all__ = ["Agent", "Operation", "AGENT_KINDS", "COST_MAX", "check_name", "check_cost"]

AGENT_KINDS = ("human", "robot")

COST_MAX = 1e100
"""Largest hyper-arc cost. A plan's cost is a sum of hyper-arc costs, so costs near the float limit
(1.8e308) would overflow to inf and make a feasible task look infeasible; 1e100 leaves room for any
number of operations while being far above any risk-based cost (eq. 10-11 give at most p·(1 + Γ))."""

# Part and agent names are plain identifiers, so that generated operation names ("A-B+C", "p1..p5+p6")
# can use '-', '+' and '..' as separators without ambiguity.
_IDENTIFIER = re.compile(r"[A-Za-z0-9_]+\Z")


def check_name(value: object, what: str) -> str | None:
    """Return a problem description if ``value`` is not a valid part/agent name, else None."""
    if not isinstance(value, str) or not _IDENTIFIER.match(value):
        return f"{what} must be a non-empty name of letters, digits and '_', got {value!r}"
    return None


def check_cost(value: object, what: str) -> str | None:
    """Return a problem description if ``value`` is not a finite, non-negative number, else None."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"{what} must be a number, got {shown(value)}"
    if isinstance(value, int) and value > COST_MAX:  # before isfinite: 10**400 is no float
        return (f"{what} must be <= {COST_MAX:g} (a plan sums its costs, which must stay finite), got "
                f"{shown(value)}")
    if not math.isfinite(value) or value < 0:
        return f"{what} must be finite and >= 0, got {value!r}"
    if value > COST_MAX:
        return f"{what} must be <= {COST_MAX:g} (a plan sums its costs, which must stay finite), got {value}"
    return None


@dataclass(frozen=True)
class Agent:
    """A worker w_j of the team W: a human or a robot.

    ``cost`` is the default cost c_{h,w} of this agent's hyper-arcs when neither the operation nor the
    planner call gives one (dimensionless, the same scale as the ergonomic risk of eq. 2).
    """

    name: str
    kind: str
    cost: float = 1.0


@dataclass(frozen=True)
class Operation:
    """An assembly operation: ``children`` (two or more disjoint sub-assemblies) are joined into ``father``.

    ``father`` and each child are tuples of part names in the task's part order. ``agents`` may do the
    operation, each with the fixed cost at the same position of ``costs``; every (operation, agent) pair
    is one hyper-arc of the AND/OR graph. An agent absent from ``agents`` has no hyper-arc for this
    operation: that is the paper's pruning. Operations sharing an ``action`` label are the same
    physical action and receive the same per-call cost override.
    """

    name: str
    action: str
    father: tuple[str, ...]
    children: tuple[tuple[str, ...], ...]
    agents: tuple[str, ...]
    costs: tuple[float, ...]

    def cost_of(self, agent: str) -> float:
        """Fixed cost of this operation for ``agent``; KeyError if the agent may not do it."""
        try:
            return self.costs[self.agents.index(agent)]
        except ValueError:
            raise KeyError(agent) from None

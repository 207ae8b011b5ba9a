"""Built-in task generators of the paper's complexity study (§6).

- ``sequential:N``: N parts in a chain, liaison i joining p_i and p_{i+1} (the pen): every interval of
  the chain is a node, N(N+1)/2 of them, and every cut of an interval an operation, C(N+1, 3) of them.
- ``scarce:N``: N parts that connect only to the growing sub-assembly (the table top and its legs):
  liaisons p1–p_i, made in the fixed order p1+p2, then +p3, and so on (precedence constraints), so
  there are 2N - 1 nodes and N - 1 operations.

``sequential`` goes through the liaison generator, so its node and hyper-arc counts come out of the
generation. ``scarce`` is built directly: its operations are known (sub-assembly p1..p_k splits into
p1..p_{k-1} and p_k), and the liaison generator, which enumerates every connected split of every
sub-assembly before precedence prunes them, takes O(N⁴) on this star of liaisons (300 parts: minutes).
A test checks the two agree operation for operation.
Agent 0 is the human ``human``; the others are the robots ``robot1``, ``robot2``, ... Each hyper-arc
cost is drawn from U[0, 1) by the generator passed in, operation by operation, agent by agent.
"""

from __future__ import annotations

import numpy as np

from ergosim.errors import ConfigError
from ergosim.planner.agents import Agent, Operation
from ergosim.planner.graph import AndOrGraph
from ergosim.planner.liaisons import Liaison, child_label, generate_operations
from ergosim.planner.limits import (
    check_agent_count,
    check_operation_count,
    check_part_count,
    generated_operations,
)

__all__ = ["generate_task", "parse_spec", "SHAPES"]

SHAPES = ("sequential", "scarce")


def parse_spec(spec: str) -> tuple[str, int]:
    """``"sequential:20"`` -> ("sequential", 20); ConfigError for anything else."""
    shape, _, count = spec.partition(":")
    if shape not in SHAPES or not count.isdigit() or int(count) < 2 or len(count) > 12:
        raise ConfigError(
            f"expected sequential:N or scarce:N with N >= 2 parts, got {spec!r}", where="--generate"
        )
    check_operation_count(generated_operations(shape, int(count)), f"--generate {spec}")
    check_part_count(int(count), f"--generate {spec}")
    return shape, int(count)


def team(agents: int, operations: int = 1) -> list[Agent]:
    """Agent 0 human, the others robots, all with default cost 1 (``operations``: of the task they do, for
    the hyper-arc limit)."""
    if isinstance(agents, bool) or not isinstance(agents, (int, np.integer)) or agents < 1:
        raise ConfigError(f"the number of agents must be an integer >= 1, got {agents!r}", where="--agents")
    check_agent_count(int(agents), operations, where="--agents")
    return [Agent("human", "human")] + [Agent(f"robot{k}", "robot") for k in range(1, int(agents))]


def generate_task(
    spec: str, agents: int = 2, seed: int | None = 0, *, rng: np.random.Generator | None = None
) -> AndOrGraph:
    """Generate ``sequential:N`` or ``scarce:N`` for ``agents`` agents.

    Costs come from ``rng`` if given, else from ``np.random.default_rng(seed)``.
    """
    shape, n = parse_spec(spec)
    members = team(agents, generated_operations(shape, n))
    names = tuple(a.name for a in members)
    ones = (1.0,) * len(names)
    parts = [f"p{i}" for i in range(1, n + 1)]
    if shape == "sequential":
        liaisons = [Liaison(parts[i], parts[i + 1], f"l{i + 1}", names, ones) for i in range(n - 1)]
        generated = [op for op, _ in generate_operations(parts, liaisons, [], names, where=spec)]
    else:
        liaisons = [Liaison(parts[0], parts[i], f"l{i}", names, ones) for i in range(1, n)]
        generated = [_scarce_operation(parts, k, names) for k in range(2, n + 1)]
    rng = rng if rng is not None else np.random.default_rng(seed)
    draws = rng.random((len(generated), len(names)))
    ops = [
        Operation(op.name, op.action, op.father, op.children, names, tuple(row))
        for op, row in zip(generated, draws.tolist(), strict=True)
    ]
    return AndOrGraph(spec, parts, members, ops, actions=[lia.action for lia in liaisons], source=spec)


def _scarce_operation(parts: list[str], k: int, names: tuple[str, ...]) -> Operation:
    """The one operation of ``scarce`` whose father is p1..p_k: liaison l_{k-1} joins p_k to p1..p_{k-1}
    (the operation the liaison generator makes of it, with unit costs)."""
    father, rest = tuple(parts[:k]), (1 << (k - 1)) - 1
    return Operation(f"{child_label(parts, rest)}+{parts[k - 1]}", f"l{k - 1}", father,
                     (father[:-1], (parts[k - 1],)), names, (1.0,) * len(names))

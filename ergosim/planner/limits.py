"""Size limits of the planners, so a task too large for the machine is refused with one line, not by
running out of memory or time. Each limit names the knob a user can turn.

- :data:`MAX_OPERATIONS`: operations of one task, explicit or generated from liaisons (and ``--generate``).
  The ``fast`` planner is linear in them; 200 000 operations take some 100 MB and seconds to build.
- :data:`MAX_PAPER_STATES`: configurations the ``paper`` planner (Algorithm 1) may create in one search
  (``--max-states``). It enumerates configurations, whose number grows exponentially with the parts;
  each costs a few hundred bytes (its bit set, score, father pointer, heap entry), so the default
  1 000 000 keeps one search under about 1 GB. The ``fast`` planner has no such limit. A budget larger
  than this machine's memory can hold is refused (:func:`check_paper_states`).
- :data:`MAX_PARTS`: parts of one task. A sub-assembly is a bit mask over the parts, and every mask
  operation costs up to parts/64 machine words; 4096 parts keep that under 64 words, so reading a task
  file is linear in its size (``scripts/bench_taskfile.py``). An assembly of a workcell has tens of parts.
- :data:`MAX_AGENTS`: agents of one task (``--agents``). A workcell has a handful; every operation has a
  hyper-arc per agent, and both planners are linear in hyper-arcs, at most :data:`MAX_HYPER_ARCS`.
"""

from __future__ import annotations

from math import comb

from ergosim.errors import ConfigError
from ergosim.machine import physical_memory

__all__ = ["MAX_OPERATIONS", "MAX_PARTS", "MAX_PAPER_STATES", "MAX_AGENTS", "MAX_HYPER_ARCS",
           "PAPER_STATE_BYTES", "generated_operations", "check_operation_count", "check_part_count",
           "check_agent_count", "check_paper_states"]

MAX_OPERATIONS = 200_000
MAX_PARTS = 4_096
MAX_PAPER_STATES = 1_000_000
MAX_AGENTS = 1_000
MAX_HYPER_ARCS = 2_000_000
PAPER_STATE_BYTES = 1_000
"""Memory of one configuration of the paper planner [bytes] (module docstring: 1 000 000 in about 1 GB)."""


def generated_operations(shape: str, n: int) -> int:
    """Operations of the generated task ``shape:n`` (module docstring of ergosim.planner.generators)."""
    return comb(n + 1, 3) if shape == "sequential" else n - 1


def check_operation_count(count: int, where: str, error=ConfigError) -> None:
    """Raise ``error`` if ``count`` operations exceed :data:`MAX_OPERATIONS`."""
    if count > MAX_OPERATIONS:
        raise error(f"{count} operations, more than the limit of {MAX_OPERATIONS} "
                    "(ergosim.planner.limits.MAX_OPERATIONS)", where=where)


def check_part_count(count: int, where: str, error=ConfigError) -> None:
    """Raise ``error`` if ``count`` parts exceed :data:`MAX_PARTS`."""
    if count > MAX_PARTS:
        raise error(f"{count} parts, more than the limit of {MAX_PARTS} (ergosim.planner.limits.MAX_PARTS)",
                    where=where)


def check_agent_count(agents: int, operations: int, where: str, error=ConfigError) -> None:
    """Raise ``error`` if ``agents`` exceed :data:`MAX_AGENTS`, or their hyper-arcs over ``operations``
    exceed :data:`MAX_HYPER_ARCS`."""
    if agents > MAX_AGENTS:
        raise error(f"{agents} agents, more than the limit of {MAX_AGENTS} "
                    "(ergosim.planner.limits.MAX_AGENTS)", where=where)
    if agents * operations > MAX_HYPER_ARCS:
        raise error(f"{agents} agents × {operations} operations = {agents * operations} hyper-arcs, more "
                    f"than the limit of {MAX_HYPER_ARCS} (ergosim.planner.limits.MAX_HYPER_ARCS)",
                    where=where)


def check_paper_states(states: int, where: str) -> None:
    """Raise a ConfigError if a budget of ``states`` configurations cannot fit in this machine's memory
    (:data:`PAPER_STATE_BYTES` each): the search would run out of memory long after it started."""
    memory = physical_memory()
    most = memory // PAPER_STATE_BYTES
    if states > most:
        raise ConfigError(f"{states} configurations need about {states * PAPER_STATE_BYTES / 1e9:.3g} GB; "
                          f"this machine has {memory / 1e9:.3g} GB: at most {most}", where=where)

"""Size limits of the planners, so a task too large for the machine is refused with one line, not by
running out of memory or time. Each limit names the knob a user can turn.

- :data:`MAX_OPERATIONS`: operations of one task, explicit or generated from liaisons (and ``--generate``).
  The ``fast`` planner is linear in them; 200 000 operations take some 100 MB and seconds to build.
- :data:`MAX_PAPER_STATES`: configurations the ``paper`` planner (Algorithm 1) may create in one search
  (``--max-states``). It enumerates configurations, whose number grows exponentially with the parts;
  each costs a few hundred bytes (its bit set, score, father pointer, heap entry), so the default
  1 000 000 keeps one search under about 1 GB. The ``fast`` planner has no such limit.
"""

from __future__ import annotations

from math import comb

from ergosim.errors import ConfigError

__all__ = ["MAX_OPERATIONS", "MAX_PAPER_STATES", "generated_operations", "check_operation_count"]

MAX_OPERATIONS = 200_000
MAX_PAPER_STATES = 1_000_000


def generated_operations(shape: str, n: int) -> int:
    """Operations of the generated task ``shape:n`` (module docstring of ergosim.planner.generators)."""
    return comb(n + 1, 3) if shape == "sequential" else n - 1


def check_operation_count(count: int, where: str, error=ConfigError) -> None:
    """Raise ``error`` if ``count`` operations exceed :data:`MAX_OPERATIONS`."""
    if count > MAX_OPERATIONS:
        raise error(f"{count} operations, more than the limit of {MAX_OPERATIONS} "
                    "(ergosim.planner.limits.MAX_OPERATIONS)", where=where)

"""The pace of a worker still learning a task: Wright's learning curve against MTM-1 standard times.

MTM-1 times (:mod:`ergosim.worker.mtm`) are those of an operator practised in the method. A worker new to a
task is slower and speeds up with every execution. Wright's learning curve (T. P. Wright, "Factors
affecting the cost of airplanes", J. Aeronautical Sciences 3(4), 1936) has the time of the n-th execution
fall by a constant *learning rate* per doubling of n: T(n) = T(1) n^b with b = log2(rate). Taking the
standard time as reached after ``standard_after`` executions, a worker at execution n works at the pace
T_std / T(n) = (n / standard_after)^(-b).

Defaults (assumed, docs/fidelity.md): a learning rate of 90 %, within the 85-95 % usually quoted for
manual assembly; standard performance after 1000 executions of a short-cycle task.
"""

from __future__ import annotations

import math

from ergosim.errors import ConfigError

__all__ = ["learning_curve_pace", "LEARNING_RATE", "STANDARD_AFTER"]

LEARNING_RATE = 0.90
STANDARD_AFTER = 1000


def learning_curve_pace(executions: float, learning_rate: float = LEARNING_RATE,
                        standard_after: float = STANDARD_AFTER) -> float:
    """Pace (1 = MTM-1 standard) of a worker at its ``executions``-th execution of a task."""
    if not 0.5 < learning_rate <= 1.0:
        raise ConfigError(f"learning_rate must be in (0.5, 1], got {learning_rate}", where="learning curve")
    if not 1 <= executions <= standard_after:
        raise ConfigError(f"executions must be in [1, {standard_after}], got {executions}",
                          where="learning curve")
    b = math.log2(learning_rate)
    return (executions / standard_after) ** (-b)

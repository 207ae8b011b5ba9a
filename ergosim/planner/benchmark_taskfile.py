"""Task-file reading benchmark: the reader must be linear in the number of operations.

A balanced binary assembly of ``n + 1`` parts has ``n`` explicit operations; its TOML text is generated,
then parsed and built into an :class:`~ergosim.planner.graph.AndOrGraph` ``repeats`` times. The median
time per size, and the ratio of consecutive sizes' times over the ratio of their sizes (1 for a linear
reader, 2 for a quadratic one at doubling sizes), are what ``scripts/bench_taskfile.py`` prints.
"""

from __future__ import annotations

import dataclasses
import statistics
import time

from ergosim.planner.taskfile import parse_task

__all__ = ["TaskfileRow", "balanced_task_text", "run_taskfile_benchmark"]


@dataclasses.dataclass(frozen=True)
class TaskfileRow:
    operations: int
    median_ms: float
    """Median wall time of parse + build [ms]."""
    growth: float | None
    """(time / previous time) / (size / previous size); None for the first row."""


def balanced_task_text(n: int) -> str:
    """The TOML text of a balanced binary assembly with ``n`` explicit operations (``n + 1`` parts)."""
    parts = [f"p{i}" for i in range(n + 1)]
    groups, ops = [[p] for p in parts], []
    while len(groups) > 1:
        ops += [(groups[i], groups[i + 1]) for i in range(0, len(groups) - 1, 2)]
        groups = [groups[i] + groups[i + 1] for i in range(0, len(groups) - 1, 2)] + (
            [groups[-1]] if len(groups) % 2 else [])
    lines = ["parts = [" + ",".join(f'"{p}"' for p in parts) + "]", "[agents.human]", 'kind = "human"']
    for k, (a, b) in enumerate(ops):
        left, right = (",".join(f'"{p}"' for p in side) for side in (a, b))
        lines += ["[[operations]]", f'name = "o{k}"', f"joins = [[{left}], [{right}]]"]
    return "\n".join(lines) + "\n"


def run_taskfile_benchmark(sizes: tuple[int, ...] = (1250, 2500, 5000, 10000),
                           repeats: int = 5) -> list[TaskfileRow]:
    rows: list[TaskfileRow] = []
    for n in sizes:
        text = balanced_task_text(n)
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            graph = parse_task(text)
            times.append(time.perf_counter() - t0)
        assert len(graph.operations) == n
        med = statistics.median(times) * 1e3
        growth = None
        if rows:
            prev = rows[-1]
            growth = (med / prev.median_ms) / (n / prev.operations)
        rows.append(TaskfileRow(n, med, growth))
    return rows

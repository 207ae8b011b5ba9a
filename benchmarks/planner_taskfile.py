"""Task-file reading benchmark: the reader must be linear in the file's size.

Two shapes of explicit-operation task files are generated, then parsed and built into an
:class:`~ergosim.planner.graph.AndOrGraph` ``repeats`` times each:

- ``chain``: the operations of ``sequential:N`` written out (every cut of every interval of a chain of N
  parts, C(N+1, 3) operations; N = 50, 64, 80 give the 62k, 131k and 265k lines of issue 27's report,
  which took 3.8, 13.5 and 57 s);
- ``balanced``: a balanced binary assembly of ``n + 1`` parts, ``n`` operations, up to the part limit
  (:data:`~ergosim.planner.limits.MAX_PARTS`).

A row gives the median wall time and the median CPU time of this process (which other work on a shared
machine does not inflate), and the growth: the ratio of consecutive rows' CPU times over the ratio of their
sizes in bytes (1 for a reader linear in the file's size, more for a superlinear one).
"""

from __future__ import annotations

import dataclasses
import statistics
import time

from ergosim.planner.taskfile import parse_task

__all__ = ["TaskfileRow", "balanced_task_text", "chain_task_text", "run_taskfile_benchmark"]

CHAINS = (40, 50, 64, 80)
BALANCED = (500, 1000, 2000, 4000)


@dataclasses.dataclass(frozen=True)
class TaskfileRow:
    shape: str
    operations: int
    lines: int
    megabytes: float
    median_ms: float
    """Median wall time of parse + build [ms]."""
    cpu_ms: float
    """Median CPU time of this process for parse + build [ms]."""
    growth: float | None
    """(CPU time / previous CPU time) / (bytes / previous bytes) within the shape; None for its first row."""


def balanced_task_text(n: int) -> str:
    """The TOML text of a balanced binary assembly with ``n`` explicit operations (``n + 1`` parts)."""
    parts = [f"p{i}" for i in range(n + 1)]
    groups, ops = [[p] for p in parts], []
    while len(groups) > 1:
        ops += [(groups[i], groups[i + 1]) for i in range(0, len(groups) - 1, 2)]
        groups = [groups[i] + groups[i + 1] for i in range(0, len(groups) - 1, 2)] + (
            [groups[-1]] if len(groups) % 2 else [])
    return _text(parts, [(f"o{k}", (a, b)) for k, (a, b) in enumerate(ops)])


def chain_task_text(n: int) -> str:
    """The TOML text of ``sequential:n``'s operations written out as explicit operations."""
    from ergosim.planner.generators import generate_task  # noqa: PLC0415

    graph = generate_task(f"sequential:{n}", agents=2)
    return _text(list(graph.parts), [(op.name, op.children) for op in graph.operations])


def _text(parts, ops) -> str:
    lines = ["parts = [" + ",".join(f'"{p}"' for p in parts) + "]", "[agents.human]", 'kind = "human"']
    for name, children in ops:
        joins = ", ".join("[" + ",".join(f'"{p}"' for p in child) + "]" for child in children)
        lines += ["[[operations]]", f'name = "{name}"', f"joins = [{joins}]"]
    return "\n".join(lines) + "\n"


def run_taskfile_benchmark(chains: tuple[int, ...] = CHAINS, balanced: tuple[int, ...] = BALANCED,
                           repeats: int = 3) -> list[TaskfileRow]:
    rows: list[TaskfileRow] = []
    shapes = (("chain", chains, chain_task_text), ("balanced", balanced, balanced_task_text))
    for shape, sizes, make in shapes:
        first = True
        for n in sizes:
            text = make(n)
            wall, cpu = [], []
            for _ in range(repeats):
                t0, c0 = time.perf_counter(), time.process_time()
                graph = parse_task(text)
                wall.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
            med, med_cpu = statistics.median(wall) * 1e3, statistics.median(cpu) * 1e3
            size = len(text.encode()) / 1e6
            growth = None
            if not first:
                prev = rows[-1]
                growth = (med_cpu / prev.cpu_ms) / (size / prev.megabytes)
            rows.append(TaskfileRow(shape, len(graph.operations), text.count("\n"), size, med, med_cpu,
                                    growth))
            first = False
    return rows

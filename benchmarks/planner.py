"""The planners' computational-time study (paper §6), extended: fast vs paper side by side.

Each row builds a generated task once and times a *replan* on it, the call the twin makes after every
action: ``graph.plan(costs=...)`` with fresh human costs for every action. Times are medians of
repeats. The paper planner runs under a per-row time cap and its memory budget
(:data:`~ergosim.planner.limits.MAX_PAPER_STATES` configurations); a row past either records ``paper_ms =
None`` and says which in ``paper_note``, and larger piece counts of the same shape and team are then
skipped (its time and configurations only grow).
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass

import numpy as np

from ergosim.planner import paper_search
from ergosim.planner.generators import generate_task
from ergosim.planner.graph import AndOrGraph

__all__ = [
    "BenchRow",
    "PAPER_NOTES",
    "bench_cases",
    "time_replans",
    "run_benchmark",
    "format_table",
    "check_targets",
    "rows_json",
]

DEFAULT_CAP_S = 60.0

OVER_CAP, OVER_BUDGET, SKIPPED, NOT_RUN = "over time cap", "over budget", "skipped", "not run"
PAPER_NOTES = (OVER_CAP, OVER_BUDGET, SKIPPED, NOT_RUN)
"""Why a row has no paper time: past the time cap, past the memory budget, skipped because a smaller
size of the same shape and team was past one of them, or a fast-only row."""


@dataclass(frozen=True)
class BenchRow:
    """One measured task; times are the median replan time in milliseconds.

    ``paper_ms`` is None when the paper planner has no time, and ``paper_note`` (one of
    :data:`PAPER_NOTES`) then says why; it is ``""`` when ``paper_ms`` is measured.
    """

    shape: str
    pieces: int
    agents: int
    nodes: int
    hyperarcs: int
    fast_ms: float
    paper_ms: float | None
    paper_note: str = ""


def bench_cases(quick: bool = False) -> list[tuple[str, int, int, bool]]:
    """(shape, pieces, agents, time the paper planner too) in run order, without duplicates."""
    max_pieces, team_sizes, large = (12, (2, 10, 30), (30,)) if quick else (20, range(2, 31), (30, 40, 60))
    cases = [(s, n, 2, True) for s in ("sequential", "scarce") for n in range(2, max_pieces + 1)]
    cases += [(s, 10, k, True) for s in ("sequential", "scarce") for k in team_sizes]
    cases += [("sequential", n, k, False) for n in large for k in (2, 30)]
    return list(dict.fromkeys(cases))


def _costs(graph: AndOrGraph, rng: np.random.Generator) -> dict[tuple[str, str], float]:
    human = graph.agents[0].name
    return {(a, human): float(c) for a, c in zip(graph.actions, rng.random(len(graph.actions)), strict=True)}


def time_replans(
    graph: AndOrGraph,
    planner: str,
    rng: np.random.Generator,
    *,
    min_repeats: int = 5,
    min_total_s: float = 0.2,
    max_repeats: int = 200,
    cap_s: float | None = None,
    max_states: int | None = None,
) -> float | None:
    """Median wall time [ms] of ``graph.plan(costs=..., planner=planner)``; None if a call passes ``cap_s``.

    Repeats until both ``min_repeats`` and ``min_total_s`` are reached (at most ``max_repeats``); a call
    slower than 1 s is not repeated more than twice. A paper search past its memory budget raises
    :class:`~ergosim.planner.paper_search.SearchMemoryExceeded`.
    """
    times: list[float] = []
    while len(times) < max_repeats:
        costs = _costs(graph, rng)
        t0 = time.perf_counter()
        try:
            graph.plan(costs=costs, planner=planner, time_budget=cap_s, max_states=max_states)
        except paper_search.SearchBudgetExceeded:
            return None
        times.append(time.perf_counter() - t0)
        slow = times[-1] > 1.0
        if (slow and len(times) >= 2) or (times[-1] > 0.25 * (cap_s or np.inf)):
            break
        if len(times) >= min_repeats and sum(times) >= min_total_s:
            break
    return 1e3 * statistics.median(times)


def run_benchmark(
    quick: bool = False,
    cap_s: float = DEFAULT_CAP_S,
    seed: int = 0,
    progress: Callable[[BenchRow], None] | None = None,
    *,
    cases: list[tuple[str, int, int, bool]] | None = None,
    max_states: int | None = None,
) -> list[BenchRow]:
    """Measure every case of ``cases`` (default :func:`bench_cases`); ``progress(row)`` is called as each
    row completes. ``max_states`` is the paper planner's memory budget (default
    :data:`~ergosim.planner.limits.MAX_PAPER_STATES`)."""
    rng = np.random.default_rng(seed)
    rows = []
    capped: set[tuple[str, int]] = set()
    for shape, pieces, agents, with_paper in bench_cases(quick) if cases is None else cases:
        graph = generate_task(f"{shape}:{pieces}", agents=agents, rng=rng)
        fast_ms = time_replans(graph, "fast", rng)
        paper_ms, note = None, NOT_RUN
        if with_paper and (shape, agents) in capped:
            note = SKIPPED
        elif with_paper:
            paper_ms, note = _time_paper(graph, rng, cap_s, max_states)
            if paper_ms is None:
                capped.add((shape, agents))
        row = BenchRow(shape, pieces, agents, graph.n_nodes, graph.n_hyperarcs, fast_ms, paper_ms, note)
        rows.append(row)
        if progress is not None:
            progress(row)
    return rows


def _time_paper(
    graph: AndOrGraph, rng: np.random.Generator, cap_s: float, max_states: int | None
) -> tuple[float | None, str]:
    """(median paper replan [ms] or None, its note): past the cap or the memory budget is a result."""
    _ = graph.node_edges  # the per-graph edge lists are build-time work, not replan work
    try:
        paper_ms = time_replans(
            graph, "paper", rng, min_repeats=3, min_total_s=1.0, cap_s=cap_s, max_states=max_states
        )
    except paper_search.SearchMemoryExceeded:
        return None, OVER_BUDGET
    return paper_ms, ("" if paper_ms is not None else OVER_CAP)


def _ms(value: float | None) -> str:
    return "-" if value is None else f"{value:.4g}"


TABLE_HEADER = ("shape", "pieces", "agents", "nodes", "hyperarcs", "fast_ms", "paper_ms", "paper/fast")


_WIDTHS = (11, 7, 7, 7, 10, 10, 15, 12)


def format_row(row: BenchRow) -> str:
    """One table line; a paper row without a time shows why (:data:`PAPER_NOTES`) in its place."""
    ratio = "-" if row.paper_ms is None else f"{row.paper_ms / row.fast_ms:.3g}"
    paper = row.paper_note if row.paper_note not in ("", NOT_RUN) else _ms(row.paper_ms)
    cells = (
        row.shape,
        row.pieces,
        row.agents,
        row.nodes,
        row.hyperarcs,
        _ms(row.fast_ms),
        paper,
        ratio,
    )
    return "".join(str(c).rjust(w) for c, w in zip(cells, _WIDTHS, strict=True))


def format_table(rows: list[BenchRow]) -> str:
    head = "".join(h.rjust(w) for h, w in zip(TABLE_HEADER, _WIDTHS, strict=True))
    return "\n".join([head] + [format_row(r) for r in rows])


def check_targets(rows: list[BenchRow]) -> list[tuple[str, bool | None, str]]:
    """The issue's three targets as (target, met or None if not measured, measured value)."""
    find = {(r.shape, r.pieces, r.agents): r for r in rows}
    out: list[tuple[str, bool | None, str]] = []
    r = find.get(("sequential", 20, 2))
    out.append(
        (
            "fast <= 2 ms on sequential:20, 2 agents",
            None if r is None else r.fast_ms <= 2.0,
            _ms(r and r.fast_ms),
        )
    )
    # "size" = pieces, as in the paper; a size both finish is one where no paper row stopped at its cap or
    # budget (scarce:20 alone is no such size when sequential:20 is over budget); ties go to the larger graph
    stopped = {r.pieces for r in rows if r.paper_ms is None and r.paper_note != NOT_RUN}
    both = [r for r in rows if r.paper_ms is not None and r.pieces not in stopped]
    if both:
        big = max(both, key=lambda r: (r.pieces, r.hyperarcs))
        ratio = big.paper_ms / big.fast_ms
        out.append(
            (
                f">= 1000x faster than paper at the largest size both finish ({big.shape}:{big.pieces}, "
                f"{big.agents} agents)",
                ratio >= 1000.0,
                f"{ratio:.0f}x",
            )
        )
    r = find.get(("sequential", 40, 30))
    out.append(
        (
            "fast < 1 s on sequential:40, 30 agents",
            None if r is None else r.fast_ms < 1000.0,
            _ms(r and r.fast_ms),
        )
    )
    return out


def rows_json(rows: list[BenchRow]) -> dict[str, list[dict[str, object]]]:
    """``{"rows": [{"shape", "pieces", "agents", "nodes", "hyperarcs", "fast_ms", "paper_ms",
    "paper_note"}]}``."""
    return {"rows": [asdict(r) for r in rows]}

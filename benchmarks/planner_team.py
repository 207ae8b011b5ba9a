"""Team-decision benchmark: one decision for a whole idle team (:func:`~ergosim.planner.team.team_assign`)
beside a plain replan on the same graph, with the same fresh costs.

A team decision at the start of an assembly is the heaviest: every agent is idle and every operation whose
children are parts is ready. Times are medians of repeats [ms]; the replan is timed in the same loop, so
the ratio holds whatever else the machine is doing.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import asdict, dataclass

import numpy as np

from benchmarks.planner import _costs
from ergosim.planner.generators import generate_task
from ergosim.planner.team import team_assign

__all__ = ["TeamBenchRow", "TEAM_CASES", "TEAM_TARGET_MS", "time_team_decision", "run_team_benchmark",
           "format_team_rows", "check_team_target", "team_rows_json"]

TEAM_CASES = (("sequential", 10, 2), ("sequential", 20, 10), ("sequential", 40, 30), ("scarce", 40, 30))
"""(shape, pieces, agents) timed; sequential:40 with 30 agents is the issue's target."""
TEAM_TARGET_MS = 10.0
"""One decision for 30 agents on sequential:40 takes at most this [ms] (issue 17)."""


@dataclass(frozen=True)
class TeamBenchRow:
    """Median times [ms] of a team decision and of a replan, and how many agents the decision started."""

    shape: str
    pieces: int
    agents: int
    hyperarcs: int
    team_ms: float
    replan_ms: float
    started: int


def time_team_decision(graph, rng: np.random.Generator, repeats: int = 25) -> tuple[float, float, int]:
    """(team decision [ms], replan [ms], agents started) medians over ``repeats`` fresh cost draws."""
    idle = [a.name for a in graph.agents]
    team_assign(graph, idle=idle)  # the per-graph layout is build-time work, not decision work
    team, plan, started = [], [], 0
    for _ in range(repeats):
        costs = _costs(graph, rng)
        t0 = time.perf_counter()
        out = team_assign(graph, idle=idle, costs=costs)
        t1 = time.perf_counter()
        graph.plan(costs=costs)
        t2 = time.perf_counter()
        team.append(t1 - t0)
        plan.append(t2 - t1)
        started = len(out.steps)
    return 1e3 * statistics.median(team), 1e3 * statistics.median(plan), started


def run_team_benchmark(seed: int = 0, quick: bool = False, progress=None) -> list[TeamBenchRow]:
    rng = np.random.default_rng(seed)
    rows = []
    for shape, pieces, agents in TEAM_CASES[:2] if quick else TEAM_CASES:
        graph = generate_task(f"{shape}:{pieces}", agents=agents, rng=rng)
        team_ms, replan_ms, started = time_team_decision(graph, rng, repeats=5 if quick else 25)
        row = TeamBenchRow(shape, pieces, agents, graph.n_hyperarcs, team_ms, replan_ms, started)
        rows.append(row)
        if progress is not None:
            progress(row)
    return rows


_HEADER = ("shape", "pieces", "agents", "hyperarcs", "team_ms", "replan_ms", "team/replan", "started")
_WIDTHS = (11, 7, 7, 10, 10, 10, 12, 9)


def format_team_rows(rows: list[TeamBenchRow]) -> str:
    lines = ["".join(h.rjust(w) for h, w in zip(_HEADER, _WIDTHS, strict=True))]
    for r in rows:
        cells = (r.shape, r.pieces, r.agents, r.hyperarcs, f"{r.team_ms:.4g}", f"{r.replan_ms:.4g}",
                 f"{r.team_ms / r.replan_ms:.3g}", r.started)
        lines.append("".join(str(c).rjust(w) for c, w in zip(cells, _WIDTHS, strict=True)))
    return "\n".join(lines)


def check_team_target(rows: list[TeamBenchRow]) -> tuple[str, bool | None, str]:
    """The issue's target as (target, met or None if not measured, measured value)."""
    r = next((r for r in rows if (r.shape, r.pieces, r.agents) == ("sequential", 40, 30)), None)
    return (f"team decision <= {TEAM_TARGET_MS:g} ms on sequential:40, 30 agents",
            None if r is None else r.team_ms <= TEAM_TARGET_MS, "-" if r is None else f"{r.team_ms:.4g}")


def team_rows_json(rows: list[TeamBenchRow]) -> list[dict]:
    return [asdict(r) for r in rows]

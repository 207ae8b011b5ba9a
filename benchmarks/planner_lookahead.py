"""Look-ahead benchmark (``scripts/bench_planner.py --lookahead``): decision time of the kwear-lookahead
planner, sequential and parallel, beside the paper's replan on the same graph, and the beam's distance from
the exact optimum.

Every decision is priced from fresh wear: α per (action, joint) drawn from U[0.85, 0.99] (wear per execution
of the order of the bundled cells', 0.05-0.4 summed over joints), the worker's durations from U[3, 8] s and
the robot's from U[10, 20] s (the Panda's measured spans in the bundled cells), c_r = 2.5, Γ = 100,
V_th = 0.8, a takt of 10 s per action with the default takt weight Γ/takt, and the next repetition priced
(``next_weight`` = 1). The start wear V is drawn from U[0, 0.4] per joint for each decision. Times are medians
of repeats [ms], the replan timed in the same loop. With a ``baseline`` (another git revision's planner,
:func:`~benchmarks.planner_revision.planner_at`) every decision is also taken by it, the two in
alternating order, and the row says whether every plan was the same.
"""

from __future__ import annotations

import math
import statistics
import time
import types
from dataclasses import asdict, dataclass

import numpy as np

from ergosim.ergonomics.cost import CostParams
from ergosim.ergonomics.kwear import KWearParams
from ergosim.planner.bundled import bundled_task
from ergosim.planner.generators import generate_task
from ergosim.planner.lookahead import SearchLimits, lookahead_plan
from ergosim.planner.lookahead_team import TeamState, lookahead_team
from ergosim.planner.wear_chain import WearModel

__all__ = ["LookaheadRow", "LOOKAHEAD_CASES", "LOOKAHEAD_TARGET_MS", "CURRENT", "random_model",
           "time_decisions", "run_lookahead_benchmark", "beam_quality", "format_lookahead_rows",
           "check_lookahead_target", "lookahead_rows_json"]

LOOKAHEAD_CASES = (("sequential:21", 2, "sequential"), ("sequential:21", 2, "parallel"),
                   ("sequential:6", 2, "sequential"), ("scarce:21", 2, "sequential"),
                   ("corner-joint:multi-subject", 2, "sequential"),
                   ("corner-joint:multi-subject", 2, "parallel"),
                   ("gearbox", 2, "sequential"), ("gearbox", 2, "parallel"))
"""(task, agents, execution) timed; ``sequential:21`` (20 actions) with 2 agents is the issue's target."""
LOOKAHEAD_TARGET_MS = 5.0
"""One sequential look-ahead decision on a 20-action sequential task with 2 agents takes at most this [ms]."""


@dataclass(frozen=True)
class LookaheadRow:
    """Median decision time [ms] (``cpu_ms``: process time, what the machine's other jobs do not add), the
    paper's replan on the same graph [ms], the search used and its mean reported gap, and the partial
    sequences priced per decision."""

    task: str
    agents: int
    execution: str
    actions: int
    hyperarcs: int
    lookahead_ms: float
    cpu_ms: float
    replan_ms: float
    exact: bool
    gap: float
    expanded: int
    base_ms: float = math.nan
    """The baseline's median decision time [ms] (wall), NaN without one; ``base_cpu_ms`` its process time."""
    base_cpu_ms: float = math.nan
    same: bool | None = None
    """Every decision's plan (steps, prices, cost, bound, expansions) equal to the baseline's, bit for bit."""


def _graph(task: str, agents: int, rng: np.random.Generator):
    if task.startswith(("sequential:", "scarce:")):
        return generate_task(task, agents=agents, rng=rng)
    return bundled_task(task)


def random_model(graph, rng: np.random.Generator) -> WearModel:
    """A wear model for ``graph`` drawn as the module docstring says."""
    names = [a.name for a in graph.agents]
    human = next(a.name for a in graph.agents if a.kind == "human")
    alphas = {a: rng.uniform(0.85, 0.99, 5) for a in graph.actions}
    durations = {(a, n): float(rng.uniform(3.0, 8.0) if n == human else rng.uniform(10.0, 20.0))
                 for a in graph.actions for n in names}
    takt = 10.0 * len(graph.actions)
    return WearModel.build(graph.actions, names, human, alphas=alphas, kwear=KWearParams(),
                           cost=CostParams(gamma=100.0, v_th=0.8, robot_cost=2.5), durations=durations,
                           takt=takt, takt_weight=100.0 / takt, next_weight=1.0)


CURRENT = types.SimpleNamespace(lookahead_plan=lookahead_plan, lookahead_team=lookahead_team)
"""This revision's planner (a baseline is another revision's:
:func:`~benchmarks.planner_revision.planner_at`)."""


def _decide(planner, graph, model, v, execution: str, limits: SearchLimits):
    if execution == "sequential":
        return planner.lookahead_plan(graph, model, v, limits=limits)
    names = [a.name for a in graph.agents]
    team = TeamState(0.0, v, 0.0, {n: 0.0 for n in names[1:]}, {}, {})
    return planner.lookahead_team(graph, model, team, idle=names, limits=limits).plan


def _record(plan) -> tuple:
    return (tuple(plan.steps), plan.starts, plan.cost, plan.lower_bound, plan.exact, plan.expanded)


def time_decisions(graph, rng: np.random.Generator, execution: str, repeats: int,
                   limits: SearchLimits = SearchLimits(), baseline=None) -> dict:
    """Medians over ``repeats`` fresh wear draws: ``wall`` and ``cpu`` [ms] per decision, ``replan`` [ms],
    and the last plan's ``exact``, the mean ``gap`` and ``expanded``; with a ``baseline`` planner also
    ``base_wall``, ``base_cpu`` and ``same`` (every plan equal)."""
    model = random_model(graph, rng)
    planners = {"": CURRENT} if baseline is None else {"": CURRENT, "base_": baseline}
    for planner in planners.values():  # the graph's configurations: build-time work
        _decide(planner, graph, model, np.zeros(5), execution, limits)
    times: dict[str, list[float]] = {f"{k}{x}": [] for k in planners for x in ("wall", "cpu")}
    replans, gaps = [], []
    same = True
    plan = None
    for i in range(repeats):
        v = rng.uniform(0.0, 0.4, 5)
        plans = {}
        for key in list(planners)[::1 if i % 2 else -1]:  # alternate: neither always runs first
            w0, c0 = time.perf_counter(), time.process_time()
            plans[key] = _decide(planners[key], graph, model, v, execution, limits)
            c1, w1 = time.process_time(), time.perf_counter()
            times[f"{key}wall"].append(w1 - w0)
            times[f"{key}cpu"].append(c1 - c0)
        plan = plans[""]
        same = same and all(_record(p) == _record(plan) for p in plans.values())
        w1 = time.perf_counter()
        graph.plan(costs={(a, graph.agents[0].name): float(x) for a, x in
                          zip(graph.actions, model.price(1.0 - model.alpha * (1.0 - v)), strict=True)})
        replans.append(time.perf_counter() - w1)
        gaps.append(plan.gap)
    out = {k: 1e3 * statistics.median(x) for k, x in times.items()}
    out.update(replan=1e3 * statistics.median(replans), exact=plan.exact, gap=float(np.mean(gaps)),
               expanded=plan.expanded, same=same if baseline is not None else None)
    return out


def run_lookahead_benchmark(seed: int = 0, quick: bool = False, progress=None, baseline=None,
                            repeats: int | None = None) -> list[LookaheadRow]:
    """The rows of :data:`LOOKAHEAD_CASES` (the first three if ``quick``), ``repeats`` decisions each
    (default 31, quick 5), beside a ``baseline`` planner if given (module docstring)."""
    rng = np.random.default_rng(seed)
    rows = []
    for task, agents, execution in LOOKAHEAD_CASES[:3] if quick else LOOKAHEAD_CASES:
        graph = _graph(task, agents, rng)
        t = time_decisions(graph, rng, execution, repeats or (5 if quick else 31), baseline=baseline)
        row = LookaheadRow(task, agents, execution, len(graph.actions), graph.n_hyperarcs, t["wall"],
                           t["cpu"], t["replan"], t["exact"], t["gap"], t["expanded"],
                           t.get("base_wall", math.nan), t.get("base_cpu", math.nan), t["same"])
        rows.append(row)
        if progress is not None:
            progress(row)
    return rows


def beam_quality(task: str = "sequential:7", draws: int = 40, seed: int = 0, widths=(1, 2, 4, 6)) -> dict:
    """The beam against the exact search on ``task`` (small enough to search exactly), over ``draws`` wear
    models and start wears: per beam width, the share of decisions with the exact first step, the share of
    optimal plans, the mean and largest excess over the optimum [%], and the mean reported gap [%]."""
    rng = np.random.default_rng(seed)
    graph = _graph(task, 2, rng)
    exact_limits = SearchLimits(exact_sequences=10**9, max_expansions=10**7)
    out = {w: {"same_first": 0, "optimal": 0, "excess": [], "gap": []} for w in widths}
    for _ in range(draws):
        model = random_model(graph, rng)
        v = rng.uniform(0.0, 0.4, 5)
        best = lookahead_plan(graph, model, v, limits=exact_limits)
        for w in widths:
            beam = lookahead_plan(graph, model, v, limits=SearchLimits(exact_sequences=0, beam_width=w))
            row = out[w]
            row["same_first"] += beam.next == best.next
            row["optimal"] += beam.cost <= best.cost * (1 + 1e-9)
            row["excess"].append(100.0 * (beam.cost - best.cost) / best.cost)
            row["gap"].append(100.0 * beam.gap / beam.cost)
    return {w: {"same_first": r["same_first"] / draws, "optimal": r["optimal"] / draws,
                "mean_excess_pct": float(np.mean(r["excess"])), "max_excess_pct": float(np.max(r["excess"])),
                "mean_reported_gap_pct": float(np.mean(r["gap"]))} for w, r in out.items()}


_HEADER = ("task", "agents", "execution", "actions", "hyperarcs", "look_ms", "cpu_ms", "replan_ms", "search",
           "gap", "expanded")
_WIDTHS = (28, 7, 11, 8, 10, 9, 8, 10, 7, 8, 9)
_BASE_HEADER = ("base_ms", "base_cpu", "cpu_ratio", "same")
_BASE_WIDTHS = (9, 9, 10, 6)


def format_lookahead_rows(rows: list[LookaheadRow]) -> str:
    """The rows as a fixed-width table; with a baseline, its times, the process-time ratio (this revision
    over the baseline) and whether every plan was the same."""
    base = any(r.same is not None for r in rows)
    header, widths = (_HEADER + _BASE_HEADER, _WIDTHS + _BASE_WIDTHS) if base else (_HEADER, _WIDTHS)
    lines = ["".join(h.rjust(w) for h, w in zip(header, widths, strict=True))]
    for r in rows:
        cells = (r.task, r.agents, r.execution, r.actions, r.hyperarcs, f"{r.lookahead_ms:.3g}",
                 f"{r.cpu_ms:.3g}", f"{r.replan_ms:.3g}", "exact" if r.exact else "beam", f"{r.gap:.3g}",
                 r.expanded)
        if base:
            cells += (f"{r.base_ms:.3g}", f"{r.base_cpu_ms:.3g}", f"{r.cpu_ms / r.base_cpu_ms:.3f}",
                      "yes" if r.same else "NO")
        lines.append("".join(str(c).rjust(w) for c, w in zip(cells, widths, strict=True)))
    return "\n".join(lines)


def check_lookahead_target(rows: list[LookaheadRow]) -> tuple[str, bool | None, str]:
    """The issue's target as (target, met or None if not measured, measured value)."""
    r = next((r for r in rows if (r.task, r.agents, r.execution) == ("sequential:21", 2, "sequential")), None)
    return (f"look-ahead decision <= {LOOKAHEAD_TARGET_MS:g} ms on a 20-action sequential task, 2 agents",
            None if r is None else r.lookahead_ms <= LOOKAHEAD_TARGET_MS,
            "-" if r is None else f"{r.lookahead_ms:.3g} ms (process time {r.cpu_ms:.3g} ms)")


def lookahead_rows_json(rows: list[LookaheadRow]) -> list[dict]:
    """The rows as dicts; the baseline's fields only where one was timed (JSON has no NaN)."""
    return [{k: x for k, x in asdict(r).items() if r.same is not None or k not in _BASELINE_FIELDS}
            for r in rows]


_BASELINE_FIELDS = ("base_ms", "base_cpu_ms", "same")

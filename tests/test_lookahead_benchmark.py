"""The look-ahead rows of scripts/bench_planner.py: they run, and the beam's quality table is consistent
(no figure here is a speed target: those are read from the script's output, never asserted)."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.planner_lookahead import (
    CURRENT,
    LOOKAHEAD_CASES,
    _graph,
    beam_quality,
    check_lookahead_target,
    format_lookahead_rows,
    lookahead_rows_json,
    random_model,
    run_lookahead_benchmark,
    time_decisions,
)
from benchmarks.planner_revision import planner_at
from ergosim.errors import ConfigError


@pytest.mark.slow
def test_quick_rows_and_the_target_row():
    rows = run_lookahead_benchmark(quick=True)
    assert [(r.task, r.agents, r.execution) for r in rows] == list(LOOKAHEAD_CASES[:3])
    target, met, value = check_lookahead_target(rows)
    assert met is not None and "ms" in value and "20-action" in target
    by = {(r.task, r.execution): r for r in rows}
    assert not by[("sequential:21", "sequential")].exact and by[("sequential:6", "sequential")].exact
    assert all(r.actions == int(r.task.split(":")[1]) - 1 for r in rows)
    assert "sequential:21" in format_lookahead_rows(rows) and len(lookahead_rows_json(rows)) == 3


def test_beam_quality_against_the_exact_search():
    q = beam_quality("sequential:5", draws=4, widths=(1, 6))
    for row in q.values():
        assert 0.0 <= row["optimal"] <= row["same_first"] + 1.0 and row["mean_excess_pct"] >= -1e-9
        assert row["max_excess_pct"] >= row["mean_excess_pct"] - 1e-9
    assert q[6]["mean_excess_pct"] <= q[1]["mean_excess_pct"] + 1e-9


def test_a_baseline_revision_loads_plans_and_is_compared():
    head = planner_at("HEAD")
    assert head.lookahead_plan is not CURRENT.lookahead_plan
    rng = np.random.default_rng(3)
    graph = _graph("sequential:8", 2, rng)
    model = random_model(graph, rng)
    v = rng.uniform(0.0, 0.4, 5)
    ours, theirs = CURRENT.lookahead_plan(graph, model, v), head.lookahead_plan(graph, model, v)
    assert theirs.cost > 0 and len(theirs.steps) == len(ours.steps) == 7
    out = time_decisions(graph, rng, "sequential", 3, baseline=CURRENT)
    assert out["same"] is True and out["base_cpu"] > 0 and out["cpu"] > 0
    assert time_decisions(graph, rng, "sequential", 1)["same"] is None
    with pytest.raises(ConfigError, match="no-such-revision"):
        planner_at("no-such-revision")


@pytest.mark.slow
def test_the_rows_carry_the_baseline():
    rows = run_lookahead_benchmark(quick=True, repeats=2, baseline=CURRENT)
    assert all(r.same for r in rows) and "cpu_ratio" in format_lookahead_rows(rows)
    assert all("base_cpu_ms" in r for r in lookahead_rows_json(rows))
    assert "base_cpu_ms" not in lookahead_rows_json(run_lookahead_benchmark(quick=True, repeats=1))[0]

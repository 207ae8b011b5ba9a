"""The look-ahead rows of scripts/bench_planner.py: they run, and the beam's quality table is consistent
(no figure here is a speed target: those are read from the script's output, never asserted)."""

from __future__ import annotations

import pytest

from ergosim.planner.benchmark_lookahead import (
    LOOKAHEAD_CASES,
    beam_quality,
    check_lookahead_target,
    format_lookahead_rows,
    lookahead_rows_json,
    run_lookahead_benchmark,
)


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

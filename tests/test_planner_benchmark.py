"""Benchmark plumbing: cases, timing, targets, JSON schema and the plot (not the timings themselves)."""

from __future__ import annotations

import json

import numpy as np

from benchmarks.planner import (
    BenchRow,
    bench_cases,
    check_targets,
    format_table,
    rows_json,
    run_benchmark,
    time_replans,
)
from benchmarks.planner_plot import plot_benchmark
from ergosim.atomic import write_json
from ergosim.planner import generate_task


def test_cases_cover_the_issue_rows():
    cases = bench_cases()
    assert len(cases) == len(set(cases))
    for shape in ("sequential", "scarce"):
        assert {n for s, n, k, p in cases if s == shape and k == 2 and p} == set(range(2, 21))
        assert {k for s, n, k, p in cases if s == shape and n == 10 and p} == set(range(2, 31))
    assert [(n, k) for s, n, k, p in cases if not p] == [
        (30, 2),
        (30, 30),
        (40, 2),
        (40, 30),
        (60, 2),
        (60, 30),
    ]


def test_time_replans_and_cap():
    g = generate_task("sequential:6", agents=2, seed=0)
    rng = np.random.default_rng(0)
    assert 0.0 < time_replans(g, "fast", rng, min_total_s=0.0) < 1000.0
    assert time_replans(g, "paper", rng, min_total_s=0.0, cap_s=10.0) > 0.0
    big = generate_task("sequential:22", agents=2, seed=0)
    assert time_replans(big, "paper", rng, cap_s=0.05) is None  # the search stops at its budget


def _row(shape, pieces, agents, fast, paper):
    return BenchRow(shape, pieces, agents, 1, 2, fast, paper)


def test_targets():
    rows = [
        _row("sequential", 20, 2, 1.5, 3000.0),
        _row("sequential", 10, 30, 1.0, 20.0),
        _row("sequential", 40, 30, 999.0, None),
    ]
    assert [(met, value) for _, met, value in check_targets(rows)] == [
        (True, "1.5"),
        (True, "2000x"),
        (True, "999"),
    ]
    assert "sequential:20, 2 agents" in check_targets(rows)[1][0]
    rows = [_row("sequential", 20, 2, 2.5, 2000.0), _row("sequential", 40, 30, 1000.0, None)]
    assert [met for _, met, _ in check_targets(rows)] == [False, False, False]
    assert [met for _, met, _ in check_targets([])] == [None, None]


def test_the_largest_size_both_finish_skips_a_size_where_one_shape_stopped():
    rows = [
        BenchRow("sequential", 19, 2, 190, 2280, 0.15, 8000.0),
        BenchRow("sequential", 20, 2, 210, 2660, 0.16, None, "over budget"),
        BenchRow("scarce", 20, 2, 39, 38, 0.13, 0.1),
        BenchRow("scarce", 19, 2, 37, 36, 0.12, 0.09),
        BenchRow("sequential", 30, 2, 465, 8990, 0.3, None, "not run"),
    ]
    target, met, value = check_targets(rows)[1]
    assert "(sequential:19, 2 agents)" in target
    assert (met, value) == (True, "53333x")


def test_json_schema_table_and_plot(tmp_path):
    rows = [_row("sequential", n, 2, 0.1 * n, 0.5 * n if n < 4 else None) for n in range(2, 6)]
    rows += [_row("scarce", 10, k, 0.2, 0.3) for k in (2, 10)]
    write_json(tmp_path / "bench.json", rows_json(rows))
    data = json.loads((tmp_path / "bench.json").read_text())
    assert list(data) == ["rows"]
    assert set(data["rows"][0]) == {
        "shape", "pieces", "agents", "nodes", "hyperarcs", "fast_ms", "paper_ms", "paper_note"
    }
    assert data["rows"][3]["paper_ms"] is None
    table = format_table(rows).splitlines()
    assert table[0].split() == [
        "shape",
        "pieces",
        "agents",
        "nodes",
        "hyperarcs",
        "fast_ms",
        "paper_ms",
        "paper/fast",
    ]
    assert table[4].split()[-2:] == ["-", "-"]
    plot_benchmark(rows, tmp_path / "bench.png")
    assert (tmp_path / "bench.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert list(tmp_path.glob(".*.tmp")) == []


def test_a_row_over_the_memory_budget_says_so_and_the_benchmark_goes_on():
    cases = [("sequential", 4, 2, True), ("sequential", 8, 2, True), ("sequential", 9, 2, True),
             ("scarce", 9, 2, True), ("sequential", 9, 2, False)]
    rows = run_benchmark(cap_s=10.0, cases=cases, max_states=200)
    assert [(r.pieces, r.paper_note) for r in rows] == [
        (4, ""), (8, "over budget"), (9, "skipped"), (9, ""), (9, "not run")
    ]
    assert rows[0].paper_ms > 0.0 and rows[3].paper_ms > 0.0
    assert all(r.paper_ms is None for r in rows[1:3] + rows[4:])
    assert all(r.fast_ms > 0.0 for r in rows)
    table = format_table(rows).splitlines()
    assert table[2].split()[-3:] == ["over", "budget", "-"]
    assert table[3].split()[-2:] == ["skipped", "-"]
    assert table[5].split()[-2:] == ["-", "-"]


def test_a_row_over_the_time_cap_says_so():
    rows = run_benchmark(cap_s=0.05, cases=[("sequential", 22, 2, True), ("sequential", 23, 2, True)])
    assert [r.paper_note for r in rows] == ["over time cap", "skipped"]

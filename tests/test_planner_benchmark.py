"""Benchmark plumbing: cases, timing, targets, JSON schema and the plot (not the timings themselves)."""

from __future__ import annotations

import json

import numpy as np

from ergosim.atomic import write_json
from ergosim.planner import generate_task
from ergosim.planner.benchmark import (
    BenchRow,
    bench_cases,
    check_targets,
    format_table,
    rows_json,
    time_replans,
)
from ergosim.planner.benchmark_plot import plot_benchmark


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


def test_json_schema_table_and_plot(tmp_path):
    rows = [_row("sequential", n, 2, 0.1 * n, 0.5 * n if n < 4 else None) for n in range(2, 6)]
    rows += [_row("scarce", 10, k, 0.2, 0.3) for k in (2, 10)]
    write_json(tmp_path / "bench.json", rows_json(rows))
    data = json.loads((tmp_path / "bench.json").read_text())
    assert list(data) == ["rows"]
    assert set(data["rows"][0]) == {"shape", "pieces", "agents", "nodes", "hyperarcs", "fast_ms", "paper_ms"}
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

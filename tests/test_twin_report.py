"""Summary statistics, tables and files built from subject runs."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from ergosim.atomic import write_json
from ergosim.errors import ConfigError
from ergosim.experiment.csv_files import write_allocations, write_ticks
from ergosim.experiment.scenario import scenario_config
from ergosim.experiment.summary import summarise, wilcoxon_between
from ergosim.posture import KWEAR_JOINTS
from ergosim.twin.records import TICK_COLUMNS, Allocation, SubjectRun, TickLog

KWEAR_COLUMNS = [TICK_COLUMNS.index(f"kwear_{j}") for j in KWEAR_JOINTS]


def _run(subject: int, mode: str, agents: list[str], kwear_level: float) -> SubjectRun:
    allocs = [
        Allocation(subject, mode, rep, order, f"a{order + 1}", agent, 1.0, 2.5, 0.0, 1.0,
                   had_choice=order < 4, allocatable=order < 4)
        for rep in (1, 2)
        for order, agent in enumerate(agents)
    ]
    ticks = TickLog(capacity=16)
    for k in range(40):
        row = np.zeros(len(TICK_COLUMNS))
        row[KWEAR_COLUMNS] = kwear_level
        ticks.append(row)
    return SubjectRun(subject, mode, allocs, ticks, 2, 1, 0.05, 0.8)


def test_robot_share_counts_completed_actions_either_agent_may_do():
    runs = {"hrc": [_run(0, "hrc", ["robot", "human", "human", "robot", "human"], 0.5)]}
    s = summarise("x", 7, runs, actions=["a1", "a2", "a3", "a4", "a5"])["modes"]["hrc"]
    assert (s["actions"], s["robot_actions"]) == (8, 4)  # a5 is the human's alone: not allocatable
    assert s["robot_share"] == 0.5 and s["robot_share_chosen"] == 0.5
    assert s["robot_share_by_action"] == {"a1": 1.0, "a2": 0.0, "a3": 0.0, "a4": 1.0}
    # 40 ticks x 0.05 s x 5 joints x 0.5
    assert s["kwear_integral_by_subject"] == [pytest.approx(5.0)]


def test_ticklog_grows_past_capacity_without_losing_rows():
    run = _run(0, "hrc", ["human"] * 5, 0.9)
    assert run.ticks.n == 40 and run.ticks.rows.shape == (40, len(TICK_COLUMNS))
    assert run.time_above_threshold == pytest.approx(2.0)


def test_wilcoxon_detects_a_consistent_paired_difference():
    hrc = [10.0 + i for i in range(12)]
    honly = [h + 3.0 + 0.1 * i for i, h in enumerate(hrc)]
    res = wilcoxon_between(hrc, honly, "kwear_integral")
    assert res["statistic"] == 0.0 and res["p"] < 0.01
    assert wilcoxon_between(hrc, hrc, "m")["p"] == 1.0


def test_allocation_table_and_files(tmp_path):
    runs = {
        "hrc": [_run(0, "hrc", ["human", "robot", "human", "human", "robot"], 0.1)],
        "rula": [_run(0, "rula", ["human"] * 5, 0.1)],
    }
    summary = summarise("kwear-validation", 0, runs, actions=["a1", "a2", "a3", "a4", "a5"])
    assert summary["allocation_table"]["kwear"] == [["H", "R", "H", "H", "R"]] * 2
    assert summary["allocation_table"]["rula"] == [["H"] * 5] * 2
    write_json(tmp_path / "summary.json", summary)
    assert json.loads((tmp_path / "summary.json").read_text())["seed"] == 0
    write_allocations(tmp_path / "allocations.csv", runs["hrc"][0].allocations)
    rows = list(csv.DictReader((tmp_path / "allocations.csv").open()))
    assert len(rows) == 10 and rows[1]["agent"] == "robot" and float(rows[1]["robot_cost"]) == 2.5
    write_ticks(tmp_path / "ticks.csv", runs["hrc"])
    data = np.genfromtxt(tmp_path / "ticks.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert data.shape == (40,) and np.allclose(data["kwear_neck"], 0.1)
    assert not list(tmp_path.glob(".*.tmp"))


def test_scenarios_validate_and_reject_bad_values():
    cfg = scenario_config("multi-subject")
    cfg.validate()
    assert cfg.cost.rula_threshold == pytest.approx(7.2)
    with pytest.raises(ConfigError, match="unknown scenario 'nope'; valid scenarios: gearbox, "):
        scenario_config("nope")


def test_kwear_integral_covers_the_production_schedule_only():
    """The headline load proxy integrates over repetitions × takt; the whole-run one is kept beside it."""
    run = _run(0, "hrc", ["human"] * 5, 0.5)
    t_col = TICK_COLUMNS.index("t")
    rows = run.ticks.rows.copy()
    rows[:, t_col] = 0.05 * np.arange(1, len(rows) + 1)  # 40 ticks: 0.05 .. 2.0 s
    ticks = TickLog()
    for row in rows:
        ticks.append(row)
    windowed = SubjectRun(0, "hrc", run.allocations, ticks, 2, 1, 0.05, 0.8, horizon=1.0)
    assert windowed.kwear_integral == pytest.approx(20 * 0.05 * 5 * 0.5)  # ticks with t <= 1.0 s
    assert windowed.kwear_integral_run == pytest.approx(40 * 0.05 * 5 * 0.5)
    assert windowed.kwear_mean == pytest.approx(2.5) and windowed.duration == pytest.approx(2.0)
    s = summarise("x", 0, {"hrc": [windowed], "h-only": [windowed]}, actions=["a1"])
    assert set(s["wilcoxon_by_metric"]) == {"kwear_integral", "kwear_integral_run", "kwear_mean",
                                            "time_above_vth"}
    assert s["wilcoxon"]["metric"] == "kwear_integral"
    assert all(w["modes"] == ["hrc", "h-only"] for w in s["wilcoxon_by_metric"].values())

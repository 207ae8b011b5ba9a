"""Team execution in the real loop (issue 17), in short runs: parallel multi-subject and gearbox, negotiation,
the time term, speed and separation monitoring, and the outputs that report them. The sequential default
keeps the paper's outputs (no team fields in summary.json)."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from ergosim.cli import main
from ergosim.errors import ConfigError
from ergosim.experiment.scenario import load_scenario
from ergosim.planner import bundled_task
from ergosim.twin.allocator import Allocator
from ergosim.twin.modes import Mode
from ergosim.viz import RecordingReader
from ergosim.viz.paths import ALLOCATION_LOG


def _run(out, scenario, *args):
    code = main(["run", scenario, "--subjects", "1", "--quiet", "--no-plots", "--seed", "0", "--jobs", "1",
                 "--out", str(out), *args])
    assert code == 0
    rows = list(csv.DictReader((out / "allocations.csv").open()))
    return json.loads((out / "summary.json").read_text()), json.loads((out / "team.json").read_text()), rows


@pytest.fixture(scope="module")
def parallel_ms(tmp_path_factory):
    out = tmp_path_factory.mktemp("team") / "ms"
    return _run(out, "multi-subject", "--reps", "3", "--mode", "hrc", "--set", "execution=parallel")


@pytest.fixture(scope="module")
def parallel_gearbox(tmp_path_factory):
    base = tmp_path_factory.mktemp("team")
    rrd = base / "gearbox.rrd"
    return (*_run(base / "gb", "gearbox", "--reps", "2", "--mode", "hrc", "--set", "execution=parallel",
                  "--rrd", str(rrd)), rrd)


@pytest.fixture(scope="module")
def negotiating(tmp_path_factory):
    """Sequential, a worker who refuses readily, and a time term."""
    out = tmp_path_factory.mktemp("team") / "neg"
    return _run(out, "multi-subject", "--reps", "3", "--mode", "hrc", "--set", "negotiation=true",
                "--set", "refusal_tolerance=0.35", "--set", "w_time=0.02")


def _precedence_holds(rows, before, after):
    """Every ``after`` action of a repetition ends after its ``before`` action ended."""
    for rep in {r["repetition"] for r in rows}:
        done = {r["action"]: float(r["t_end"]) for r in rows
                if r["repetition"] == rep and r["status"] == "done"}
        assert all(done[a] > done[before] for a in after if a in done), (rep, done)


def _overlap(a, b) -> bool:
    return min(float(a["t_end"]), float(b["t_end"])) > max(float(a["t_start"]), float(b["t_start"])) + 1e-6


@pytest.mark.slow
def test_parallel_multi_subject_overlaps_the_robot_and_the_worker(parallel_ms):
    summary, team, rows = parallel_ms
    m = team["modes"]["hrc"]
    assert m["execution"] == "parallel" and m["repetitions_completed"] == 3
    assert summary["team"] == team and summary["config"]["execution"] == "parallel"
    assert m["overlapping_repetitions"] >= 2 and m["both_busy_s"] > 0
    # the robot fetches while the worker works: a robot row starts before the worker's row before it ends
    by_rep = {}
    for r in rows:
        by_rep.setdefault(r["repetition"], []).append(r)
    assert any(_overlap(x, y) for rs in by_rep.values() for x in rs for y in rs
               if x["agent"] == "robot" and y["agent"] == "human")
    _precedence_holds(rows, "a1", ["a2", "a3", "a4", "a5"])
    _precedence_holds(rows, "a4", ["a5"])
    # one agent never does two of its own actions at once (the worker's own rows never overlap)
    worker = [r for r in rows if r["agent"] == "human"]
    assert not any(_overlap(x, y) for i, x in enumerate(worker) for y in worker[i + 1:])
    assert len(m["makespan_s"][0]) == 3 and m["throughput_per_hour"] > 0
    assert set(m["idle_s"]) == {"human", "robot"}


def test_parallel_runs_are_monitored_and_end_apart(parallel_ms):
    safety = parallel_ms[1]["modes"]["hrc"]["safety"]
    assert safety["ssm"] is True  # auto: on in parallel execution
    assert safety["end_separation_min_m"] > 0.05  # the robot is home, well clear of the worker
    assert np.isfinite(safety["min_separation_m"]) and safety["min_separation_m"] < 0.3
    assert safety["robot_slowed_s"] + safety["robot_stopped_s"] > 0  # handovers bring the robot close
    assert safety["params"]["reaction_time"] == 0.1


@pytest.mark.slow
def test_gearbox_builds_both_sub_assemblies_at_once(parallel_gearbox):
    summary, team, rows, rrd = parallel_gearbox
    for rep in ("1", "2"):
        of = {r["action"]: r for r in rows if r["repetition"] == rep and r["status"] == "done"}
        first = [of[a] for a in ("g1", "g2") if a in of]
        second = [of[a] for a in ("g3", "g4") if a in of]
        assert any(_overlap(x, y) and x["agent"] != y["agent"] for x in first for y in second), rep
    _precedence_holds(rows, "g5", ["g6", "g7", "g8"])
    _precedence_holds(rows, "g2", ["g5"])
    _precedence_holds(rows, "g4", ["g5"])
    # the recording's log shows the two decisions at the same instant
    _, lines = RecordingReader(rrd).texts(ALLOCATION_LOG)
    assert any("g3 → robot" in s for s in lines) and any("g1 → human" in s for s in lines)


@pytest.mark.slow
def test_negotiation_refuses_high_wear_actions_and_still_completes(negotiating):
    summary, team, rows = negotiating
    m = team["modes"]["hrc"]
    refused = [r for r in rows if r["status"] == "refused"]
    assert refused and all(r["agent"] == "human" and r["t_start"] == r["t_end"] for r in refused)
    assert m["refusals"] == len(refused) and m["offers"] > m["refusals"]
    assert summary["modes"]["hrc"]["repetitions_completed"] == 3
    # a refused action is re-planned at once: the next row of that decision gives it to someone
    for r in refused:
        later = [x for x in rows if x["repetition"] == r["repetition"] and int(x["order"]) > int(r["order"])]
        assert later
    assert m["v_hat_refused_mean"] > m["v_hat_accepted_mean"]
    # the weights used are recorded
    assert summary["team"]["settings"]["w_time"] == 0.02 and summary["config"]["negotiation"] is True


def test_sequential_defaults_keep_the_papers_summary(kv_run):
    """The shared run: 1 subject, seed 0, 1 repetition, hrc, exit status 0 (tests/conftest.py)."""
    out = kv_run.out
    assert kv_run.code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert "team" not in summary and not (out / "team.json").exists()
    assert not {"execution", "w_time", "negotiation"} & set(summary["config"])


@pytest.mark.parametrize("key, value, message", [
    ("execution", "swarm", "is not one of sequential, parallel"),
    ("w_time", "-1", r"w_time must be in \[0, 1e\+06\]"),
    ("refusal_tolerance", "1.5", "refusal_tolerance must be in"),
    ("team_margin", "0", "team_margin must be > 0"),
    ("scene.safety.ssm", "maybe", "ssm must be one of auto, on, off"),
    ("scene.safety.reaction_time", "-0.1", "reaction_time must be >= 0"),
])
def test_bad_team_settings_are_one_line_errors(key, value, message):
    with pytest.raises(ConfigError, match=message) as err:
        load_scenario("multi-subject", {key: value})
    assert "\n" not in str(err.value)


def test_the_safety_table_is_read_and_overridden():
    sc = load_scenario("gearbox", {"scene.safety.ssm": "on", "scene.safety.stopping_time": "0.4"})
    safety = sc.cell().safety
    assert safety.ssm == "on" and safety.stopping_time == 0.4 and safety.enabled("sequential")
    assert not load_scenario("gearbox").cell().safety.enabled("sequential")


def test_the_time_term_moves_work_to_the_faster_agent():
    graph = bundled_task("gearbox")
    plain = Mode("plain", "fixed task costs")
    slow_worker = {(a, "human"): 10.0 for a in graph.actions} | {(a, "robot"): 1.0 for a in graph.actions}
    paper = Allocator(graph, plain, index=None, cost=None)
    timed = Allocator(graph, plain, index=None, cost=None, w_time=1.0, durations=slow_worker)
    assert paper.decide(np.zeros(5), [], set(), 0.0, 1).agent == "human"  # g1 is the worker's alone
    done = ["fixture+housing"]
    assert paper.decide(np.zeros(5), done, set(), 0.0, 1).agent == "human"  # 1.0 < 2.5
    assert timed.decide(np.zeros(5), done, set(), 0.0, 1).agent == "robot"  # 1 + 2.5 < 10 + 1
    assert timed.price(list(graph.actions))[2][("g2", "robot")] == 1.0


@pytest.mark.slow
def test_the_robot_hands_every_part_over_in_parallel_beside_an_idle_worker(tmp_path):
    """multi-subject, robot only, in parallel (separation monitoring on): each part is presented at the
    assembly, in front of the idle worker, who does not step aside. The robot used to stop there for good
    (the run hung); on a hand-over's transits it creeps at the contact speed instead, so every hand-over
    is made, and the monitor reports the time it was slowed and how long it moved overlapping the worker."""
    summary, team, rows = _run(tmp_path / "ronly", "multi-subject", "--mode", "r-only", "--reps", "1",
                               "--set", "execution=parallel")
    assert summary["status"] == "complete"
    assert [(r["action"], r["agent"], r["status"]) for r in rows] == [
        ("a1", "robot", "done"), ("a2", "robot", "done"), ("a3", "robot", "done"), ("a4", "robot", "done"),
        ("a5", "human", "done")]
    safety = team["modes"]["r-only"]["safety"]
    assert safety["ssm"] is True and safety["robot_slowed_s"] > 0
    assert safety["end_separation_min_m"] > 0.05

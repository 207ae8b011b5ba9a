"""Outputs that tell the truth (issue 14): allocation statuses, failures, robot share of completed actions,
repetition outcomes, the printed summary, per-subject recordings, KWear state files and noise_scale."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest

from ergosim.cli import main
from ergosim.ergonomics.kwear import predict
from ergosim.experiment.csv_files import ALLOCATION_COLUMNS, FAILURE_COLUMNS
from ergosim.experiment.kwear_state import read_state
from ergosim.experiment.scenario import load_scenario, scenario_config
from ergosim.experiment.summary import summarise
from ergosim.experiment.summary_text import summary_text
from ergosim.posture import HUMAN_JOINTS, KWEAR_JOINTS
from ergosim.twin.records import Allocation, Failure, RepetitionOutcome, SubjectRun, TickLog
from ergosim.viz import RecordingReader
from ergosim.worker.stream import MocapStream
from ergosim.worker.subjects import make_subjects

ROOT = Path(__file__).resolve().parents[1]


def _rows(path: Path) -> list[dict]:
    with path.open() as f:
        return list(csv.DictReader(f))


@pytest.mark.slow
def test_forced_robot_actions_count_in_the_robot_share(forced_run):
    """The worker cannot reach L, its a2 attempt fails and the robot does a2 in every repetition: the old
    robot share said 0 % (0/8); every completed a2 is the robot's."""
    out = forced_run.out
    assert forced_run.code == 0
    m = json.loads((out / "summary.json").read_text())["modes"]["hrc"]
    assert m["repetitions_completed"] == 2
    assert m["forced_robot_actions"] == 2 and m["forced_human_actions"] == 0
    assert m["robot_share_by_action"]["a2"] == 1.0
    assert m["robot_actions"] >= 2 and m["robot_share"] == m["robot_actions"] / m["actions"] > 0
    assert m["actions"] == 8  # a1..a4 completed in each repetition; a5 is the worker's alone
    assert m["worker_failures"] == 2 and m["robot_failures"] == 0
    assert m["robot_share_chosen"] == m["robot_choices"] / m["choices"]


def test_allocations_csv_has_a_row_per_attempt_with_its_status(forced_run):
    out = forced_run.out
    rows = _rows(out / "allocations.csv")
    assert tuple(rows[0]) == ALLOCATION_COLUMNS
    a2 = [r for r in rows if r["action"] == "a2" and r["repetition"] == "1"]
    assert [(r["agent"], r["status"], r["attempt"], r["forced"]) for r in a2] == [
        ("human", "failed:unreachable", "1", ""), ("robot", "done", "2", "robot")]
    assert all(r["status"] in ("done", "pruned") or r["status"].startswith("failed:") for r in rows)
    assert {r["allocatable"] for r in rows if r["action"] == "a5"} == {"0"}


def test_failures_csv_and_the_recording_log_hold_every_failure(forced_run, tmp_path):
    out = forced_run.out
    rows = _rows(out / "failures.csv")
    assert tuple(rows[0]) == FAILURE_COLUMNS
    assert len(rows) == 2
    for r in rows:
        assert (r["action"], r["agent"], r["mode"]) == ("a2", "human", "hrc")
        assert r["status"] == "failed:unreachable"
        assert re.search(r"cm short", r["message"])


def test_failures_reach_the_recording_text_log(forced_run):
    """The forced run's two failed a2 attempts (one a repetition) are in the recording's text log."""
    assert forced_run.code == 0
    _, texts = RecordingReader(forced_run.rrd).texts("allocation/log")
    failed = [t for t in texts if t.startswith("failed:")]
    assert len(failed) == len(_rows(forced_run.out / "failures.csv")) == 2
    assert all("a2 by human failed" in t for t in failed)
    assert len(texts) > len(failed)  # the decisions are there too


def test_printed_summary_labels_rows_names_the_mode_and_warns(forced_run):
    out = forced_run.out
    summary = json.loads((out / "summary.json").read_text())
    cfg = scenario_config("multi-subject")
    text = summary_text(summary, cfg)
    assert "actions: a1 a2 a3 a4 a5" in text
    assert "allocations, hrc" in text and "kwear)" not in text
    assert re.search(r"subject 0 rep 1\s+H\s+R\*!", text) and "subject 0 rep 2" in text
    assert re.search(r"WARNING: hrc: 2 forced robot action\(s\), 2 worker failure\(s\)", text)


def test_a_clean_run_prints_no_warning():
    allocs = [Allocation(0, "hrc", 1, k, f"a{k + 1}", "human", 1.0, 2.5, k, k + 1.0, True,
                         allocatable=k < 4) for k in range(5)]
    run = SubjectRun(0, "hrc", allocs, TickLog(), 1, 0, 0.05, 0.8,
                     outcomes=[RepetitionOutcome(0, "hrc", 1, "completed", t_start=0.0, t_end=5.0)])
    summary = summarise("multi-subject", 0, {"hrc": [run]}, actions=["a1", "a2", "a3", "a4", "a5"])
    text = summary_text(summary, scenario_config("multi-subject"))
    assert "WARNING" not in text and "subject 0 rep 1" in text
    assert summary["modes"]["hrc"]["repetitions"] == [
        {"subject": 0, "repetition": 1, "outcome": "completed", "reason": "", "duration_s": 5.0}]


def test_robot_and_worker_failures_count_their_own_agent():
    fail = [Failure(1.0, 0, "hrc", 1, "a2", "robot", "failed:unreachable", "m"),
            Failure(2.0, 0, "hrc", 1, "a2", "human", "failed:timeout", "m"),
            Failure(3.0, 0, "hrc", 1, "a3", "robot", "failed:dropped", "m"),
            Failure(4.0, 0, "hrc", 1, "", "", "abandoned", "m")]
    run = SubjectRun(0, "hrc", [], TickLog(), 0, 0, 0.05, 0.8, failures=fail)
    m = summarise("x", 0, {"hrc": [run]}, actions=["a2"])["modes"]["hrc"]
    assert (m["robot_failures"], m["worker_failures"]) == (2, 1)


def test_kwear_state_file_prices_the_plan_with_eq_9_to_11(forced_run, capsys):
    out = forced_run.out
    path = out / "kwear_state_s0_hrc.json"
    state = read_state(path)
    doc = json.loads(path.read_text())
    ticks = _rows(out / "ticks.csv")
    np.testing.assert_allclose(state.v, [float(ticks[-1][f"kwear_{j}"]) for j in KWEAR_JOINTS], atol=1e-8)
    assert main(["plan", "corner-joint", "--state", str(path), "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)
    for step in plan["plan"]:
        v_hat = predict(state.v, state.alpha[step["action"]])
        human = float(np.sum(v_hat + doc["cost"]["gamma"] * (v_hat >= doc["cost"]["v_th"])))
        expected = human if step["agent"] == "human" else doc["cost"]["robot_cost"]
        assert step["cost"] == pytest.approx(expected, abs=1e-12)
        if step["action"] != "a5":  # the cheaper agent wins (eq. 2); a5 is the worker's alone
            assert step["cost"] <= min(human, doc["cost"]["robot_cost"]) + 1e-12


def test_plan_state_sends_a_worn_shoulder_to_the_robot(tmp_path, capsys):
    alpha = {a: [0.9] * 5 for a in ("a1", "a2", "a3", "a4", "a5")}
    state = {"format": "ergosim-kwear-state/1", "v": [0.85, 0.1, 0.1, 0.1, 0.1], "alpha": alpha,
             "kwear_params": {"t_max": 240.0, "v_max": 0.993, "g_avg": 3.0},
             "cost": {"gamma": 100.0, "v_th": 0.8, "robot_cost": 2.5}}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(state))
    assert main(["plan", "corner-joint", "--state", str(path), "--done", "a1", "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)
    # V̂_shoulder = 1 - 0.9 * 0.15 = 0.865 >= V_th: every robot-capable action goes to the robot
    assert {s["action"]: s["agent"] for s in plan["plan"]} == {"a2": "robot", "a3": "robot", "a4": "robot",
                                                              "a5": "human"}
    bad = {**state, "v": [0.1] * 4}
    path.write_text(json.dumps(bad))
    assert main(["plan", "corner-joint", "--state", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}: v: v must be a list of 5 numbers" in err and err.count("\n") == 1


def test_plan_done_takes_labels_and_costs_are_what_ifs(capsys):
    assert main(["plan", "corner-joint", "--done", "a1", "--json"]) == 0
    by_label = json.loads(capsys.readouterr().out)
    assert main(["plan", "corner-joint", "--done", "area+J", "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == by_label
    assert main(["plan", "corner-joint", "--costs", "human.a2=3.1,robot.a3=0.5", "--json"]) == 0
    agents = {s["action"]: (s["agent"], s["cost"]) for s in json.loads(capsys.readouterr().out)["plan"]}
    assert agents["a2"] == ("robot", 2.5) and agents["a3"] == ("robot", 0.5) and agents["a1"][0] == "human"
    assert main(["plan", "corner-joint", "--done", "a9"]) == 2
    assert "--done: 'a9' is neither an operation nor an action" in capsys.readouterr().err
    assert main(["plan", "corner-joint", "--costs", "nobody.a2=1"]) == 2
    assert "--costs: unknown agent 'nobody'" in capsys.readouterr().err


def test_rrd_subject_and_mode_choose_what_is_recorded(kv_two_subjects):
    """The shared run recorded with --rrd-subject 1 --rrd-mode rula (tests/conftest.py)."""
    out, rrd, code = kv_two_subjects
    assert code == 0
    rows = [r for r in _rows(out / "ticks.csv") if r["subject"] == "1" and r["mode"] == "rula"]
    t, v = RecordingReader(rrd).scalars("ergonomics/kwear/shoulder")
    np.testing.assert_allclose(t, [float(r["t"]) for r in rows], atol=1e-6)
    np.testing.assert_allclose(v, [float(r["kwear_shoulder"]) for r in rows], atol=1e-9)
    other = [r for r in _rows(out / "ticks.csv") if r["subject"] == "0" and r["mode"] == "hrc"]
    assert not np.allclose(v[: len(other)], [float(r["kwear_shoulder"]) for r in other][: len(v)])


@pytest.mark.parametrize(("args", "needle"), [
    (["--rrd-subject", "2"], "--rrd-subject: must be a subject index in 0..1"),
    (["--rrd-mode", "h-only"], "--rrd-mode: mode 'h-only' is not run"),
])
def test_rrd_choices_are_checked(args, needle, tmp_path, capsys):
    code = main(["run", "kwear-validation", "--subjects", "2", "--quiet", "--out", str(tmp_path / "n"),
                 "--rrd", str(tmp_path / "r.rrd"), *args])
    err = capsys.readouterr().err
    assert code == 2 and needle in err and err.count("\n") == 1


def test_noise_scale_multiplies_the_sensor_noise():
    subject = make_subjects(1, 0)[0]
    true = np.tile(np.linspace(0, 30, len(HUMAN_JOINTS)), (240, 1))
    errors = {}
    for scale in (0.0, 0.5, 1.0):
        stream = MocapStream(subject, np.random.default_rng(4), noise=scale)
        errors[scale] = stream.measure(true).angles - true
    assert np.all(errors[0.0] == 0.0)
    np.testing.assert_allclose(errors[0.5], 0.5 * errors[1.0], rtol=1e-12, atol=1e-12)
    assert np.std(errors[1.0]) > 0.1
    legacy = MocapStream(subject, np.random.default_rng(4), noise=True).measure(true).angles - true
    np.testing.assert_array_equal(legacy, errors[1.0])  # noise=True is scale 1, bit for bit


def test_noise_scale_reaches_the_twin():
    from ergosim.experiment.subject import rig_spec  # noqa: PLC0415
    from ergosim.twin.rig import build_rig  # noqa: PLC0415

    scenario = load_scenario("kwear-validation", {"noise_scale": "0.5"})
    rig = build_rig(rig_spec(scenario), make_subjects(1, 0)[0], np.random.default_rng(0))
    assert rig.plant.track.stream.noise_scale == 0.5


def test_ci_runs_the_readme_test_command_and_ruff():
    readme = (ROOT / "README.md").read_text()
    ci = (ROOT / ".ci" / "run").read_text()
    command = re.search(r"```bash\n(python3 -m venv .venv && .*pytest -q)\n```", readme).group(1)
    assert command in ci
    assert re.search(r"^\.venv/bin/ruff check \.$", ci, re.M)

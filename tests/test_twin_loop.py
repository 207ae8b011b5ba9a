"""The digital-twin loop on the real workcells: short scenarios run end to end (issue 6, 7).

These run the real loop -- physics, the mocap-driven worker, RULA/KWear per tick, the planner after every
action -- shortened only in subjects and repetitions.
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import KV_SHORT

from ergosim.cli import main
from ergosim.experiment.runner import run_subject
from ergosim.experiment.scenario import load_scenario
from ergosim.posture import KWEAR_JOINTS
from ergosim.viz import RecordingReader


@pytest.fixture(scope="module")
def hrc_run():
    # a cheaper robot than the paper's 2.5, so two repetitions surely give it actions whatever the calibration
    sc = load_scenario("multi-subject", {"repetitions": "2", "modes": "hrc,h-only", "robot_cost": "1.0"})
    return sc.protocol, run_subject(sc, 0, 0, sc.protocol.modes)


@pytest.mark.slow
def test_hrc_completes_every_assembly_through_the_scene(hrc_run):
    cfg, res = hrc_run
    run = res.runs["hrc"]
    assert run.repetitions_completed == 2
    done = [a for a in run.allocations if a.status == "done"]
    # every repetition does a1..a5 once, in an order the planner allowed (a1 first, a5 last)
    for rep in (1, 2):
        order = [a.action for a in done if a.repetition == rep]
        assert sorted(order) == ["a1", "a2", "a3", "a4", "a5"]
        assert order[0] == "a1" and order[-1] == "a5"
    # ticks run at the ergonomics rate and KWear stays in [0, 1)
    t = run.ticks.column("t")
    assert np.allclose(np.diff(t), 1.0 / cfg.sensing.ergonomics_rate)
    assert np.all((run.ticks.kwear >= 0) & (run.ticks.kwear < 1))


def test_allocations_follow_the_costs(hrc_run):
    _, res = hrc_run
    for a in res.runs["hrc"].allocations:
        if not a.had_choice:
            assert a.action == "a5" and a.agent == "human"  # a5 is the human's alone (§7.2)
            continue
        # actions are priced independently (one prediction from V(t_k) each), so the optimal plan gives
        # each action to its cheaper agent; ties go to the first agent of the task file (the human)
        if a.agent == "robot":
            assert a.robot_cost < a.human_cost
        else:
            assert a.human_cost <= a.robot_cost


def test_human_costs_are_eq_10_11_of_the_predicted_kwear(hrc_run):
    cfg, res = hrc_run
    run = res.runs["hrc"]
    for d in run.decisions:
        for action, v_hat in d.v_hat.items():
            alpha = np.asarray(res.alphas[action])
            np.testing.assert_allclose(v_hat, 1 - alpha * (1 - d.v_now), rtol=0, atol=1e-12)  # eq. 9
            expected = float(np.sum(v_hat + cfg.cost.gamma * (v_hat >= cfg.cost.v_th)))  # eq. 10-11
            assert d.costs[(action, "human")] == pytest.approx(expected, abs=1e-12)
            assert d.costs[(action, "robot")] == cfg.cost.robot_cost


def test_h_only_never_dispatches_to_the_robot(hrc_run):
    cfg, res = hrc_run
    run = res.runs["h-only"]
    assert run.repetitions_completed == 2
    assert {a.agent for a in run.allocations} == {"human"}
    # the worker waits for the takt before the next repetition (paper §7.2)
    starts = [min(a.t_start for a in run.allocations if a.repetition == r) for r in (1, 2)]
    assert starts[1] == pytest.approx(cfg.pacing.takt, abs=1.0 / cfg.sensing.mocap_rate)


def _repetition_starts(run) -> list[float]:
    return [min(a.t_start for a in run.allocations if a.repetition == r) for r in (1, 2)]


@pytest.mark.slow
@pytest.mark.parametrize("takt_paced", [False, True])
def test_hrc_is_paced_by_the_robot_unless_takt_paced(takt_paced):
    """§7.2: in HRC "the assembly rhythm was marked by the robot executions" (``takt_paced = false``, the
    scenario's default): the next repetition starts as soon as the last one ends. ``takt_paced = true``
    starts every mode's repetitions at their takt slot."""
    sc = load_scenario("multi-subject", {"repetitions": "2", "modes": "hrc",
                                         "takt_paced": str(takt_paced).lower()})
    assert sc.protocol.pacing.takt_paced is takt_paced
    run = run_subject(sc, 0, 0, ("hrc",)).runs["hrc"]
    first_end = max(a.t_end for a in run.allocations if a.repetition == 1)
    assert first_end < sc.protocol.pacing.takt - 5.0  # shorter than the takt, so the two readings differ
    expected = sc.protocol.pacing.takt if takt_paced else first_end
    assert _repetition_starts(run)[1] == pytest.approx(expected, abs=1.0 / sc.protocol.sensing.mocap_rate)


def test_the_multi_subject_scenario_paces_hrc_by_the_robot():
    assert load_scenario("multi-subject").protocol.pacing.takt_paced is False


def test_every_mode_covers_the_production_schedule(hrc_run):
    """A worker who finishes early rests to the end of repetitions × takt, so load proxies compare."""
    cfg, res = hrc_run
    for run in res.runs.values():
        assert run.horizon == pytest.approx(2 * cfg.pacing.takt)
        assert run.ticks.column("t")[-1] >= run.horizon - 1.0 / cfg.sensing.ergonomics_rate
        assert run.kwear_integral <= run.kwear_integral_run


def test_robot_rests_the_worker(hrc_run):
    """While the robot works the worker rests: KWear decays (eq. 5) over every robot-only stretch."""
    _, res = hrc_run
    run = res.runs["hrc"]
    t, acting, v = run.ticks.column("t"), run.ticks.column("acting"), run.ticks.kwear
    robot = [a for a in run.allocations if a.agent == "robot"]
    assert robot, "the robot got no action in two repetitions"
    for a in robot:
        idle = (t > a.t_start) & (t < a.t_end) & (acting == 0)
        both = idle[1:] & idle[:-1]  # consecutive resting ticks (the worker acts at a handover)
        assert both.sum() > 20
        assert np.all(np.diff(v, axis=0)[both] < 0)


@pytest.mark.slow
def test_same_seed_same_results_serial_or_parallel(kv_two_subjects, tmp_path):
    """The shared two-subject run (one process, tests/conftest.py) against the same run in two processes."""
    a, b = kv_two_subjects.out, tmp_path / "parallel"
    assert kv_two_subjects.code == 0
    assert main(["run", "kwear-validation", "--subjects", "2", "--reps", "1", "--jobs", "2", "--quiet",
                 "--no-plots", *KV_SHORT, "--out", str(b)]) == 0
    for name in ("summary.json", "allocations.csv", "ticks.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    summary = json.loads((a / "summary.json").read_text())
    assert summary["complete"] is True and summary["seed"] == 0
    assert summary["modes"]["hrc"]["repetitions_completed"] == 2


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--set", "tackt=40"], "--set: unknown key 'tackt'"),
        (["--set", "takt=fast"], "takt='fast' is not a number"),
        (["--set", "v_th=1.5"], "v_th must be in (0, 1)"),
        (["--set", "scene.shelf_hieght=2"], "unknown key 'shelf_hieght'"),
        (["--set", "noequals"], "expected KEY=VALUE"),
        (["--reps", "0"], "--reps: must be >= 1"),
    ],
)
def test_bad_settings_are_one_line_errors(args, message, capsys, tmp_path):
    code = main(["run", "kwear-validation", "--out", str(tmp_path), "--quiet", *args])
    err = capsys.readouterr().err
    assert code == 2
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


@pytest.mark.slow
def test_cli_error_has_no_traceback_in_a_subprocess(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "ergosim.cli", "run", "no-such-scenario", "--out",
                           str(tmp_path)], check=False, capture_output=True, text=True)
    assert proc.returncode == 2
    assert "unknown scenario 'no-such-scenario'" in proc.stderr and "Traceback" not in proc.stderr


@pytest.mark.slow
def test_recording_of_a_run_matches_its_ticks_file(kv_run):
    out, rrd, code = kv_run  # the shared run (tests/conftest.py)
    assert code == 0
    verify = subprocess.run([sys.executable, "-m", "rerun", "rrd", "verify", str(rrd)], check=False,
                            capture_output=True, text=True)
    assert verify.returncode == 0, verify.stderr
    reader = RecordingReader(rrd)
    assert any(e.startswith("world/robot/panda_link") for e in reader.entities)
    assert any(e.startswith("world/human/") for e in reader.entities)
    with (out / "ticks.csv").open() as f:
        rows = list(csv.DictReader(f))
    ticks_t = np.array([float(r["t"]) for r in rows])
    for joint in KWEAR_JOINTS:
        t, v = reader.scalars(f"ergonomics/kwear/{joint}")
        np.testing.assert_allclose(t, ticks_t, atol=1e-6)
        np.testing.assert_allclose(v, [float(r[f"kwear_{joint}"]) for r in rows], rtol=1e-8, atol=1e-9)
    for part in ("upper_arm", "trunk", "neck"):
        t, v = reader.scalars(f"ergonomics/rula/{part}")
        assert len(t) > 0 and np.nanmax(v) <= 6


def _robot_share(out, *sets: str) -> tuple[float, float]:
    """Robot share of the decisions with a choice (robot_share_chosen: what the allocator chose, whether the
    robot then managed it or not) and mean human cost, from a real `ergosim run`."""
    args = ["run", "multi-subject", "--mode", "hrc", "--subjects", "4", "--reps", "5", "--seed", "0",
            "--jobs", "2", "--quiet", "--no-plots", "--out", str(out)]
    for s in sets:
        args += ["--set", s]
    assert main(args) == 0
    summary = json.loads((out / "summary.json").read_text())["modes"]["hrc"]
    with (out / "allocations.csv").open() as f:
        human = [float(r["human_cost"]) for r in csv.DictReader(f) if r["action"] != "a5"]
    return summary["robot_share_chosen"], float(np.mean(human))


@pytest.mark.slow
def test_pieces_moved_away_from_the_worker_raise_the_robot_share(tmp_path):
    """Issue 6, layout: S1 and S2 moved from the bench edge beside the worker onto the side table by the
    robot (about 0.25 m farther from the worker) -> higher predicted wear, more actions to the robot.
    Measured: 4 subjects x 5 repetitions, 19/80 -> 21/80 (seeds 1-3 and 12 subjects agree)."""
    near, cost_near = _robot_share(tmp_path / "near")
    far, cost_far = _robot_share(tmp_path / "far", "scene.s1_xy=0.40,0.62", "scene.s2_xy=0.52,0.66")
    assert cost_far > cost_near
    assert far > near

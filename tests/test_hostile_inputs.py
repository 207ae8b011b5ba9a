"""The hostile-input pass of issue 14, one test (or more) per case of its list.

Every bad input that reaches the CLI gets exit status 2, one line naming the file, key or value, and no
traceback; every interrupted or failed run leaves a valid summary.json and CSVs, marked incomplete, and
never a half-written file.
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from ergosim.cli import main
from ergosim.errors import ConfigError, InfeasiblePlanError, TaskFileError
from ergosim.experiment.run_folder import RunFolder
from ergosim.planner import Agent, AndOrGraph, Operation, generate_task, limits, load_task
from ergosim.planner.taskfile import parse_task
from ergosim.viz import recorder, sinks
from ergosim.worker.bvh_parse import parse_bvh_text

ROOT = Path(__file__).resolve().parents[1]
BVH = ROOT / "tests" / "data" / "reach_overhead.bvh"
KV = ["run", "kwear-validation", "--reps", "1", "--mode", "hrc", "--jobs", "1", "--quiet"]


def _one_line_error(capsys, code: int, *needles: str) -> str:
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("ergosim: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err
    for needle in needles:
        assert needle in err, err
    return err


def _cli(args: list[str], timeout: float = 240.0, **kw) -> subprocess.CompletedProcess:
    env = {**os.environ, "MUJOCO_GL": "egl", **kw.pop("env", {})}
    return subprocess.run([sys.executable, "-m", "ergosim.cli", *args], capture_output=True, text=True,
                          timeout=timeout, env=env, check=False, **kw)


def _valid_outputs(out: Path) -> dict:
    """Every output is whole: parseable JSON/CSV, no temporary file left. Returns summary.json."""
    assert not list(out.glob(".*.tmp"))
    summary = json.loads((out / "summary.json").read_text())
    for name in ("allocations.csv", "failures.csv"):
        with (out / name).open() as f:
            rows = list(csv.reader(f))
        assert rows and all(len(r) == len(rows[0]) for r in rows), name
    return summary


# -- 1. hangs: a recorder that cannot deliver, a viewer that cannot open -------------------------------------
def test_connect_to_a_dead_port_fails_after_a_bounded_flush_with_the_results_written(tmp_path, capsys,
                                                                                    monkeypatch):
    """In-process, with the flush bound cut from its default to 2 s: the run waits that long, no longer."""
    assert 0 < recorder._FLUSH_TIMEOUT < 280
    monkeypatch.setattr(recorder, "_FLUSH_TIMEOUT", 2.0)
    out = tmp_path / "x"
    start = time.monotonic()
    code = main([*KV, "--connect", "rerun+http://127.0.0.1:9/proxy", "--out", str(out)])
    printed = capsys.readouterr()
    assert code == 2, printed.err
    assert "ergosim: error: --spawn/--connect: the recording did not reach the viewer" in printed.err
    assert "Traceback" not in printed.err
    assert time.monotonic() - start < 280
    summary = _valid_outputs(out)
    assert summary["complete"] is True and (out / "ticks.csv").is_file()
    assert "results:" in printed.out  # the summary is printed before the error


def test_spawn_without_a_display_is_refused_before_the_run(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    out = tmp_path / "x"
    code = main([*KV, "--spawn", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "--spawn: cannot open a viewer: no display" in err
    assert not out.exists()


# -- 2. the spawned viewer listens on the loopback interface only --------------------------------------------
def test_spawn_binds_the_viewer_to_127_0_0_1(monkeypatch):
    calls = []

    class FakeViewer:
        returncode = None

        def __init__(self, args, **kw):
            calls.append(args)

        def poll(self):
            return None

    answers = iter([False, True])
    monkeypatch.setattr(sinks, "_listening", lambda port: next(answers))
    monkeypatch.setattr(sinks.subprocess, "Popen", FakeViewer)
    monkeypatch.setenv("DISPLAY", ":0")
    assert isinstance(sinks.spawn_viewer(9876, wait=5.0), FakeViewer)
    args = calls[0]
    assert args[args.index("--bind") + 1] == "127.0.0.1" and args[args.index("--port") + 1] == "9876"
    assert sinks.SPAWN_HOST == "127.0.0.1"


# -- 3. failed robot attempts are never robot actions --------------------------------------------------------
def test_a_robot_out_of_reach_is_refused_before_the_run(tmp_path, capsys):
    """robot_base=3,3,0.85 puts the robot far from its support (the side table): the workcell check refuses
    it before any subject starts (the issue's run printed a robot share of 54.5 %). A robot that does stand
    on its support, at the bench's far corner, but reaches none of its actions is refused by the
    reachability pre-check."""
    out = tmp_path / "far"
    code = main(["run", "multi-subject", "--subjects", "1", "--reps", "1", "--mode", "r-only", "--jobs", "1",
                 "--quiet", "--set", "scene.robot_base=3,3,0.85", "--out", str(out)])
    _one_line_error(capsys, code, "robots.robot.base: the robot base at xy=(3.0, 3.0) is not over its "
                                  "support side_table")
    code = main(["run", "multi-subject", "--subjects", "1", "--reps", "1", "--mode", "r-only", "--jobs", "1",
                 "--quiet", *FAR_ROBOT, "--out", str(out)])
    _one_line_error(capsys, code, "robot 'robot' at [0.94, -0.5, 0.9] reaches none of the 4 actions")
    assert not out.exists()


FAR_ROBOT = ["--set", "scene.robot_base=0.94,-0.5,0.9", "--set", "scene.robots.robot.support=bench"]
"""The Panda on the bench's far right corner: every piece and the handover pose are out of its reach."""


def test_failed_robot_attempts_do_not_count_as_robot_actions(tmp_path, monkeypatch):
    """The same cell run from Python, past the CLI's pre-check and with the robot's contract not asked (its
    refusals would take every action from it before the physics): r-only sends the robot every action it
    may do, each attempt fails as unreachable in the physics, and the robot share stays 0."""
    import ergosim.experiment.runner as runner  # noqa: PLC0415
    from ergosim.experiment.scenario import load_scenario  # noqa: PLC0415
    from ergosim.experiment.scenario_run import run_scenario  # noqa: PLC0415
    from ergosim.experiment.summary_text import summary_text  # noqa: PLC0415

    monkeypatch.setattr(runner, "robot_refusals", lambda task, cell: {})
    scenario = load_scenario("multi-subject", {"subjects": "1", "repetitions": "1", "modes": "r-only",
                                               "scene.robot_base": "0.94,-0.5,0.9",
                                               "scene.robots.robot.support": "bench"})
    out = tmp_path / "far"
    result = run_scenario(scenario, seed=0, out=out, jobs=1, progress=False)
    assert result.status == "abandoned"
    m = _valid_outputs(out)["modes"]["r-only"]
    assert m["robot_actions"] == 0 and m["robot_share"] == 0.0
    assert m["robot_failures"] >= 1 and m["worker_failures"] == 0
    assert m["repetitions_abandoned"] == 1
    with (out / "failures.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert {r["status"] for r in rows if r["agent"] == "robot"} == {"failed:unreachable"}
    printed = summary_text(result.summary, scenario.protocol)
    assert "WARNING: r-only:" in printed and "robot failure(s)" in printed


# -- 4. impossible runs: exit 3, complete false, abandoned repetitions named --------------------------
def test_a_run_with_an_abandoned_repetition_exits_3_and_says_why(tmp_path, capsys):
    out = tmp_path / "l"
    code = main(["run", "multi-subject", "--subjects", "1", "--reps", "2", "--mode", "h-only", "--jobs", "1",
                 "--quiet", "--set", "scene.l_xy=0.72,1.03", "--set", "scene.worker.standing_area=0,0,0,0",
                 "--set", "scene.worker.max_turn=0", "--out", str(out)])  # L beyond a planted worker's reach
    printed = capsys.readouterr()
    assert code == 3
    summary = _valid_outputs(out)
    assert summary["complete"] is False and summary["status"] == "abandoned"
    reps = summary["modes"]["h-only"]["repetitions"]
    assert [r["outcome"] for r in reps] == ["abandoned", "not_run"]
    assert "a2" in reps[0]["reason"] and reps[1]["reason"] == "repetition 1 was abandoned"
    assert summary["modes"]["h-only"]["repetitions_completed"] == 0
    assert json.loads((out / "run.json").read_text())["status"] == "abandoned"
    assert "[INCOMPLETE: repetitions abandoned]" in printed.out
    assert "subject 0 rep 1" in printed.out and "abandoned" in printed.out
    assert "exit status 3" in printed.err and "Traceback" not in printed.err
    with (out / "allocations.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert any(r["status"] == "pruned" and r["action"] == "a2" for r in rows)


# -- 5. a run owns its folder -----------------------------------------------------------------------------
def _earlier_run(out: Path) -> None:
    out.mkdir(parents=True)
    (out / "summary.json").write_text(json.dumps({"complete": True, "scenario": "earlier"}))
    (out / "kwear_timeline_rula.png").write_bytes(b"old plot")
    (out / "kwear_state_s3_rula.json").write_text("{}")
    (out / "extra_from_the_earlier_run.csv").write_text("x\n")
    (out / "run.json").write_text(json.dumps({"files": ["extra_from_the_earlier_run.csv", "../escape"]}))
    (out / "my_notes.txt").write_text("mine")


def test_a_run_removes_what_an_earlier_run_left_and_keeps_other_files(tmp_path):
    out = tmp_path / "o"
    _earlier_run(out)
    (tmp_path / "escape").write_text("outside")
    folder = RunFolder(out, scenario="kwear-validation", seed=0)
    folder.claim({})
    left = sorted(p.name for p in out.iterdir())
    assert left == ["my_notes.txt", "run.json"]
    manifest = json.loads((out / "run.json").read_text())
    assert manifest["status"] == "running"
    assert "kwear_timeline_rula.png" in manifest["removed_from_earlier_run"]
    assert (tmp_path / "escape").read_text() == "outside"  # a manifest cannot point outside the folder


@pytest.mark.slow
def test_interrupting_a_run_over_an_earlier_complete_one_leaves_no_stale_complete_summary(tmp_path):
    out = tmp_path / "o"
    _earlier_run(out)
    proc = subprocess.Popen([sys.executable, "-m", "ergosim.cli", *KV, "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "MUJOCO_GL": "egl"})
    deadline = time.monotonic() + 60
    while not (out / "run.json").exists() or "running" not in (out / "run.json").read_text():
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "interrupted" in err
    summary = _valid_outputs(out)
    assert summary["complete"] is False and summary["status"] == "interrupted"
    assert summary["subjects_finished"] == 0
    assert json.loads((out / "run.json").read_text())["status"] == "interrupted"
    assert not (out / "kwear_timeline_rula.png").exists() and (out / "my_notes.txt").exists()


# -- 6. unwritable output is found before the first tick --------------------------------------------------
def _read_only_dir(tmp_path: Path) -> Path:
    if os.geteuid() == 0:  # root writes through permission bits; sysfs refuses new files even to root
        return Path("/sys")
    d = tmp_path / "ro"
    d.mkdir()
    d.chmod(0o555)
    return d


def test_output_on_a_read_only_directory_is_refused_before_the_run(tmp_path, capsys):
    target = _read_only_dir(tmp_path)
    start = time.monotonic()
    code = main([*KV, "--out", str(target)])
    _one_line_error(capsys, code, "--out", str(target))
    assert time.monotonic() - start < 30  # refused at once, not after a simulation


def test_output_on_an_existing_file_is_refused(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    code = main([*KV, "--out", str(f)])
    _one_line_error(capsys, code, "--out", "exists and is not a directory")
    assert f.read_text() == "x"


# -- 7. one-line errors, with value counts for tuples ----------------------------------------------------
@pytest.mark.parametrize(
    ("args", "needles"),
    [
        (["--seed", "-1"], ["--seed", "-1"]),
        (["--set", "scene.robot_base=0,0"], ["robot_base='0,0' has 2 values, expected 3"]),
        (["--set", "scene.robot_base="], ["robot_base='' has 0 values, expected 3"]),
        (["--set", "scene.l_xy="], ["l_xy='' has 0 values, expected 2"]),
        (["--set", "scene.l_xy=1"], ["l_xy='1' has 1 value, expected 2"]),
        (["--set", "scene.l_xy=1,,2"], ["l_xy='1,,2' has an empty value"]),
        (["--set", "scene.human_scale=2"], ["human_scale='2'", "name:value"]),
        (["--set", "scene.human_scale=upper_arm:x"], ["'x' is not a number"]),
        (["--set", "fixed_sequence=true"], ["unknown key 'fixed_sequence'"]),
        (["--set", "noise_scale=-1"], ["noise_scale must be >= 0"]),
    ],
)
def test_bad_run_inputs_are_one_line_errors(args, needles, capsys, tmp_path):
    out = tmp_path / "never"
    code = main(["run", "multi-subject", "--subjects", "1", "--reps", "1", "--quiet", "--out", str(out),
                 *args])
    _one_line_error(capsys, code, *needles)
    assert not out.exists()


def test_seed_minus_one_in_plan_is_one_line(capsys):
    _one_line_error(capsys, main(["plan", "--generate", "sequential:5", "--seed", "-1"]), "--seed", "-1")
    _one_line_error(capsys, main(["plan", "corner-joint", "--seed", "-1"]), "--seed")


# -- 8. cost overflow ---------------------------------------------------------------------------------
_OVERFLOW = """
parts = ["a", "b", "c"]
[agents.human]
kind = "human"
[[operations]]
name = "ab"
joins = [["a"], ["b"]]
cost = {human = 1e308}
[[operations]]
name = "abc"
joins = [["a", "b"], ["c"]]
cost = {human = 1e308}
"""


def test_costs_that_would_overflow_are_refused(tmp_path, capsys):
    task = tmp_path / "overflow.toml"
    task.write_text(_OVERFLOW)
    _one_line_error(capsys, main(["plan", str(task)]), "operations[0] 'ab'", "1e+100")
    _one_line_error(capsys, main(["plan", "corner-joint", "--costs", "human.a2=1e308"]), "--costs")


def test_an_overflowing_sum_is_diagnosed_not_an_index_error():
    graph = AndOrGraph("t", ["a", "b", "c"], [Agent("human", "human")], [
        Operation("ab", "ab", ("a", "b"), (("a",), ("b",)), ("human",), (1.0,)),
        Operation("abc", "abc", ("a", "b", "c"), (("a", "b"), ("c",)), ("human",), (1.0,)),
    ])
    from ergosim.planner import bottom_up  # noqa: PLC0415

    with pytest.raises(InfeasiblePlanError, match="overflows to inf"):
        bottom_up.solve(graph, np.array(graph.leaves), np.array([1e308, 1e308]))


# -- 9. documented bounds on size, memory and time -----------------------------------------------------
def test_paper_planner_stops_at_its_memory_budget(capsys):
    code = main(["plan", "--generate", "sequential:12", "--planner", "paper", "--max-states", "500"])
    _one_line_error(capsys, code, "--max-states", "--planner fast")


def test_generate_has_a_size_limit(capsys):
    _one_line_error(capsys, main(["plan", "--generate", "sequential:100000"]), "MAX_OPERATIONS")
    _one_line_error(capsys, main(["plan", "--generate", "scarce:99999999999999999999"]), "--generate")


def test_task_files_over_the_operation_limit_are_refused(monkeypatch, tmp_path):
    monkeypatch.setattr(limits, "MAX_OPERATIONS", 10)
    with pytest.raises(TaskFileError, match="MAX_OPERATIONS"):
        parse_task(_chain_task(12))
    with pytest.raises(ConfigError, match="MAX_OPERATIONS"):
        generate_task("sequential:5")  # C(6, 3) = 20 operations


def _chain_task(n: int) -> str:
    lines = ["parts = [" + ",".join(f'"p{i}"' for i in range(n + 1)) + "]", "[agents.human]",
             'kind = "human"']
    for i in range(1, n + 1):
        lines += ["[[operations]]", f'name = "o{i}"',
                  "joins = [[" + ",".join(f'"p{k}"' for k in range(i)) + f'], ["p{i}"]]']
    return "\n".join(lines) + "\n"


def test_a_task_file_of_5000_operations_reads_and_plans(tmp_path):
    """The reader is linear in the file (dict lookups, not list scans); its speed is in
    scripts/bench_taskfile.py. Here: 5000 operations of a balanced binary assembly load and plan exactly."""
    parts = [f"p{i}" for i in range(5001)]
    groups, ops = [[p] for p in parts], []
    while len(groups) > 1:
        nxt = [groups[i] + groups[i + 1] for i in range(0, len(groups) - 1, 2)]
        ops += [(groups[i], groups[i + 1]) for i in range(0, len(groups) - 1, 2)]
        groups = nxt + ([groups[-1]] if len(groups) % 2 else [])
    lines = ["parts = [" + ",".join(f'"{p}"' for p in parts) + "]", "[agents.human]", 'kind = "human"']
    for k, (a, b) in enumerate(ops):
        lines += ["[[operations]]", f'name = "o{k}"', "joins = [[" + ",".join(f'"{p}"' for p in a) + "], ["
                  + ",".join(f'"{p}"' for p in b) + "]]"]
    task = tmp_path / "tree.toml"
    task.write_text("\n".join(lines) + "\n")
    graph = load_task(task)
    assert len(graph.operations) == 5000
    assert graph.plan().cost == 5000.0


def test_eta_max_is_bounded(capsys, tmp_path):
    code = main(["run", "kwear-validation", "--quiet", "--out", str(tmp_path / "n"),
                 "--set", "eta_max=100000"])
    _one_line_error(capsys, code, "eta_max must be <= 50")


# -- 10. ee_speed is bounded by the robot's Cartesian limit --------------------------------------------
def test_ee_speed_is_bounded_by_the_robot(capsys, tmp_path):
    code = main(["run", "kwear-validation", "--quiet", "--out", str(tmp_path / "n"),
                 "--set", "ee_speed=100", "--set", "transit_speed=100"])
    _one_line_error(capsys, code, "ee_speed must be at most 1.7 m/s (the panda's Cartesian limit")
    code = main(["run", "kwear-validation", "--quiet", "--out", str(tmp_path / "n"),
                 "--set", "transit_speed=1.5", "--set", "scene.robots.robot.model=ur5"])
    _one_line_error(capsys, code, "transit_speed must be at most 1 m/s (the ur5's Cartesian limit")
    from ergosim.experiment.scenario import scenario_config  # noqa: PLC0415
    from ergosim.overrides import apply_overrides  # noqa: PLC0415

    # the bound itself is allowed; contact-critical motion may not outrun the transits (transit_speed)
    fast = apply_overrides(scenario_config("kwear-validation"), {"ee_speed": "1.7", "transit_speed": "1.7"})
    assert (fast.robot.ee_speed, fast.robot.transit_speed) == (1.7, 1.7)


# -- 11. interruption ------------------------------------------------------------------------------------
def _wait_for_subjects(out: Path, n: int, proc: subprocess.Popen, timeout: float = 240.0) -> None:
    deadline = time.monotonic() + timeout
    while True:
        assert proc.poll() is None and time.monotonic() < deadline
        try:
            if json.loads((out / "summary.json").read_text()).get("subjects_finished", 0) >= n:
                return
        except (OSError, ValueError):
            pass
        time.sleep(0.1)


@pytest.mark.slow
def test_ctrl_c_with_two_jobs_prints_no_worker_traceback(tmp_path):
    out = tmp_path / "o"
    proc = subprocess.Popen([sys.executable, "-m", "ergosim.cli", "run", "kwear-validation", "--subjects",
                             "2", "--reps", "1", "--mode", "hrc", "--jobs", "2", "--quiet",
                             "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "MUJOCO_GL": "egl"}, start_new_session=True)
    deadline = time.monotonic() + 120
    while not (out / "run.json").exists() or "running" not in (out / "run.json").read_text():
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.05)
    time.sleep(3.0)  # the workers are started and simulating
    assert proc.poll() is None
    os.killpg(proc.pid, signal.SIGINT)  # what a terminal's Ctrl-C does: the whole process group
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err
    assert err.strip().splitlines()[-1] == "ergosim: interrupted"
    summary = _valid_outputs(out)
    assert summary["complete"] is False and summary["status"] == "interrupted", (summary["status"], err)


@pytest.mark.slow
def test_sigterm_writes_the_finished_subjects_like_sigint(tmp_path):
    out = tmp_path / "o"
    proc = subprocess.Popen([sys.executable, "-m", "ergosim.cli", "run", "kwear-validation", "--subjects",
                             "3", "--reps", "1", "--mode", "hrc", "--jobs", "1", "--quiet",
                             "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "MUJOCO_GL": "egl"})
    _wait_for_subjects(out, 1, proc)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert "Traceback" not in err and "interrupted by SIGTERM" in err
    summary = _valid_outputs(out)
    assert summary["complete"] is False and summary["status"] == "interrupted"
    assert 1 <= summary["subjects_finished"] < 3
    assert (out / "ticks.csv").is_file() and (out / "kwear_timeline_hrc.png").is_file()
    with (out / "ticks.csv").open() as f:
        subjects = {r["subject"] for r in csv.DictReader(f)}
    assert len(subjects) == summary["subjects_finished"]
    assert json.loads((out / "run.json").read_text())["status"] == "interrupted"


def test_an_early_error_leaves_no_empty_output_folder(tmp_path, capsys):
    out = tmp_path / "deep" / "new"
    code = main(["run", "kwear-validation", "--reps", "1", "--mode", "hrc", "--jobs", "1", "--quiet",
                 "--set", "scene.human_scale=arm:1.1", "--out", str(out)])
    _one_line_error(capsys, code, "unknown segment scale 'arm'")
    assert not (tmp_path / "deep").exists()


# -- 12. special files -----------------------------------------------------------------------------------
@pytest.fixture()
def fifo(tmp_path):
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


@pytest.mark.parametrize("command", ["replay", "plan"])
def test_dev_zero_and_a_fifo_are_refused_not_read(command, fifo):
    for path in ("/dev/zero", str(fifo)):
        proc = _cli([command, path], timeout=60)
        assert proc.returncode == 2, proc.stderr
        assert "not a regular file" in proc.stderr and proc.stderr.count("\n") == 1
        assert path in proc.stderr


def test_large_files_are_refused_by_size(monkeypatch, tmp_path):
    from ergosim.planner import taskfile  # noqa: PLC0415
    from ergosim.worker import bvh_parse  # noqa: PLC0415

    monkeypatch.setattr(taskfile, "MAX_TASK_BYTES", 100)
    monkeypatch.setattr(bvh_parse, "MAX_BVH_BYTES", 100)
    task = tmp_path / "t.toml"
    task.write_text(_OVERFLOW)
    with pytest.raises(TaskFileError, match="more than the limit of 100"):
        load_task(task)
    from ergosim.errors import RecordingError  # noqa: PLC0415

    with pytest.raises(RecordingError, match="more than the limit of 100"):
        bvh_parse.parse_bvh(BVH)


# -- 13. minor --------------------------------------------------------------------------------------------
def test_reps_and_set_repetitions_together_are_refused(capsys, tmp_path):
    code = main(["run", "kwear-validation", "--reps", "2", "--set", "repetitions=3", "--quiet",
                 "--out", str(tmp_path / "n")])
    _one_line_error(capsys, code, "--reps 2 and --set repetitions=3 both set repetitions")
    code = main(["run", "kwear-validation", "--mode", "hrc", "--set", "modes=rula", "--quiet",
                 "--out", str(tmp_path / "n")])
    _one_line_error(capsys, code, "--mode")


def test_a_tab_inside_frame_time_is_accepted():
    text = BVH.read_text()
    ref = parse_bvh_text(text)
    for variant in ("Frame\tTime:\t", "Frame Time:\t", "Frame \t Time:  "):
        lines = [(variant + ln.split(":", 1)[1].strip()) if ln.startswith("Frame Time:") else ln
                 for ln in text.splitlines()]
        data = parse_bvh_text("\n".join(lines))
        assert data.frame_time == ref.frame_time
        np.testing.assert_array_equal(data.motion, ref.motion)

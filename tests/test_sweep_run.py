"""Running sweeps (issue 15): local and Ray give the same rows, a killed sweep resumes with no unit lost or
duplicated, failed units are recorded, a unit equals the same subject in ``ergosim run``, and the tables,
statistics and figures are consistent with the units. Short units: 1 repetition, one mode."""

from __future__ import annotations

import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import extension_mode  # noqa: F401 - registers the user's mode "peak" (tests/extension_mode.py)
import numpy as np
import pyarrow.parquet as pq
import pytest
import ray

from ergosim.cli import main
from ergosim.sweep import load_sweep, plan_units, run_sweep
from ergosim.sweep.compare import compare_folders, read_folder

SMALL = """
    name = "small"
    scenario = "kwear-validation"
    subjects = 2
    seeds = [0]
    modes = ["hrc"]
    metrics = ["robot_share", "kwear_integral", "time_above_vth", "rula_g.a1"]
    [set]
    repetitions = 1
    eta_max = 2               # a short calibration: the units stay short, the loop is the real one
    [grid]
    scene.shelf_height = [1.45, 1.6]
    robot_cost = [25.0, 50.0]
"""


def _sweep_file(tmp: Path, text: str = SMALL, name: str = "small.toml") -> Path:
    path = tmp / name
    path.write_text(textwrap.dedent(text))
    return path


def _cli(args: list[str], **kw) -> subprocess.Popen:
    env = {**os.environ, "MUJOCO_GL": "egl"}
    return subprocess.Popen([sys.executable, "-m", "ergosim.cli", *args], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kw)


@pytest.fixture(scope="module")
def local(tmp_path_factory):
    """The small sweep (2 x 2 cells, 2 subjects, 1 repetition, hrc) with the local executor, 2 processes."""
    tmp = tmp_path_factory.mktemp("local")
    path = _sweep_file(tmp)
    out = tmp / "out"
    assert main(["sweep", str(path), "--out", str(out), "--jobs", "2", "--quiet"]) == 0
    return path, out, pq.read_table(out / "results.parquet")


@pytest.mark.slow
def test_results_have_one_row_per_unit_with_the_issue_columns(local):
    path, out, table = local
    sweep = load_sweep(path)
    assert table.num_rows == sweep.n_units == 8
    assert table.column("unit").to_pylist() == [u.id for u in plan_units(sweep)]
    cols = set(table.column_names)
    assert {"param.scene.shelf_height", "param.robot_cost", "subject", "mode", "seed", "status", "error",
            "robot_share", "robot_share.a1", "robot_share.a5", "kwear_integral", "time_above_vth",
            "kwear_mean", "takt_overruns", "duration", "robot_failures", "worker_failures"} <= cols
    rows = table.to_pylist()
    assert {r["status"] for r in rows} == {"complete"}
    assert {(r["param.scene.shelf_height"], r["param.robot_cost"]) for r in rows} == {
        (1.45, 25.0), (1.45, 50.0), (1.6, 25.0), (1.6, 50.0)}
    for r in rows:
        assert r["duration"] >= 38.0 - 1e-9 and r["kwear_integral"] > 0 and 0 <= r["robot_share"] <= 1
        assert r["repetitions_completed"] == 1
    manifest = json.loads((out / "sweep.json").read_text())
    assert manifest["status"] == "complete" and manifest["units_finished"] == 8 and manifest["units_run"] == 8
    assert (out / "sweep.toml").read_text() == path.read_text()
    assert len(list((out / "units").glob("*.json"))) == 8 and not list(out.glob("units/.*.tmp"))
    alloc = pq.read_table(out / "allocations.parquet").to_pylist()
    assert {a["unit"] for a in alloc} == set(table.column("unit").to_pylist())
    assert all(a["status"] == "done" or a["status"].startswith("failed:") for a in alloc)


@pytest.mark.slow
def test_cells_hold_means_and_intervals_of_their_units(local):
    _, out, table = local
    cells = pq.read_table(out / "cells.parquet").to_pylist()
    rows = table.to_pylist()
    assert len(cells) == 4 and {c["units"] for c in cells} == {2}
    for c in cells:
        mine = [r["kwear_integral"] for r in rows if r["cell"] == c["cell"]]
        assert c["kwear_integral.mean"] == pytest.approx(np.mean(mine))
        assert c["kwear_integral.n"] == 2
        assert c["kwear_integral.ci_low"] <= c["kwear_integral.mean"] <= c["kwear_integral.ci_high"]
        assert c["baseline"] is None and c["kwear_integral.wilcoxon_p"] is None  # one mode: no test


@pytest.mark.slow
def test_a_response_plot_per_axis_and_a_heat_map(local):
    _, out, _ = local
    names = sorted(p.name for p in out.glob("*.png"))
    assert names == ["heatmap_scene.shelf_height__robot_cost.png", "response_robot_cost.png",
                     "response_scene.shelf_height.png"]
    for name in names:
        assert (out / name).stat().st_size > 20_000


@pytest.mark.slow
def test_local_and_ray_give_the_same_rows(local, tmp_path):
    """The issue's proof: the same sweep on a local Ray instance of 2 CPUs started by the test."""
    path, _, reference = local
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        result = run_sweep(load_sweep(path), tmp_path / "ray", executor="ray", progress=False)
        # a second driver joins the running instance as a cluster, by address (`--ray-address`); half the
        # units are found done, the rest run on the cluster
        address = ray.get_runtime_context().gcs_address
        for done in sorted((tmp_path / "ray" / "units").glob("*.json"))[:4]:
            (tmp_path / "cluster" / "units").mkdir(parents=True, exist_ok=True)
            (tmp_path / "cluster" / "units" / done.name).write_bytes(done.read_bytes())
        proc = _cli(["sweep", str(path), "--out", str(tmp_path / "cluster"), "--executor", "ray",
                     "--ray-address", address, "--quiet"])
        # a mode registered by the user's module reaches the Ray workers too
        one_unit = {'modes = ["hrc"]': 'modes = ["peak"]', "subjects = 2": "subjects = 1",
                    "robot_cost = [25.0, 50.0]": "robot_cost = [50.0]",
                    "scene.shelf_height = [1.45, 1.6]": "scene.shelf_height = [1.45]"}
        text = SMALL
        for old, new in one_unit.items():
            text = text.replace(old, new)
        peak = load_sweep(_sweep_file(tmp_path, text, "peak.toml"))
        on_ray = run_sweep(peak, tmp_path / "peak-ray", executor="ray", progress=False)
        _, err = proc.communicate(timeout=300)
    finally:
        ray.shutdown()
    assert on_ray.status == "complete", pq.read_table(tmp_path / "peak-ray" / "results.parquet").to_pylist()
    assert run_sweep(peak, tmp_path / "peak-local", jobs=1, progress=False).status == "complete"
    assert pq.read_table(tmp_path / "peak-ray" / "results.parquet").equals(
        pq.read_table(tmp_path / "peak-local" / "results.parquet"))
    assert result.status == "complete" and result.executor["executor"] == "ray" and result.ran == 8
    assert result.executor["workers"] == 2
    table = pq.read_table(tmp_path / "ray" / "results.parquet")
    assert table.equals(reference)
    assert pq.read_table(tmp_path / "ray" / "cells.parquet").equals(pq.read_table(local[1] / "cells.parquet"))
    assert proc.returncode == 0, err
    manifest = json.loads((tmp_path / "cluster" / "sweep.json").read_text())
    assert manifest["executor"]["ray_address"] == address and manifest["units_run"] == 4
    assert pq.read_table(tmp_path / "cluster" / "results.parquet").equals(reference)


@pytest.mark.slow
def test_ray_executor_starts_and_stops_its_own_instance(tmp_path, capsys):
    """Through the CLI: `--executor ray` with no address starts a local Ray and shuts it down after."""
    path = _sweep_file(tmp_path, SMALL.replace("subjects = 2", "subjects = 1").replace(
        "robot_cost = [25.0, 50.0]", "robot_cost = [25.0]"))
    code = main(["sweep", str(path), "--out", str(tmp_path / "out"), "--executor", "ray", "--jobs", "2",
                 "--quiet"])
    assert code == 0, capsys.readouterr().err
    assert not ray.is_initialized()
    manifest = json.loads((tmp_path / "out" / "sweep.json").read_text())
    assert manifest["executor"]["executor"] == "ray" and manifest["executor"]["ray_address"] == "local"
    assert manifest["units_finished"] == 2


@pytest.mark.slow
def test_a_killed_sweep_resumes_with_no_unit_lost_or_duplicated(local, tmp_path, capsys):
    path, _, reference = local
    out = tmp_path / "out"
    proc = _cli(["sweep", str(path), "--out", str(out), "--jobs", "2", "--quiet"], start_new_session=True)
    deadline = time.monotonic() + 240
    while len(list((out / "units").glob("*.json"))) < 3 and time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)  # the sweep and its worker processes, with no chance to clean up
    proc.wait(timeout=30)
    before = {p.name: p.stat().st_mtime_ns for p in (out / "units").glob("*.json")}
    assert 3 <= len(before) < 8
    assert main(["sweep", str(path), "--out", str(out), "--jobs", "2"]) == 0
    err = capsys.readouterr().err
    assert f"{len(before)}/8" in err and "unit/s" in err  # the progress bar: done/total and throughput
    table = pq.read_table(out / "results.parquet")
    ids = table.column("unit").to_pylist()
    assert len(ids) == len(set(ids)) == 8 and table.equals(reference)
    after = {p.name: p.stat().st_mtime_ns for p in (out / "units").glob("*.json")}
    assert len(after) == 8 and all(after[name] == t for name, t in before.items())  # not run again
    manifest = json.loads((out / "sweep.json").read_text())
    assert manifest["units_skipped_at_start"] == len(before) and manifest["units_run"] == 8 - len(before)
    assert not list((out / "units").glob(".*.tmp"))


@pytest.mark.slow
def test_sigterm_stops_the_sweep_and_keeps_the_finished_units(local, tmp_path):
    path, _, reference = local
    out = tmp_path / "out"
    proc = _cli(["sweep", str(path), "--out", str(out), "--jobs", "1", "--quiet"])
    deadline = time.monotonic() + 240
    while not list((out / "units").glob("*.json")) and time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    assert "Traceback" not in err and "interrupted by SIGTERM" in err
    manifest = json.loads((out / "sweep.json").read_text())
    assert manifest["status"] == "interrupted"
    table = pq.read_table(out / "results.parquet")
    n = len(list((out / "units").glob("*.json")))
    assert table.num_rows == n == manifest["units_finished"] >= 1
    ref = {r["unit"]: r for r in reference.to_pylist()}
    assert all(r == ref[r["unit"]] for r in table.to_pylist())


@pytest.mark.slow
def test_a_failed_unit_is_recorded_and_the_sweep_goes_on(tmp_path, capsys):
    """At 2.2 m nobody reaches J on the shelf: those units fail with the reachability error; the 1.6 m cell
    runs. Exit 3; a re-run skips the failed units unless --retry-failed."""
    path = _sweep_file(tmp_path, """
        scenario = "kwear-validation"
        modes = ["hrc"]
        [set]
        repetitions = 1
        eta_max = 2
        [grid]
        scene.shelf_height = [1.6, 2.2]
    """)
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--jobs", "1", "--quiet"]) == 3
    captured = capsys.readouterr()
    assert "1 unit(s) failed" in captured.err and "exit status 3" in captured.err
    rows = pq.read_table(out / "results.parquet").to_pylist()
    assert [r["status"] for r in rows] == ["complete", "failed"]
    assert "cannot reach" in rows[1]["error"] and rows[1]["kwear_integral"] is None
    assert json.loads((out / "sweep.json").read_text())["status"] == "incomplete"
    cells = pq.read_table(out / "cells.parquet").to_pylist()
    assert [(c["units"], c["units_failed"]) for c in cells] == [(1, 0), (1, 1)]
    assert cells[1]["kwear_integral.mean"] is None
    assert main(["sweep", str(path), "--out", str(out), "--quiet"]) == 3
    assert json.loads((out / "sweep.json").read_text())["units_run"] == 0
    assert main(["sweep", str(path), "--out", str(out), "--quiet", "--retry-failed"]) == 3
    assert json.loads((out / "sweep.json").read_text())["units_run"] == 1


@pytest.mark.slow
def test_a_unit_equals_the_same_subject_in_ergosim_run(local, tmp_path, capsys):
    """One cell of the sweep against `ergosim run` with the same --set: the same numbers, paired."""
    _, sweep_out, table = local
    run_out = tmp_path / "run"
    assert main(["run", "kwear-validation", "--subjects", "2", "--reps", "1", "--mode", "hrc", "--jobs", "1",
                 "--quiet", "--set", "scene.shelf_height=1.6", "--set", "robot_cost=50", "--set", "eta_max=2",
                 "--out", str(run_out)]) == 0
    run = read_folder(run_out)
    cell = [r for r in table.to_pylist()
            if r["param.scene.shelf_height"] == 1.6 and r["param.robot_cost"] == 50]
    by_subject = {r["subject"]: r for r in run.rows}
    for r in cell:
        mine = by_subject[r["subject"]]
        for key in ("robot_share", "kwear_integral", "time_above_vth", "kwear_mean", "duration",
                    "takt_overruns", "rula_g.a1", "robot_share.a1"):
            assert mine[key] == r[key], key
    capsys.readouterr()
    # a run against a sweep of four cells: the run against each cell, and the cell of the run's settings
    # has no setting that differs and no difference (at HEAD: "share no cell")
    assert main(["compare", str(run_out), str(sweep_out), "--metric", "kwear_integral", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert len(rows) == 4
    same = [r for r in rows if not r["settings"]]
    assert len(same) == 1 and same[0]["diff"] == 0 and same[0]["cell"].endswith("scene.shelf_height=1.6, "
                                                                                 "robot_cost=50")
    other = next(r for r in rows if r["cell"].endswith("scene.shelf_height=1.45, robot_cost=25"))
    assert [s[0] for s in other["settings"]] == ["robot_cost", "scene.shelf_height"]
    assert other["settings"][1] == ["scene.shelf_height", "1.6", "1.45"]
    assert main(["compare", str(sweep_out), str(run_out), "--a-cell", "scene.shelf_height=1.6",
                 "--a-cell", "robot_cost=50"]) == 0
    assert "settings that differ: none" in capsys.readouterr().out
    rows = compare_folders(read_folder(sweep_out), read_folder(sweep_out))
    assert all(r["diff"] == 0 and r["test"] == "wilcoxon" and r["p"] == 1.0 for r in rows)


def test_compare_two_cells_of_one_sweep_says_which_settings_differ(local, capsys):
    """The question a layout engineer asks first: one sweep folder, two of its cells."""
    _, out, table = local
    assert main(["compare", str(out), "--a-cell", "robot_cost=25", "--b-cell", "robot_cost=50",
                 "--metric", "kwear_integral"]) == 0
    text = capsys.readouterr().out
    # the other factor (shelf height) is matched: two comparisons, each 25 -> 50 at one shelf height
    assert text.count("settings that differ (A -> B): robot_cost 25 -> 50") == 2
    assert "A scene.shelf_height=1.45, robot_cost=25  vs  B scene.shelf_height=1.45, robot_cost=50" in text
    assert main(["compare", str(out), "--a-cell", "layout=A", "--b-cell", "robot_cost=50"]) == 2
    err = capsys.readouterr().err
    assert "has no factor 'layout'" in err and "scene.shelf_height: 1.45 | 1.6" in err
    assert main(["compare", str(out)]) == 2
    assert "give a second folder, or --a-cell and --b-cell" in capsys.readouterr().err


def test_compare_warns_about_an_interrupted_or_crashed_folder(local, tmp_path, capsys):
    _, out, _ = local
    crashed = tmp_path / "crashed"
    shutil.copytree(out, crashed)
    manifest = json.loads((crashed / "sweep.json").read_text())
    (crashed / "sweep.json").write_text(json.dumps({**manifest, "status": "running"}))
    assert main(["compare", str(out), str(crashed), "--metric", "kwear_integral"]) == 0
    err = capsys.readouterr().err
    assert f"ergosim: warning: {crashed}: the sweep still running, or was killed" in err
    (crashed / "sweep.json").write_text(json.dumps({**manifest, "status": "interrupted"}))
    assert main(["compare", str(out), str(crashed), "--metric", "kwear_integral", "--json"]) == 0
    captured = capsys.readouterr()
    assert "was interrupted (Ctrl-C or SIGTERM); only the units it finished are compared" in captured.err
    assert json.loads(captured.out)["warnings"] == [captured.err.split("warning: ")[1].strip()]


@pytest.mark.slow
def test_a_unit_keeps_each_failures_message(forced_run, tmp_path):
    """The forced run's cell as a sweep: the worker fails a2 in every repetition (L out of reach of planted
    feet). allocations.parquet says ``failed:...``; failures.parquet keeps what went wrong in words, the same
    rows as the run's failures.csv."""
    path = _sweep_file(tmp_path, """
        scenario = "multi-subject"
        subjects = 1
        seeds = [0]
        modes = ["hrc"]
        [set]
        repetitions = 2
        robot_cost = 50
        "scene.l_xy" = [0.14, 0.88]
        "scene.worker.standing_area" = [0, 0, 0, 0]
        "scene.worker.max_turn" = 0
    """)
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--jobs", "1", "--quiet"]) == 0
    attempts = pq.read_table(out / "allocations.parquet").to_pylist()
    assert any(a["status"].startswith("failed:") for a in attempts)
    failures = pq.read_table(out / "failures.parquet").to_pylist()
    with (forced_run.out / "failures.csv").open(encoding="utf-8", newline="") as f:
        expected = list(csv.DictReader(f))
    assert failures and len(failures) == len(expected)
    for got, want in zip(failures, expected, strict=True):
        assert (got["repetition"], got["action"], got["agent"], got["status"], got["message"]) == (
            int(want["repetition"]), want["action"], want["agent"], want["status"], want["message"])
        assert got["time"] == pytest.approx(float(want["time"]), abs=1e-4) and len(got["message"]) > 20
    unit = json.loads(next((out / "units").glob("*.json")).read_text())
    assert [row[-1] for row in unit["failures"]] == [w["message"] for w in expected]

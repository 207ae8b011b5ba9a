"""A user's own product and workcell, written by the test (not bundled), run end to end by ``ergosim run
PATH.toml`` (issue 12: "a scenario and workcell file written inside a test runs end to end").
"""

from __future__ import annotations

import csv
import json

import mujoco
import numpy as np
import pytest
from own_product import CELL, TASK, write_block_stl, write_product

from ergosim import api
from ergosim.cli import main
from ergosim.errors import ConfigError
from ergosim.experiment.scenario import load_scenario


@pytest.mark.slow
def test_a_scenario_with_its_own_task_and_workcell_files_runs_end_to_end(tmp_path, capsys):
    scenario = write_product(tmp_path / "mine")
    out = tmp_path / "out"
    code = main(["run", str(scenario), "--jobs", "1", "--quiet", "--out", str(out)])
    printed = capsys.readouterr().out
    assert code == 0
    assert "scenario bracket (seed 0)" in printed and "r-only" in printed
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] and summary["action_labels"] == ["b1", "b2", "b3", "b4", "b5"]
    assert summary["config"]["task"] == "bracket" and summary["config"]["scene"] == "bracket-cell"  # names
    modes = summary["modes"]
    assert modes["r-only"]["robot_share"] == 1.0 and modes["h-only"]["robot_share"] == 0.0
    assert all(m["repetitions_completed"] == 1 and m["failed_attempts"] == 0 for m in modes.values())
    with (out / "allocations.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert {r["status"] for r in rows} == {"done"} and len(rows) == 3 * 5
    for name in ("ticks.csv", "failures.csv", "kwear_timeline_hrc.png", "allocation_histogram.png",
                 "kwear_b3.png", "kwear_state_s0_hrc.json"):
        assert (out / name).stat().st_size > 0, name


@pytest.mark.slow
def test_a_scenario_with_inline_task_and_workcell_tables(tmp_path, capsys):
    """One file holds it all: ``[task]`` and ``[workcell]`` tables instead of file names."""
    lines = ['name = "inline"', 'description = "all in one file"', "", "[protocol]",
             'modes = ["r-only"]', "subjects = 1", "repetitions = 1", "robot_cost = 2.5", "eta_max = 2", ""]
    nested = [_nest(TASK, "task"), _nest(CELL, "workcell")]
    path = tmp_path / "inline.toml"
    path.write_text("\n".join(lines + nested))
    sc = load_scenario(path)
    assert sc.task().actions == ("b1", "b2", "b3", "b4", "b5") and sc.cell().name == "bracket-cell"
    out = tmp_path / "out"
    assert main(["run", str(path), "--jobs", "1", "--quiet", "--out", str(out)]) == 0
    capsys.readouterr()
    assert json.loads((out / "summary.json").read_text())["modes"]["r-only"]["robot_actions"] == 5


def _nest(text: str, table: str) -> str:
    """The TOML document ``text`` as the table ``table`` of another document."""
    out, top = [], [f"[{table}]"]
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("[[") and stripped.endswith("]]"):
            out.append(f"[[{table}.{stripped[2:-2]}]]")
        elif stripped.startswith("[") and stripped.endswith("]"):
            out.append(f"[{table}.{stripped[1:-1]}]")
        elif out:
            out.append(line)
        else:
            top.append(line)
    return "\n".join(top + out)


def test_a_part_from_an_stl_mesh(tmp_path, monkeypatch):
    """The base as an STL mesh, named relative to the workcell file; built and handled from elsewhere."""
    write_block_stl(tmp_path / "mine" / "meshes" / "block.stl")
    cell = CELL.replace('shape = "box"\nsize = [0.06, 0.06, 0.04]',
                        'shape = "mesh"\nfile = "meshes/block.stl"\nsize = [0.04, 0.04, 0.03]')
    scenario = write_product(tmp_path / "mine", cell=cell)
    monkeypatch.chdir(tmp_path)
    session = api.session(scenario, "h-only", calibrate=False)
    wc = session.cell
    assert wc.model.geom("base_geom").type == mujoco.mjtGeom.mjGEOM_MESH
    assert abs(wc.body_pose("base")[0][2] - (0.9 + 0.015)) < 1e-9  # resting on the bench by its size
    for action, agent in (("b1", "robot"), ("b2", "human")):
        assert session.perform(action, agent).ok, action
    with pytest.raises(ConfigError, match="no such mesh file"):
        api.workcell(_with(tmp_path / "other", cell.replace("meshes/block.stl", "meshes/none.stl")))


def _with(folder, cell: str):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "cell.toml").write_text(cell)
    return folder / "cell.toml"


def test_the_workers_position_facing_and_hand_come_from_the_cell(tmp_path):
    scenario = write_product(tmp_path)
    sc = load_scenario(scenario, {"scene.worker.hand": "left", "scene.worker.yaw": "20",
                                  "scene.worker.xy": "0.05,0.10"})
    session = api.session(sc, "h-only", calibrate=False)
    wc = session.cell
    pos, quat = wc.body_pose("human_pelvis")
    assert abs(pos[0] - 0.05) < 1e-9 and abs(pos[1] - 0.10) < 1e-9
    assert abs(2 * np.degrees(np.arctan2(quat[3], quat[0])) - 20.0) < 1e-6
    assert session.worker.side == "left" and session.hand == "human_left"
    motion = session.worker.plan(wc, wc.actions["b1"], np.random.default_rng(0), action="b1")
    assert motion.side == "left"
    assert session.perform("b1", "human").ok

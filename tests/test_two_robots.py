"""Zero, one or two robots (issue 12 §2): each robot agent of the task is a Panda of the cell by name.

The first robot keeps the Panda's own names; a second one's bodies, joints and actuators are prefixed with
its name (``robot2.panda_link0``), and every skill drives the robot it is given by name.
"""

from __future__ import annotations

import csv
import json

import pytest
from own_product import CELL, SCENARIO, TASK, two_robots, write_product

from ergosim import api
from ergosim.cli import main
from ergosim.viz import RecordingReader

QUICK = 'modes = ["r-only"]\neta_max = 2'


@pytest.mark.slow
def test_two_robots_each_do_the_actions_the_task_gives_them(tmp_path, capsys):
    task, cell = two_robots()
    scenario = write_product(tmp_path / "two", task=task, cell=cell,
                             scenario=SCENARIO.replace('modes = ["hrc", "h-only", "r-only"]', QUICK))
    out, rrd = tmp_path / "out", tmp_path / "two.rrd"
    assert main(["run", str(scenario), "--jobs", "1", "--quiet",
                 "--no-plots", "--out", str(out), "--rrd", str(rrd)]) == 0
    capsys.readouterr()
    with (out / "allocations.csv").open() as f:
        rows = {r["action"]: r for r in csv.DictReader(f)}
    assert {a: r["agent"] for a, r in rows.items()} == {"b1": "robot", "b2": "robot2", "b3": "robot",
                                                         "b4": "robot", "b5": "robot"}
    assert all(r["status"] == "done" for r in rows.values())
    summary = json.loads((out / "summary.json").read_text())["modes"]["r-only"]
    assert summary["robot_share"] == 1.0 and summary["robot_failures"] == 0
    entities = RecordingReader(rrd).entities
    assert "world/robot/panda_link0" in entities and "world/robot/robot2.panda_link0" in entities


def test_each_robot_moves_only_when_it_acts(tmp_path):
    task, cell = two_robots()
    session = api.session(write_product(tmp_path, task=task, cell=cell), "h-only", calibrate=False)
    wc = session.cell
    assert wc.robots == ("robot", "robot2")
    first, second = wc.robot("robot"), wc.robot("robot2")
    assert second.base == "robot2.panda_link0" and first.base == "panda_link0"
    assert first.arm_ctrl != second.arm_ctrl and first.grip_ctrl != second.grip_ctrl
    idle = wc.data.qpos[first.arm_qpos].copy()
    outcome = session.perform("b1", "robot2")  # the task does not give b1 to robot2: perform does not ask
    assert outcome.ok and wc.action_done(wc.actions["b1"])
    assert abs(wc.data.qpos[first.arm_qpos] - idle).max() < 1e-3  # robot held its ready pose meanwhile
    base = wc.robot_base_pose("robot2")[0]
    assert base[0] == 0.90 and base[1] == -0.35


@pytest.mark.slow
def test_a_cell_without_a_robot_runs_a_task_without_one(tmp_path, capsys):
    task = TASK.replace('[agents.robot]\nkind = "robot"\ncost = 2.5\n', "")
    cell = CELL[:CELL.index("[robots.robot]")] + CELL[CELL.index("[furniture.bench]"):]
    scenario = write_product(tmp_path, task=task, cell=cell, scenario=SCENARIO.replace(
        'modes = ["hrc", "h-only", "r-only"]', 'modes = ["h-only"]\neta_max = 2'))
    assert main(["run", str(scenario), "--jobs", "1", "--quiet",
                 "--no-plots", "--out", str(tmp_path / "out")]) == 0
    capsys.readouterr()
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["complete"] and summary["modes"]["h-only"]["repetitions_completed"] == 1

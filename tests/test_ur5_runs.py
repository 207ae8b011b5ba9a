"""The UR5 through the robot contract, end to end (issue 26): ``ergosim run gearbox --set
scene.robots.robot.model=ur5`` and the multi-subject cell with the UR5, every repetition complete, the UR5
doing the actions its gripper allows (gearbox: insertions and fastenings; multi-subject: hand-overs the
worker takes). Small counts: 1 subject × 2 repetitions, the robot-only mode, so that every action the UR5
may do is asked of it."""

from __future__ import annotations

import csv
import json

import pytest

from ergosim import api
from ergosim.cli import main
from ergosim.robot import get_robot

pytestmark = pytest.mark.slow  # two scenario runs end to end

UR5 = {"scene.robots.robot.model": "ur5"}


def _rows(path):
    with path.open() as f:
        return list(csv.DictReader(f))


def test_ergosim_run_gearbox_with_the_ur5(tmp_path, capsys):
    out = tmp_path / "gearbox-ur5"
    code = main(["run", "gearbox", "--set", "scene.robots.robot.model=ur5", "--set", "eta_max=2",
                 "--subjects", "1", "--reps", "2", "--mode", "r-only", "--jobs", "1", "--quiet", "--no-plots",
                 "--out", str(out)])
    printed = capsys.readouterr()
    assert code == 0
    # the UR5's gripper (55 mm) refuses the gear (60 mm) and the cover (70 mm), before the physics
    opening = get_robot("ur5").gripper.max_opening
    assert 0.05 < opening < 0.06
    said = printed.out + printed.err
    assert "ur5 cannot do g4" in said and "ur5 cannot do g5" in said
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "complete" and summary["repetitions_abandoned"] == 0
    rows = _rows(out / "allocations.csv")
    assert all(r["status"] == "done" for r in rows)
    robot = {r["action"] for r in rows if r["agent"] == "robot"}
    assert robot == {"g2", "g3", "g6", "g7"}  # every action the task and the UR5's gripper allow
    assert {r["repetition"] for r in rows} == {"1", "2"}
    assert not _rows(out / "failures.csv")


def test_the_ur5_on_the_pandas_base_is_refused_before_the_run(capsys):
    """The multi-subject base is the Panda's, at the bench's corner: the UR5's ready pose, where its
    inverse kinematics starts and near which its transits pass, holds its upper arm (its shoulder 0.09 m
    above the side table, the bench 0.05 m higher) inside the bench. Parked, turned away, it cleared the
    bench, and the run used to fail at the first grasp, the arm stopped against the bench; now one line."""
    code = main(["run", "multi-subject", "--set", "scene.robots.robot.model=ur5", "--subjects", "1",
                 "--reps", "1", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert ("robots.robot.base: the robot stands inside furniture 'bench': at its ready pose upper_arm_link"
            in err)


# the UR5 mounted where its ready pose clears the bench, handing over at the paper's pre-planned pose:
# from there S2's presentation at J's x hollow is 0.93 m from its shoulder, beyond its 0.85 m reach
UR5_MOUNTED = {**UR5, "scene.robots.robot.base": "0.62,0.82,0.85",
               **{f"scene.actions.{a}.handover": "handover" for a in ("a1", "a2", "a3", "a4")}}


def test_the_multi_subject_cell_with_the_ur5_hands_parts_over(tmp_path):
    sc = api.load("multi-subject", UR5_MOUNTED, subjects=1, repetitions=2, modes=["r-only"], eta_max=2)
    cell = sc.cell()
    assert [r.model for r in cell.robots] == ["ur5"]
    res = api.run(sc, out=tmp_path / "multi-ur5")
    assert res.status == "complete"
    (run,) = res.runs("r-only")
    assert run.repetitions_completed == 2
    rows = _rows(tmp_path / "multi-ur5" / "allocations.csv")
    handed = [r for r in rows if r["agent"] == "robot"]
    # a1..a4 are hand-overs at the pre-planned pose (a5 is the worker's): every one taken by the worker
    assert sorted({r["action"] for r in handed}) == ["a1", "a2", "a3", "a4"]
    assert len(handed) == 8 and all(r["status"] == "done" for r in handed)
    assert {a.label for a in cell.actions if a.handover is not None} == {"a1", "a2", "a3", "a4"}
    # each hand-over: the UR5 held the part out at the pose until the worker took it
    assert len(run.robot_spans) == 8 and all(waited >= 0 for _, _, _, waited in run.robot_spans)

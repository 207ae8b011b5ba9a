"""Validation before any physics (issue 12): a bad scenario or workcell gets one line naming the file, the
entry and the problem, exit 2, no traceback, and no output folder -- one test per case of the issue.

Each case goes through the command line as a user meets it: a ``--set`` on a bundled scenario, or a user's
own scenario, task and workcell files (``own_product.py``) with one thing wrong.
"""

from __future__ import annotations

import pytest
from own_product import CELL, TASK, two_robots, write_product
from test_hostile_inputs import _one_line_error as one_line_error

from ergosim.cli import main

MS = "ergosim/data/cells/multi-subject.toml"
GB = "ergosim/data/cells/gearbox.toml"


def _refused(capsys, tmp_path, scenario: str, *sets: str, needles: tuple[str, ...]) -> str:
    out = tmp_path / "out"
    argv = ["run", scenario, "--subjects", "1", "--reps", "1", "--jobs", "1", "--quiet", "--out", str(out)]
    for s in sets:
        argv += ["--set", s]
    err = one_line_error(capsys, main(argv), *needles)
    assert not out.exists()  # refused before any subject started
    return err


def _own(tmp_path, **files) -> str:
    return str(write_product(tmp_path / "own", **files))


# -- unknown part, surface or slot ---------------------------------------------------------------------------
def test_unknown_part(capsys, tmp_path):
    _refused(capsys, tmp_path, "multi-subject", "scene.actions.a2.part=K",
             needles=(MS, "actions.a2.part", "unknown part 'K'; parts: J, L, S1, S2"))


def test_unknown_surface(capsys, tmp_path):
    _refused(capsys, tmp_path, "multi-subject", "scene.parts.L.on=drawer",
             needles=(MS, "parts.L.on", "unknown surface 'drawer'; surfaces: bench, side_table, monitor"))


def test_unknown_slot(capsys, tmp_path):
    cell = CELL.replace('target = "base.pin_hole"', 'target = "base.pin_hol"')
    _refused(capsys, tmp_path, _own(tmp_path, cell=cell),
             needles=("bracket_cell.toml", "actions.b2.target",
                      "unknown slot 'base.pin_hol'; slots: base.pin_hole, base.screw_hole"))


# -- overlapping furniture -----------------------------------------------------------------------------------
def test_overlapping_furniture(capsys, tmp_path):
    _refused(capsys, tmp_path, "multi-subject", "scene.monitor_center=0.62,0,0.9",
             needles=(MS, "(with scene.monitor_center=0.62,0,0.9)", "furniture.monitor",
                      "furniture 'bench' and 'monitor' overlap"))


# -- a robot base inside furniture ---------------------------------------------------------------------------
def test_a_robot_buried_in_its_raised_support(capsys, tmp_path):
    """The issue's case: a higher side table used to bury the robot silently."""
    _refused(capsys, tmp_path, "multi-subject", "scene.side_table_height=1.15",
             needles=(MS, "(with scene.side_table_height=1.15)", "robots.robot.base",
                      "below the top of its support side_table (1.15 m): it would stand inside it"))


def test_a_robot_standing_inside_other_furniture(capsys, tmp_path):
    """Standing on the bench but inside the riser: the Panda's own links, at its ready pose, are checked."""
    _refused(capsys, tmp_path, "gearbox", "scene.robot_base=0.48,0.2,0.9",
             needles=(GB, "robots.robot.base", "the robot stands inside furniture 'riser'",
                      "mm inside riser"))


def test_two_robots_standing_in_each_other(capsys, tmp_path):
    task, cell = two_robots()
    cell = cell.replace("base = [0.90, -0.35, 0.9]", "base = [0.90, -0.05, 0.9]")
    _refused(capsys, tmp_path, _own(tmp_path, task=task, cell=cell),
             needles=("bracket_cell.toml", "robots.robot2.base",
                      "robots 'robot' and 'robot2' intersect at their ready poses"))


# -- a part intersecting furniture or floating ---------------------------------------------------------------
def test_a_part_intersecting_furniture(capsys, tmp_path):
    """The housing laid on the bench where the riser stands on it."""
    _refused(capsys, tmp_path, "gearbox", "scene.parts.housing.on=bench", "scene.parts.housing.xy=0.48,0.2",
             needles=(GB, "parts.housing", "the part intersects furniture 'riser'"))


def test_a_part_at_a_pose_inside_its_support(capsys, tmp_path):
    _refused(capsys, tmp_path, "multi-subject", "scene.parts.L.pos=0.26,0.76,0.8",
             needles=(MS, "parts.L.pos", "the part intersects the side_table", "65 mm below the top"))


def test_a_floating_part(capsys, tmp_path):
    _refused(capsys, tmp_path, "multi-subject", "scene.parts.L.pos=0.3,0.7,1.3",
             needles=(MS, "parts.L.pos", "the part floats: its bottom is at z=1.285 m"))


def test_a_part_with_no_surface_under_it(capsys, tmp_path):
    _refused(capsys, tmp_path, "multi-subject", "scene.l_xy=1.5,0.7",
             needles=(MS, "parts.L.xy", "no surface under xy=(1.5, 0.7): the part would float"))


# -- the task and the workcell -------------------------------------------------------------------------------
def test_an_operation_with_no_physical_action(capsys, tmp_path):
    cell = CELL[:CELL.index("[actions.b5]")] + CELL[CELL.index("[aliases]"):]
    _refused(capsys, tmp_path, _own(tmp_path, cell=cell),
             needles=("bracket_task.toml: b5",
                      "operation 'fixture..tray+away' (action 'b5') has no physical action",
                      "bracket_cell.toml: add [actions.b5] there"))


def test_an_action_whose_part_is_not_in_the_task(capsys, tmp_path):
    task = (TASK.replace('"screw", ', "").replace('before = ["b2", "b3"]', 'before = ["b2"]')
            .replace('[[liaisons]]\nparts = ["base", "screw"]\naction = "b3"\n', "")
            .replace('after = ["b2", "b3"]', 'after = ["b2"]'))
    _refused(capsys, tmp_path, _own(tmp_path, task=task),
             needles=("bracket_cell.toml: actions.b3.part",
                      "action b3 moves part 'screw', which is not a part of the task"))


@pytest.mark.parametrize(("agents", "needle"), [
    ('[agents.human]\nkind = "human"\n[agents.robot]\nkind = "robot"\ncost = 2.5\n'
     '[agents.robot2]\nkind = "robot"\n', "robot agent 'robot2' has no body"),
    ('[agents.operator]\nkind = "human"\n[agents.robot]\nkind = "robot"\ncost = 2.5\n',
     "human agent 'operator' has no body"),
])
def test_an_agent_with_no_body_in_the_cell(capsys, tmp_path, agents, needle):
    head, tail = TASK.index("[agents.human]"), TASK.index("[[liaisons]]")
    task = TASK[:head] + agents + "\n" + TASK[tail:]
    _refused(capsys, tmp_path, _own(tmp_path, task=task),
             needles=("bracket_task.toml: agents.", needle, "the worker 'human' (worker.name) and the robots "
                                                            "['robot']"))


@pytest.mark.slow
def test_a_part_the_gripper_cannot_take_is_refused_for_the_robot(capsys, tmp_path):
    """b1 is the worker's or the robot's: the robot is refused it before the physics, in one line, and the
    worker does it; left to the robot alone, the run is refused."""
    cell = CELL.replace("size = [0.06, 0.06, 0.04]", "size = [0.06, 0.10, 0.04]")
    out = tmp_path / "out"
    code = main(["run", _own(tmp_path, cell=cell), "--subjects", "1", "--reps", "1", "--jobs", "1", "--quiet",
                 "--no-plots", "--mode", "r-only", "--out", str(out)])
    stdout = capsys.readouterr().out
    assert code == 0
    assert "panda cannot do b1: base is 100 mm wide and the gripper opens 80 mm; the human does it" in stdout
    rows = (out / "allocations.csv").read_text().splitlines()
    assert any(",b1,human," in r and ",done," in r for r in rows)
    assert not any(",b1,robot," in r for r in rows)
    task = TASK.replace('action = "b1"', 'action = "b1"\nagents = ["robot"]')
    alone = tmp_path / "alone"
    alone.mkdir()
    _refused(capsys, alone, _own(alone, cell=cell, task=task),
             needles=("bracket_task.toml: b1", "its gripper cannot take base (100 mm wide",
                      'agents = ["human"]'))


# -- a target no allowed agent can reach: the reachability pre-check -----------------------------------------
def test_a_target_no_allowed_agent_can_reach(capsys, tmp_path):
    """The worker stands back by 0.8 m: the first action in the plan's order that no allowed agent can do
    is a4 (the worker is out of reach, and the robot's hand-over at a4's target, planned whole, has no IK
    solution on its carry), named with both agents' reasons."""
    _refused(capsys, tmp_path, "multi-subject", "scene.worker_xy=-0.8,0",
             needles=(MS, "actions.a4", "human or robot cannot reach S2 for a4",
                      "human: out of the worker's reach", "robot: on the carry", "no IK solution at",
                      "the run would fail"))


def test_a_robot_only_action_the_robot_cannot_reach(capsys, tmp_path):
    task = TASK.replace('parts = ["base", "pin"]\naction = "b2"\n', 'parts = ["base", "pin"]\naction = "b2"\n'
                        'agents = ["robot"]\n')
    cell = CELL.replace("xy = [0.50, 0.28]", "xy = [0.05, 0.45]")  # the pin at the bench's near corner
    cell = cell.replace("center = [0.62, 0.0]\nsize = [0.64, 1.0]",
                        "center = [0.45, 0.0]\nsize = [0.90, 1.0]")  # a bench long enough to hold it
    _refused(capsys, tmp_path, _own(tmp_path, task=task, cell=cell),
             needles=("bracket_cell.toml: actions.b2", "robot cannot reach pin for b2"))

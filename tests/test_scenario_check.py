"""The check before any physics (issue 27): it follows the task's plan with every part where the earlier
actions leave it, plans each robot action's whole skill (the carry included) and refuses a part the robot
would have to tilt, before a subject starts. Refusals go through the CLI in-process: one line, exit 2."""

from __future__ import annotations

import numpy as np
import pytest

from ergosim import api
from ergosim.cli import main
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.scenario_check import _action_states, _Start, precheck
from ergosim.scenes import build_cell

# the housing starts at the bench's near corner, out of the robot's reach; the worker puts it into the
# fixture (g1), where the robot, alone allowed g2, presses the bushing in
MOVED_HOST = {"scene.parts.housing.xy": "0.32,-0.45", "scene.robots.robot.base": "0.94,0.25,0.9",
              "task.liaisons.g2.agents": "robot"}


def _refused(capsys, tmp_path, overrides: dict[str, str], *needles: str) -> str:
    args = ["run", "gearbox", "--subjects", "1", "--reps", "1", "--quiet",
            "--no-plots", "--out", str(tmp_path / "o")]
    for key, value in overrides.items():
        args += ["--set", f"{key}={value}"]
    code = main(args)
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("ergosim: error: ") and err.count("\n") == 1, err
    for needle in needles:
        assert needle in err, err
    assert not (tmp_path / "o").exists()  # refused before anything was written
    return err


def test_a_slot_is_read_where_earlier_actions_moved_its_host():
    """At HEAD: "robot cannot reach bushing for g2 ... to housing_hollow_bushing at [0.32, -0.45, 0.97]",
    the housing's start, although g1 has put it into the fixture."""
    sc = load_scenario("gearbox", MOVED_HOST)
    cell = build_cell(sc.cell())
    start = _Start(cell)
    states = dict((a, s) for a, s, _ in _action_states(sc.task(), cell, start))
    fixture = cell.site_pose("fixture")[0]
    seat = start.target(cell.actions["g2"], states["g2"])[0]
    assert np.allclose(seat[:2], fixture[:2], atol=1e-6)  # the seat is on the housing in the fixture
    assert not np.allclose(start.sites[cell.actions["g2"].target][0][:2], fixture[:2], atol=0.1)
    # and it moves on with the housing: g5's cover goes onto the housing in the fixture too
    assert np.allclose(start.target(cell.actions["g5"], states["g5"])[0][:2], fixture[:2], atol=1e-6)
    precheck(sc)  # not refused


@pytest.mark.slow
def test_the_run_the_old_check_refused_completes_with_the_robot_doing_g2(tmp_path):
    sc = api.load("gearbox", {**MOVED_HOST, "subjects": "1", "repetitions": "1", "modes": "hrc"})
    result = api.run(sc, out=tmp_path / "o")  # with the check
    rows = [a for r in result.runs("hrc") for a in r.allocations if a.action == "g2" and a.done]
    assert result.summary["status"] == "complete" and [a.agent for a in rows] == ["robot"]


def test_a_carry_waypoint_without_an_ik_solution_is_refused_naming_the_point(capsys, tmp_path):
    """At HEAD the grasp and the target passed and every repetition was abandoned at run time with "no IK
    solution at ... (base frame)"."""
    _refused(capsys, tmp_path, {"scene.carry_height": "1.6", "task.liaisons.g2.agents": "robot"},
             "actions.g2: robot cannot reach bushing for g2", "on the carry",
             "no IK solution at", "in the world frame [0.43, 0.12, 1.64]", "the run would fail")


def test_a_part_the_robot_would_have_to_tilt_is_refused_up_front(capsys, tmp_path):
    """The stud lies on its side and goes into the cover upright: the robot grasps from above and turns a
    part only about the vertical (at HEAD: accepted, then not_grasped / not_seated at run time)."""
    lying = {"scene.parts.stud.pos": "0.53,0.20,1.17", "scene.parts.stud.rpy": "90,0,0"}
    _refused(capsys, tmp_path, {**lying, "task.liaisons.g3.agents": "robot"},
             "robot cannot reach stud for g3", "stud must turn 90 deg about a horizontal axis to go into "
             "cover.stud_seat", "turns it only about the vertical", 'agents = ["human"]')
    precheck(load_scenario("gearbox", {**lying, "task.liaisons.g3.agents": "human,robot"}))  # the worker can


def test_a_robot_handing_over_leaves_the_seating_to_the_worker():
    """multi-subject's a2: the robot hands L over and the worker inserts it upright into J; not refused."""
    precheck(load_scenario("multi-subject"))

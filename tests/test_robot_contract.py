"""The robot contract: the registry, what a robot cannot do (gripper, payload, reach) in words, and no
Panda-specific name outside ergosim/robot/panda* (the Panda's module) and models/panda (its data)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from ergosim.cli import main
from ergosim.errors import ConfigError
from ergosim.experiment.scenario import load_scenario
from ergosim.robot import get_robot, robot_names
from ergosim.robot.capability import refusal
from ergosim.robot.panda import PANDA
from ergosim.robot.ur5 import UR5
from ergosim.scenes import build_cell
from ergosim.twin.robot_refusals import handover_clearance, handover_poses, robot_refusals

ROOT = Path(__file__).resolve().parents[1]


def test_registry():
    assert get_robot("panda") is PANDA and get_robot("ur5") is UR5
    assert {"panda", "ur5"} <= set(robot_names())
    with pytest.raises(ConfigError, match="unknown robot model 'kuka'; valid robot models: panda, ur5"):
        get_robot("kuka")


def test_refusals_name_the_limit():
    assert refusal(UR5, "g2", "bushing", 0.047, 0.3) is None
    assert refusal(UR5, "g4", "gear", 0.060, 0.4) == ("ur5 cannot do g4: gear is 60 mm wide and the gripper "
                                                     "opens 55 mm")
    assert refusal(PANDA, "g4", "gear", 0.060, 0.4) is None
    assert refusal(PANDA, "a1", "block", 0.05, 3.5) == ("panda cannot do a1: it carries 3.50 kg (block) and "
                                                       "its payload is 3 kg")
    assert refusal(UR5, "a1", "block", 0.05, 3.5) is None
    assert "out of its reach" in refusal(PANDA, "a5", "J", 0.03, 0.2, reachable=False)


def _names_and_strings(tree: ast.AST):
    """(line, text) of every identifier and every string literal that is not a docstring."""
    docstrings = {id(node.value) for node in ast.walk(tree)
                  if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)}
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            yield node.lineno, node.id
        elif isinstance(node, ast.Attribute):
            yield node.lineno, node.attr
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            yield node.lineno, node.name
        elif isinstance(node, ast.arg | ast.keyword) and node.arg:
            yield node.lineno, node.arg
        elif isinstance(node, ast.alias):
            yield node.lineno, f"{node.name} {node.asname or ''}"
        elif isinstance(node, ast.ImportFrom) and node.module:
            yield node.lineno, node.module
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            yield node.lineno, node.value


@pytest.mark.slow
def test_no_panda_specific_name_outside_the_pandas_module():
    """Every robot comes through the contract: no identifier or string of the package and its scripts names
    the Panda outside ergosim/robot/panda*.py (its record), but for the import in ergosim/robot/__init__.py
    that registers it; its data is models/panda/. (Prose may cite it, e.g. where another robot's assumed
    figure comes from.)"""
    hits = []
    for path in sorted([*(ROOT / "ergosim").rglob("*.py"), *(ROOT / "scripts").glob("*.py")]):
        rel = path.relative_to(ROOT).as_posix()
        if re.fullmatch(r"ergosim/robot/panda\w*\.py", rel):
            continue
        for line, text in _names_and_strings(ast.parse(path.read_text())):
            registers = rel == "ergosim/robot/__init__.py" and text == "panda _first"
            if re.search(r"panda(?!s)", text.lower()) and not registers:
                hits.append(f"{rel}:{line}: {text}")
    assert not hits, "\n".join(hits)


@pytest.mark.slow
def test_a_handover_pose_at_the_workers_neck_is_refused_for_the_robot(capsys, tmp_path):
    """The hand-over clearance rule: the multi-subject hand-overs, each presented at its own target (issue
    23) where the plan has them, keep the Panda 0.32-0.46 m from the worker's head and neck (ISO/TS 15066
    region 1); handed over at the cell's free hand-over pose at 1.3 m in front of the chest it keeps
    0.21-0.23 m (the chest is not a hand-over region); moved up to 1.45 m and 3 cm closer, within 0.2 m of
    the head (which sits on the neck, over C7), the robot
    is refused every hand-over before the physics, in one line each, and the worker does them; out of its
    reach, likewise."""
    sc = load_scenario("multi-subject")
    cell = build_cell(sc.cell())
    at = handover_poses(sc.task(), cell)  # L, S1, S2 at J's hollows once J is on the bench
    clear = [handover_clearance(cell, cell.robot(), g, at[a]) for a, g in cell.actions.items() if g.handover]
    assert len(clear) == 4 and all(0.3 < c < 0.6 for c in clear)
    assert robot_refusals(sc.task(), cell) == {}
    at_pose = {f"scene.actions.{a}.handover": "handover" for a in ("a1", "a2", "a3", "a4")}
    chest = load_scenario("multi-subject", {**at_pose, "scene.targets.handover.pos": "0.25,0.3,1.3"})
    assert robot_refusals(chest.task(), build_cell(chest.cell())) == {}
    near = load_scenario("multi-subject", {**at_pose, "scene.targets.handover.pos": "0.22,0.3,1.45"})
    refused = robot_refusals(near.task(), build_cell(near.cell()))
    assert set(refused) == {("a1", "robot"), ("a2", "robot"), ("a3", "robot"), ("a4", "robot")}
    assert all("from the worker's head or neck (at least 0.2 m)" in why for why in refused.values())
    sets = [x for k, v in at_pose.items() for x in ("--set", f"{k}={v}")]
    code = main(["run", "multi-subject", "--subjects", "1", "--reps", "1", "--mode", "r-only", "--quiet",
                 "--no-plots",
                 *sets, "--set", "scene.targets.handover.pos=0.22,0.3,1.45", "--out", str(tmp_path / "o")])
    out = capsys.readouterr().out
    assert code == 0 and out.count("holding") == 4 and "the human does it" in out
    # behind the worker's right, out of the side-table robot's reach
    far = load_scenario("multi-subject", {**at_pose, "scene.targets.handover.pos": "0.15,-0.5,1.35"})
    refused = robot_refusals(far.task(), build_cell(far.cell()))
    assert len(refused) == 4 and all("handover is out of its reach" in why for why in refused.values())

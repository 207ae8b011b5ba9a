"""The action vocabulary (issue 12 §3): place, insert, fasten, remove, handover, each with its completion
check, done by the worker and by the robot on the same operations of a user's own product.

The bracket of ``own_product.py`` has one action of every kind, and both agents may do each; the real loop
pieces do them one at a time (:meth:`Session.perform`: the worker's planned motion, or the Panda's skill
in the physics), and the scene's completion check decides.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from own_product import write_product

from ergosim import api
from ergosim.errors import ConfigError
from ergosim.robot import SkillStatus
from ergosim.robot.skills import PickPlace
from ergosim.scenes.action_kinds import ACTION_KINDS, ActionKind, register_action_kind

ORDER = ("b1", "b2", "b3", "b4", "b5")


@pytest.fixture(scope="module")
def bracket(tmp_path_factory):
    return api.load(write_product(tmp_path_factory.mktemp("bracket")))


def _assemble(scenario, agent: str) -> dict:
    """``agent`` does b1..b5 in order; per action, the part's pose, its distance to the target site and the
    attempt's outcome, just after the action."""
    session = api.session(scenario, "h-only", calibrate=False)
    cell = session.cell
    out = {}
    for action in ORDER:
        outcome = session.perform(action, agent)
        geom = cell.actions[action]
        pos, quat = cell.body_pose(geom.part)
        target = cell.site_pose(geom.target)[0]
        host = cell.body_pose(cell.assembly(geom.part)[0])
        out[action] = {"outcome": outcome, "pos": pos, "quat": quat, "host": host,
                       "to_target": np.linalg.norm(pos - target), "done": cell.action_done(geom),
                       "assembly": cell.assembly(geom.part)}
    out["cell"] = cell
    out["session"] = session
    return out


@pytest.fixture(scope="module")
def by_worker(bracket):
    return _assemble(bracket, "human")


@pytest.fixture(scope="module")
def by_robot(bracket):
    return _assemble(bracket, "robot")


def test_the_vocabulary_is_registered_in_one_place():
    assert set(ACTION_KINDS) >= {"place", "insert", "fasten", "remove", "handover"}
    assert ACTION_KINDS["fasten"].seats and ACTION_KINDS["fasten"].holds
    assert ACTION_KINDS["handover"].received and ACTION_KINDS["handover"].target == "free"
    assert ACTION_KINDS["remove"].assembly and not ACTION_KINDS["place"].assembly


@pytest.mark.slow
@pytest.mark.parametrize("agent", ["human", "robot"])
def test_every_kind_completes_by_its_own_check(agent, by_worker, by_robot):
    run = by_worker if agent == "human" else by_robot
    cell = run["cell"]
    for action in ORDER:
        assert run[action]["outcome"].ok, (agent, action, run[action]["outcome"])
        assert run[action]["done"], (agent, action)
    tol = cell.config.place_tolerance
    assert run["b1"]["to_target"] <= tol  # place: released on its target
    assert cell.is_seated("pin") and cell.is_seated("screw")  # insert, fasten: seated
    assert run["b2"]["to_target"] < 1e-4 and run["b3"]["to_target"] < 1e-4  # welded at the seat
    assert run["b4"]["to_target"] <= tol  # remove: on the tray ...
    assert set(run["b4"]["assembly"]) == {"base", "pin", "screw"}  # ... with what is seated in the base
    assert cell.is_received("base") and run["b5"]["to_target"] <= tol  # handover: the receiver holds it
    assert cell.holder_of("base") is None  # nobody of the cell does


def test_a_fastener_is_held_for_its_turns(by_worker, by_robot):
    turn = by_robot["cell"].actions["b3"].turn_time
    assert turn > 0
    for run in (by_worker, by_robot):
        fasten = run["b3"]["outcome"]
        assert fasten.t_end - fasten.t_start > turn
    # the worker's motion has a fasten phase at least turn_time long
    session = by_worker["session"]
    cell = session.cell
    cell.reset_parts()
    motion = session.worker.plan(cell, cell.actions["b3"], np.random.default_rng(0), action="b3")
    phase = next(p for p in motion.phases if p.name == "fasten")
    assert phase.end - phase.start >= turn


def test_worker_and_robot_move_the_same_part_to_the_same_target(by_worker, by_robot):
    tol = by_robot["cell"].config.place_tolerance
    for action in ORDER:
        w, r = by_worker[action], by_robot[action]
        gap = float(np.linalg.norm(w["pos"] - r["pos"]))
        if action in ("b2", "b3"):  # seated: the same pose in the host (a stiff weld)
            rel_w = w["pos"] - w["host"][0]
            rel_r = r["pos"] - r["host"][0]
            assert np.linalg.norm(rel_w - rel_r) < 2e-4, action
        else:
            assert gap <= 2 * tol, (action, gap)


def test_a_received_assembly_stays_where_it_was_taken(by_robot):
    cell = by_robot["cell"]
    before = {p: cell.body_pose(p)[0] for p in ("base", "pin", "screw")}
    mujoco.mj_step(cell.model, cell.data, nstep=500)  # 1 s: gravity pulls, the receiver holds
    for p, pos in before.items():
        assert np.linalg.norm(cell.body_pose(p)[0] - pos) < 2e-3, p
    cell.reset_parts()  # the next repetition starts with the parts laid out, nobody holding anything
    assert not cell.is_received("base") and not cell.is_seated("pin")


def test_a_handover_out_of_the_receivers_reach_fails_as_not_seated(bracket, tmp_path):
    """The robot delivers 2 mm off (its release height), the receiver's tolerance is 1 mm: nobody takes
    the part, the skill says not_seated and the part falls."""
    cell = api.workcell(bracket.cell_source, {"place_tolerance": 0.001})
    pos, quat = cell.site_pose("second_operator")
    result = PickPlace(cell, "base", pos, quat, receive=True).run_to_completion(120.0)
    assert result.status is SkillStatus.NOT_SEATED and "receiver" in result.message
    assert not cell.is_received("base")
    assert cell.body_pose("base")[0][2] < pos[2] - 0.1


def test_a_new_kind_is_one_registration(tmp_path):
    """A user's kind ("press": a seated part held for a while, like fasten) is usable in a cell file."""
    from own_product import CELL  # noqa: PLC0415

    register_action_kind(ActionKind("press", "slot", "push and hold", seats=True, holds=True))
    try:
        path = tmp_path / "cell.toml"
        path.write_text(CELL.replace('kind = "fasten"', 'kind = "press"'))
        assert api.workcell(path).actions["b3"].seats
        path.write_text(CELL.replace('kind = "fasten"', 'kind = "screw_in"'))
        with pytest.raises(ConfigError, match="unknown action kind 'screw_in'; kinds: .*press"):
            api.workcell(path)
    finally:
        ACTION_KINDS.unregister("press")  # leave the registry as the other tests expect it

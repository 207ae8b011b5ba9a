"""The kwear-lookahead mode in the twin: a generated cell's free-order group (the action that wears more goes
to the robot more, whatever the file order), the decisions and records of a run, observed durations, the
paper's outputs untouched, and parallel decisions that look at time."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from own_product import CELL, SCENARIO, TASK, write_product

from ergosim import api
from ergosim.experiment.runner import run_subject
from ergosim.experiment.subject import subject_session
from ergosim.twin.lookahead_allocator import LookaheadAllocator, lookahead_settings
from ergosim.twin.lookahead_team_allocator import team_state
from ergosim.twin.protocol import LookaheadConfig
from ergosim.twin.team_allocator import Busy
from ergosim.twin.team_board import TeamBoard
from ergosim.viz.reason import reason_text

PARTS = 'parts = ["fixture", "base", "pin", "screw", "tray", "away"]'


def free_order_cell(folder, *, pin_first: bool):
    """The bracket with its pin high and far on a shelf (b2) and its screw close to the worker (b3), b2 and
    b3 in one free-order group; ``pin_first`` lists the pin before the screw in the task file."""
    cell = CELL.replace("[furniture.bench]", "[furniture.shelf]\ntype = \"table\"\ncenter = [0.62, 0.42]\n"
                        "size = [0.30, 0.20]\nheight = 1.30\n\n[furniture.bench]")
    cell = cell.replace("xy = [0.50, 0.28]", "xy = [0.66, 0.44]\non = \"shelf\"")
    cell = cell.replace("xy = [0.60, 0.30]", "xy = [0.40, 0.12]")
    task = TASK if pin_first else TASK.replace(PARTS, PARTS.replace('"pin", "screw"', '"screw", "pin"'))
    assert cell != CELL and (pin_first or task != TASK)
    scenario = SCENARIO.replace('modes = ["hrc", "h-only", "r-only"]', 'modes = ["kwear-lookahead"]')
    return write_product(folder, task=task, cell=cell, scenario=scenario)


@pytest.mark.slow
def test_in_a_free_order_group_the_action_that_wears_more_goes_to_the_robot_more(tmp_path):
    runs = {}
    for pin_first in (True, False):
        path = free_order_cell(tmp_path / f"pin_first_{pin_first}", pin_first=pin_first)
        sc = api.load(path, subjects=2, repetitions=6)
        runs[pin_first] = api.run(sc, seed=1, jobs=2)
    first = runs[True].subjects[0]
    wear = {a: float(v[-1].sum()) for a, (_, v) in first.traces.items()}  # V from zero after one execution
    # which of the two wears more is the worker's to say: the stance-first worker steps to the far pin and
    # its fastened screw lasts longer, so the near screw wears a little more (the worker of issue 23 reached
    # for the pin and wore more on it)
    more, less = sorted(("b2", "b3"), key=lambda a: -wear[a])
    assert wear[more] > wear[less]
    shares = {k: r.summary["modes"]["kwear-lookahead"]["robot_share_by_action"] for k, r in runs.items()}
    for share in shares.values():  # whichever order the task file lists them in
        assert share[more] >= share[less]
    assert shares[True] == shares[False]  # the order of the task file decides nothing
    rows = {k: [(a.action, a.agent, a.t_end) for s in r.subjects
                for a in s.runs["kwear-lookahead"].allocations] for k, r in runs.items()}
    assert rows[True] == rows[False]


@pytest.fixture(scope="module")
def multi():
    return api.load("multi-subject", {"repetitions": "3", "subjects": "1", "modes": "kwear-lookahead,hrc"})


@pytest.mark.slow
def test_a_run_decides_by_sequences_and_is_paired_with_the_papers_rule(multi, tmp_path):
    res = api.run(multi, seed=0, jobs=1, out=tmp_path / "out")
    run = res.subjects[0].runs["kwear-lookahead"]
    assert run.decisions
    words = [reason_text(d) for d in run.decisions]
    assert all("cheapest sequence" in w and "exact" in w for w in words)
    assert all(d.sequence is not None and d.sequence.exact and d.sequence.steps[0] == (d.action, d.agent)
               for d in run.decisions)
    assert all(np.isfinite(d.through) for d in run.decisions)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["wilcoxon"]["n"] == 1  # kwear-lookahead against hrc, subject by subject
    assert summary["wilcoxon"]["modes"] == ["kwear-lookahead", "hrc"]  # named from the run, not "h-only"
    assert summary["config"]["takt_weight"] is None and summary["config"]["lookahead_exact"] == 20_000
    again = run_subject(multi, 0, 0, ("kwear-lookahead",)).runs["kwear-lookahead"]
    assert [(a.action, a.agent, a.t_end) for a in again.allocations] == \
        [(a.action, a.agent, a.t_end) for a in run.allocations]


LOOKAHEAD_FIELDS = tuple(f.name for f in dataclasses.fields(LookaheadConfig))


def test_the_papers_outputs_do_not_record_the_lookahead_fields():
    sc = api.load("multi-subject")
    assert not set(LOOKAHEAD_FIELDS) & set(sc.protocol.record())
    assert set(LOOKAHEAD_FIELDS) <= set(api.load("multi-subject", {"takt_weight": "1.5"}).protocol.record())
    assert set(LOOKAHEAD_FIELDS) <= set(api.load("gearbox", {"modes": "kwear-lookahead"}).protocol.record())


@pytest.mark.slow
def test_settings_and_observed_durations(multi):
    session = subject_session(multi, 0, 0, "kwear-lookahead")
    alloc = session.allocator
    assert isinstance(alloc, LookaheadAllocator)
    takt_weight, time_weight, limits = lookahead_settings(multi.protocol)
    assert takt_weight == pytest.approx(100.0 / 38.0) and time_weight == 0.0 and limits.beam_width == 6
    parallel = api.load("multi-subject", {"execution": "parallel"}).protocol
    assert lookahead_settings(parallel)[1] == pytest.approx(100.0 / 38.0)
    model = alloc.model
    a2, robot = model.action_index["a2"], model.agent_index["robot"]
    planned = model.duration[a2, robot]
    part = planned - (model.duration[a2, robot] - model.rest[a2, robot])  # the robot's planned share
    # a handover: its take is what it adds to the robot's plan (a4: a3's hand-over at its target has no
    # trajectory planned from the cell as laid out, so the look-ahead leaves a3 to the worker)
    assert ("a3", "robot") in alloc.unreachable
    alloc.observe("a4", "robot", 24.0)
    a4 = model.action_index["a4"]
    take = 24.0 - alloc.model.rest[a4, robot]
    assert alloc.model.duration[a4, robot] == pytest.approx(24.0)
    assert alloc.model.duration[a2, robot] == pytest.approx(part + take)  # the same take for a2, unobserved
    alloc.observe("a1", "human", 4.0)
    alloc.observe("a1", "human", 6.0)
    assert alloc.model.duration[model.action_index["a1"], model.agent_index["human"]] == pytest.approx(5.0)


@pytest.mark.slow
def test_team_state_from_the_session_jobs(multi):
    alloc = subject_session(multi, 0, 0, "kwear-lookahead").allocator
    board = TeamBoard(alloc.graph, {("a2", "robot"): "L"})
    board.done.append("area+J")
    board.reserved["a2"] = ("robot", "L")
    board.running[7] = "area-J+S1"
    model = alloc.model
    d3 = model.duration[model.action_index["a3"], model.agent_index["human"]]
    state = team_state(alloc, np.full(5, 0.2), board, [Busy("human", "a3", 10.0, "acting"),
                                                        Busy("robot", "a2", 8.0, "fetching")], 12.0, 10.0)
    assert state.now == pytest.approx(2.0) and state.reserved == {"a2": "robot"}
    assert state.worker_free == pytest.approx(d3) and state.running == {"area-J+S1": pytest.approx(d3)}
    assert np.all(state.v > 0.2)  # the rest of a3's wear is still to come
    assert state.free["robot"] == pytest.approx(max(2.0, -2.0 + model.rest[model.action_index["a2"], 1]))


@pytest.mark.slow
def test_parallel_first_decisions_do_not_hand_the_robot_what_the_worker_does_far_faster():
    """The issue's gearbox case: in parallel the paper's team rule gives the idle robot g3 at t = 0 (18.6 s
    for what the worker does in 4.4 s) and the worker waits 12 s for it. The look-ahead prices the
    schedule's makespan: the worker starts g3 at t = 0 and nothing is given to the robot then.

    (Not claimed: that the worker never waits. The robot's expected durations come from trajectories
    planned on the cell as laid out at setup; its g4 is expected to take 7.8 s to the release at first, and
    took 12.9 s in parallel under the separation monitor.)"""
    sc = api.load("gearbox", {"repetitions": "1", "subjects": "1", "execution": "parallel",
                              "modes": "kwear-lookahead,hrc"})
    runs = run_subject(sc, 0, 9, ("kwear-lookahead", "hrc")).runs
    paper = [a for a in runs["hrc"].allocations if a.t_start == 0.0]
    # (the case, the paper's rule giving the idle robot g3 at t = 0, no longer arises with the
    # worker of issue 23; what the look-ahead does at t = 0 is still checked)
    assert paper
    run = runs["kwear-lookahead"]
    first = [d for d in run.decisions if d.time == 0.0]
    assert first and all(d.agent == "human" for d in first) and first[0].action == "g3"
    assert all(a.status == "done" for a in run.allocations)


@pytest.mark.slow
def test_in_parallel_a_robot_is_expected_as_slow_as_it_was_and_free_after_its_way_home():
    """In parallel a robot's expected durations run to its release (its way home is ``leave``), and once it
    has executed an action, its actions not yet executed are expected as much slower than planned as that
    one was (the separation monitor slows it near the worker). Sequential execution keeps both as before."""
    def allocator(execution):
        sc = api.load("gearbox", {"repetitions": "1", "subjects": "1", "execution": execution,
                                  "modes": "kwear-lookahead"})
        return subject_session(sc, 0, 0, "kwear-lookahead").allocator

    parallel, sequential = allocator("parallel"), allocator("sequential")
    m = parallel.model
    robot, g2, g4 = m.agent_index["robot"], m.action_index["g2"], m.action_index["g4"]
    planned2, planned4 = m.duration[g2, robot], m.duration[g4, robot]
    assert m.leave[g4, robot] > 1.0 and not sequential.model.leave.any()
    assert planned4 == pytest.approx(sequential.model.duration[g4, robot] - m.leave[g4, robot])
    parallel.observe("g4", "robot", 2.0 * planned4)
    assert parallel.model.duration[g4, robot] == pytest.approx(2.0 * planned4)
    assert parallel.model.duration[g2, robot] == pytest.approx(2.0 * planned2)
    before = sequential.model.duration[g2, robot]
    sequential.observe("g4", "robot", 2.0 * sequential.model.duration[g4, robot])
    assert sequential.model.duration[g2, robot] == pytest.approx(before)

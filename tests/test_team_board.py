"""Parallel execution without physics, on random AND/OR graphs (hypothesis): a discrete-event team runs the
team planner and the board the way the parallel session does (early handovers joined when the worker takes
the part, failures that prune a hyper-arc, abandonment when nothing can finish the assembly), and every step
is checked: precedence is never violated, no sub-assembly is held by two agents, and every repetition
completes or says why not."""

from __future__ import annotations

import heapq

import numpy as np
import pytest
from aog_strategies import explicit_graphs, liaison_graphs
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ergosim.errors import InfeasiblePlanError
from ergosim.planner import bundled_task
from ergosim.planner.team import team_assign
from ergosim.twin.team_board import TeamBoard

SETTINGS = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def check_holds(board: TeamBoard) -> None:
    """Every held sub-assembly exists now and has exactly one holder."""
    graph = board.graph
    nodes = set(graph.configuration(board.done))
    held = []
    for op in board.running.values():
        held += list(graph.operation(op).children)
    for action, (_, part) in board.reserved.items():
        held += [n for n in nodes if part in n]
    assert len(held) == len(set(held)), f"a sub-assembly is held twice: {held}"
    assert set(held) <= nodes, "an operation holds a sub-assembly that does not exist"


class Team:
    """A discrete-event team on ``graph``: durations and failures drawn from ``rng``; robots in ``early``
    fetch first (their hyper-arcs start early) and wait for the worker to take the part."""

    def __init__(self, graph, rng: np.random.Generator, early, failure_rate: float, costs) -> None:
        self.graph, self.rng, self.early = graph, rng, early
        self.failure_rate = failure_rate
        self.costs = costs
        self.human = next(a.name for a in graph.agents if a.kind == "human")
        self.agents = [a.name for a in graph.agents]

    def run(self) -> tuple[str, str]:
        graph, rng = self.graph, self.rng
        board = TeamBoard(graph, self.early)
        pruned: set[tuple[str, str]] = set()
        busy: dict[str, tuple] = {}  # agent -> (kind, job, step)
        waiting: list = []  # robots holding a part out: (since, agent, job, step)
        events: list = []
        now, ids = 0.0, 0
        for _ in range(2000):
            # the worker serves a waiting robot first
            if self.human not in busy:
                for since, agent, job, step in sorted(waiting):
                    before = set(graph.configuration(board.done))
                    op = board.join(job, step.action)
                    if op is None:
                        continue
                    assert set(graph.operation(op).children) <= before, "joined before its children exist"
                    waiting.remove((since, agent, job, step))
                    busy[self.human] = ("take", job, step)
                    heapq.heappush(events, (now + rng.uniform(0.5, 2.0), job, self.human))
                    break
            idle = [a for a in self.agents if a not in busy]
            if board.complete and not busy:
                return "completed", ""
            picks = []
            if idle and not board.complete:
                try:
                    picks = team_assign(graph, idle=idle, done=board.done, running=board.running.values(),
                                        reserved=board.reserved, costs=self.costs, pruned=pruned,
                                        early=self.early, margin=None).steps
                except InfeasiblePlanError as err:
                    if not busy and not waiting:
                        return "abandoned", err.what
            config = set(graph.configuration(board.done))
            for step in picks:
                op = graph.operation(step.operation)
                if step.early:
                    moving = [c for c in op.children if step.part in c]
                    assert moving and moving[0] in config, "an early start without its part"
                else:
                    assert set(op.children) <= config, "precedence violated: children missing at the start"
                job = ids
                ids += 1
                board.start(job, step)
                busy[step.agent] = ("early" if step.early else "full", job, step)
                heapq.heappush(events, (now + rng.uniform(0.5, 3.0), job, step.agent))
            check_holds(board)
            if not events:
                if busy or waiting:
                    raise AssertionError("agents busy with nothing scheduled")
                if board.complete:
                    return "completed", ""
                return "stuck", "no agent can start any remaining operation"
            now, job, agent = heapq.heappop(events)
            if agent not in busy or busy[agent][1] != job:
                continue  # a stale timeout of a hand-over that was taken
            kind, job, step = busy.pop(agent)
            failed = rng.random() < self.failure_rate
            if kind == "early":
                if failed:  # the robot could not fetch the part
                    board.drop(action=step.action)
                    pruned.add((step.action, agent))
                else:  # it holds the part out until the worker takes it, or gives up after a while
                    waiting.append((now, agent, job, step))
                    busy[agent] = ("holding", job, step)
                    heapq.heappush(events, (now + 30.0, job, agent))
            elif kind == "holding":  # nobody took the part in time
                waiting.remove(next(w for w in waiting if w[2] == job))
                board.drop(action=step.action)
                pruned.add((step.action, agent))
            elif kind == "take":
                robot = next(a for a, (k, j, _) in busy.items() if k == "holding" and j == job)
                del busy[robot]
                if failed:
                    board.drop(job=job)
                    pruned.add((step.action, robot))
                else:
                    board.finish(job)
            elif failed:
                board.drop(job=job)
                pruned.add((step.action, agent))
            else:
                board.finish(job)
        raise AssertionError("the team did not finish within 2000 events")


def _early(graph, draw) -> dict[tuple[str, str], str]:
    robots = [a.name for a in graph.agents if a.kind == "robot"]
    out, part = {}, {}
    for op in graph.operations:
        for r in robots:
            if r in op.agents and (op.action, r) not in out and draw(st.integers(0, 2)) == 0:
                out[(op.action, r)] = part.setdefault(op.action, op.children[0][0])  # one part per action
    return out


def check_team(graph, data) -> None:
    keys = [(a, ag.name) for a in graph.actions for ag in graph.agents]
    costs = {k: data.draw(st.floats(0.0, 5.0)) for k in keys if data.draw(st.booleans())}
    early = _early(graph, data.draw)
    rng = np.random.default_rng(data.draw(st.integers(0, 2**32 - 1)))
    outcome, why = Team(graph, rng, early, data.draw(st.sampled_from([0.0, 0.1, 0.3])), costs).run()
    assert outcome in ("completed", "abandoned"), (outcome, why)
    if outcome == "abandoned":
        assert why.startswith("no feasible plan")


@SETTINGS
@given(st.data())
def test_team_execution_on_random_graphs(data):
    check_team(data.draw(explicit_graphs()), data)


@SETTINGS
@given(st.data())
def test_team_execution_on_random_liaison_graphs(data):
    check_team(data.draw(liaison_graphs()), data)


def test_join_picks_the_operation_that_fits_what_is_there_now():
    graph = bundled_task("corner-joint:multi-subject")
    board = TeamBoard(graph)
    step = team_assign(graph, idle=["human"]).steps[0]
    board.start(1, step)  # the worker places J
    board.finish(1)
    board.reserved["a2"] = ("robot", "L")  # the robot fetches L
    s1 = next(s for s in team_assign(graph, idle=["human"], done=board.done, reserved=board.reserved).steps)
    board.start(2, s1)  # meanwhile the worker inserts another profile into J
    assert board.join(3, "a2") is None  # J is held by the worker: the robot keeps waiting
    board.finish(2)
    op = board.join(3, "a2")
    assert op is not None and set(graph.operation(op).children) <= set(graph.configuration(board.done))
    assert board.holder_of(graph.children(graph.op_index[op])[0]) == 3
    board.finish(3)
    assert "a2" in {graph.operation(o).action for o in board.done}


def test_a_failed_job_frees_what_it_held():
    graph = bundled_task("gearbox")
    board = TeamBoard(graph)
    step = team_assign(graph, idle=["human"]).steps[0]
    board.start(7, step)
    assert board.busy
    board.drop(job=7)
    assert not board.busy and not board.done
    with pytest.raises(KeyError):
        board.finish(7)

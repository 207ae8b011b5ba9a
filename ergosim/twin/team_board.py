"""Who holds what during one repetition of parallel execution: the team's shared state, without physics.

The board keeps the operations ``done``, the operations ``running`` (each held by one job of the session:
all its children are taken) and the actions ``reserved`` by an agent that started them early (a robot
fetching a part to hand it over holds only the child containing that part). When the worker takes a handed
part, :meth:`TeamBoard.join` resolves which operation the reserved action now is: the one that joins the
part's sub-assembly to what is there *now* (another profile may have gone into J meanwhile). The session
(:mod:`ergosim.twin.team_session`) moves jobs through the board; the property tests drive it with a
discrete-event stand-in for the physics.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ergosim.planner.call_inputs import configuration
from ergosim.planner.team import TeamStep

__all__ = ["TeamBoard"]


class TeamBoard:
    """The state of one repetition on ``graph``; ``early``: (action, agent) -> moving part of the hyper-arcs
    that start early (:func:`~ergosim.planner.team.team_assign`)."""

    def __init__(self, graph, early: Mapping[tuple[str, str], str] | None = None) -> None:
        self.graph = graph
        self.early = dict(early or {})
        self.done: list[str] = []
        self.running: dict[int, str] = {}
        """job id -> operation it holds."""
        self.reserved: dict[str, tuple[str, str]] = {}
        """action -> (agent, moving part) of an early start not joined yet."""

    @property
    def complete(self) -> bool:
        """The full assembly exists."""
        return len(configuration(self.graph, self.done)) == 1

    @property
    def busy(self) -> bool:
        """Something holds a sub-assembly (a running operation or a reservation)."""
        return bool(self.running or self.reserved)

    def start(self, job: int, step: TeamStep) -> None:
        """Job ``job`` starts ``step``: it holds the operation's children, or reserves its action (early)."""
        if step.early:
            self.reserved[step.action] = (step.agent, step.part)
        else:
            self.running[job] = step.operation

    def join(self, job: int, action: str) -> str | None:
        """The reserved ``action`` joins now as job ``job``: the operation of ``action`` whose children are
        the reserved part's sub-assembly and others that exist and nobody holds, neither a running operation
        nor another reservation (None if there is none yet;
        the reservation stays). The job then holds it."""
        graph = self.graph
        _, part = self.reserved[action]
        nodes = configuration(graph, self.done)
        free = np.zeros(graph.n_nodes + 1, dtype=bool)
        free[nodes] = True
        tl = graph.op_table
        for op in self.running.values():
            free[tl.op_children[graph.op_index[op]]] = False
        for other, (_, held) in self.reserved.items():  # the parts other robots hold out
            if other != action:
                mask = graph.part_bit(held)
                free[[n for n in nodes.tolist() if graph.node_masks[n] & mask]] = False
        free[-1] = True
        bit = graph.part_bit(part)
        for op in tl.action_ops.get(action, np.zeros(0, np.int64)).tolist():
            children = graph.op_children[op]
            if any(graph.node_masks[c] & bit for c in children) and free[tl.op_children[op]].all():
                name = graph.operations[op].name
                del self.reserved[action]
                self.running[job] = name
                return name
        return None

    def finish(self, job: int) -> str:
        """Job ``job``'s operation is done; returns it."""
        op = self.running.pop(job)
        self.done.append(op)
        return op

    def drop(self, job: int | None = None, action: str | None = None) -> None:
        """Job ``job`` (or the reservation of ``action``) failed: what it held is free again."""
        if job is not None:
            self.running.pop(job, None)
        if action is not None:
            self.reserved.pop(action, None)

    def holder_of(self, node: int) -> int | None:
        """The job holding sub-assembly ``node`` (a child of its running operation), or None."""
        graph = self.graph
        for job, op in self.running.items():
            if node in graph.children(graph.op_index[op]):
                return job
        return None

"""The role allocator of paper Fig. 1: risk prediction -> hyper-arc costs -> AO* -> next (action, agent).

What differs between modes (the risk index that prices the worker's hyper-arcs, the pruning, the decision
text) comes from the mode (:mod:`ergosim.twin.modes`): ``hrc`` predicts KWear per candidate action (eq. 9)
and prices the human's hyper-arcs with eq. 10-11. The risk index and the cost model live in
:mod:`ergosim.ergonomics`; the search in :mod:`ergosim.planner`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from ergosim.ergonomics.cost import CostParams, risk_costs
from ergosim.ergonomics.risk_index import RiskIndex
from ergosim.planner import AndOrGraph
from ergosim.planner.tie_break import PAPER_TIE_RULE, next_step
from ergosim.twin.durations import expected_durations
from ergosim.twin.modes import Mode

__all__ = ["Basis", "Decision", "DecisionPoint", "SequenceChoice", "Allocator"]


@dataclasses.dataclass(frozen=True)
class Basis:
    """What a decision's reason is judged by, the same for every decision of an allocator: the ``mode``, its
    risk index by name (None: costs from the task file), the index's thresholds ``v_th`` (a scalar or (p,);
    None without an index), its display ``scale`` (:attr:`~ergosim.ergonomics.risk_index.RiskIndex.scale`),
    the ``human`` agent and the ``robots``. :func:`ergosim.viz.reason.reason_text` words it."""

    mode: str
    index: str | None
    v_th: float | tuple[float, ...] | None
    scale: float
    human: str
    robots: tuple[str, ...]


@dataclasses.dataclass(frozen=True)
class SequenceChoice:
    """Why a look-ahead decision (``kwear-lookahead``) chose as it did: the ``steps`` ((action, agent) in
    order) of the cheapest sequence it starts, that sequence's ``cost``, ``other``, the cheapest sequence that
    gives the action to another agent (NaN if not computed), whether the search was ``exact``, and the beam's
    ``gap`` from the optimum otherwise."""

    steps: tuple[tuple[str, str], ...]
    cost: float
    other: float
    exact: bool
    gap: float


@dataclasses.dataclass(frozen=True)
class Decision:
    """What the allocator saw and chose at one decision point (sim time [s]), and why, as data.

    ``v_now`` (5,) KWear; ``v_hat``: action -> predicted risk (p,) of the index in use; ``costs``: the
    (action, agent) costs the planner got; ``had_choice``: more than one agent could take ``action``;
    ``basis``: what the choice is judged by. Parallel execution adds ``through``, the cost of the cheapest
    plan through the chosen hyper-arc, ``excess``, how much that exceeds the optimal plan (0: the agent
    follows it), and ``early`` with ``part``: the agent fetches ``part`` for a handover before the
    operation's other children exist. A look-ahead decision adds ``sequence``
    (:class:`SequenceChoice`). The sentence the recording and the video show is
    :func:`ergosim.viz.reason.reason_text`.
    """

    time: float
    repetition: int
    v_now: np.ndarray
    v_hat: Mapping[str, np.ndarray]
    costs: Mapping[tuple[str, str], float]
    action: str
    agent: str
    operation: str
    had_choice: bool
    basis: Basis
    through: float = float("nan")
    excess: float = 0.0
    early: bool = False
    part: str = ""
    sequence: SequenceChoice | None = None

    def cost_of(self, agent: str) -> float:
        return float(self.costs.get((self.action, agent), np.nan))


class DecisionPoint(NamedTuple):
    """Where the loop asks for the next (action, agent): the arguments of
    :meth:`Allocator.decide` (KWear (5,), the operations done, the pruned and declined
    (action, agent) pairs, sim time [s], repetition)."""

    v_now: np.ndarray
    done: list[str]
    pruned: set[tuple[str, str]]
    time: float
    repetition: int


class Allocator:
    """Decides the next (action, agent) for one worker and its robots on an AND/OR graph.

    ``mode``: a registered :class:`~ergosim.twin.modes.Mode`; ``index``: the risk index whose prediction
    sets the human's costs (None for modes without one); ``cost``: Γ, V_th, c_r (eq. 10-11); ``w_time`` and
    ``durations``: the time term, w_time × expected duration per (action, agent) (0: the paper's cost).
    ``refused``: (action, robot) pairs the robot cannot do in this cell (its gripper, payload or reach,
    :func:`ergosim.twin.robot_refusals.robot_refusals`): taken from the task for the whole run, as if
    the task did not allow them.
    """

    def __init__(self, graph: AndOrGraph, mode: Mode, *, index: RiskIndex | None, cost: CostParams | None,
                 planner: str = "fast", w_time: float = 0.0,
                 durations: Mapping[tuple[str, str], float] | None = None, tie: str = PAPER_TIE_RULE,
                 refused: frozenset[tuple[str, str]] = frozenset()) -> None:
        self.graph = graph
        self.mode = mode
        self.index = index
        self.cost = cost
        self.planner = planner
        kinds = {a.name: a.kind for a in graph.agents}
        self.human = next(n for n, k in kinds.items() if k == "human")
        self.robots = tuple(n for n, k in kinds.items() if k == "robot")
        self.robot = self.robots[0] if self.robots else None
        self.allowed: dict[str, set[str]] = {}
        for op in graph.operations:
            self.allowed.setdefault(op.action, set()).update(op.agents)
        for action, agent in refused:
            self.allowed.get(action, set()).discard(agent)
        self.base_pruned = mode.pruned(self.allowed, self.human, self.robots) | set(refused)
        self._action_of = {op.name: op.action for op in graph.operations}
        self.w_time = float(w_time)
        """Weight of the time term [cost per s]: w_time × expected duration is added to every hyper-arc."""
        self.durations = dict(durations or {})
        """(action, agent) -> expected duration [s] (ergosim.twin.durations)."""
        self.tie = tie
        """Which ready step of an optimal plan goes first (ergosim.planner.tie_break)."""
        self.basis = Basis(mode.name, mode.risk_index, None if cost is None else cost.v_th,
                           1.0 if index is None else index.scale, self.human, self.robots)

    def prepare(self, *, cfg, cell, robots, human_seconds: Mapping[str, float]) -> None:
        """Before the first decision: the time term's expected durations (protocol ``w_time`` > 0) from the
        cell, its robots (name -> RobotTrack) and the worker's calibrated ``human_seconds``."""
        if cfg.team.w_time > 0:
            self.w_time = cfg.team.w_time
            self.durations = expected_durations(cell, robots, self.allowed, self.human, human_seconds)

    def observe(self, action: str, agent: str, seconds: float) -> None:
        """``agent`` completed ``action`` in ``seconds`` (not a handover's span in parallel execution, which
        includes its wait); the paper's rule does not use it."""

    def action_of(self, operation: str) -> str:
        return self._action_of[operation]

    def price(self, remaining: list[str]):
        """What the planner is given for the ``remaining`` actions: (V̂ per action, the costs (eq. 10-11,
        with the time term where the mode prices the action), the time term of the other hyper-arcs)."""
        costs: dict[tuple[str, str], float] = {}
        v_hat: dict[str, np.ndarray] = {}
        if self.index is not None:
            v_hat = {a: self.index.predict(a) for a in remaining}
            costs = risk_costs(self.index, remaining, self.human, list(self.robots), self.cost)
        added: dict[tuple[str, str], float] = {}
        if self.w_time > 0:
            left = set(remaining)
            for key, seconds in self.durations.items():
                if key[0] in left:
                    if key in costs:
                        costs[key] += self.w_time * seconds
                    else:
                        added[key] = self.w_time * seconds
        return v_hat, costs, added

    def ready(self, done: list[str], pruned: set[tuple[str, str]]) -> dict[tuple[str, str], str]:
        """(action, agent) -> the operation it would do now: the first operation (in task order) of each
        action whose children all exist, for each agent allowed on it and not pruned (by the mode or
        ``pruned``)."""
        config = set(self.graph.configuration(done))
        cut = self.base_pruned | pruned
        out: dict[tuple[str, str], str] = {}
        for op in self.graph.operations:
            if op.name in done or not set(op.children) <= config:
                continue
            for agent in op.agents:
                if (op.action, agent) not in cut:
                    out.setdefault((op.action, agent), op.name)
        return out

    def excluded(self, pruned: set[tuple[str, str]]) -> set[tuple[str, str]]:
        """The (action, agent) pairs this mode leaves out of its decisions now: the mode's and the robots'
        refusals for the run, and the repetition's failures ``pruned``."""
        return self.base_pruned | pruned

    def chosen(self, action: str, agent: str, v_now: np.ndarray, done: list[str],
               pruned: set[tuple[str, str]], time: float, repetition: int) -> Decision | None:
        """The :class:`Decision` for an (action, agent) chosen by someone else (a Gym policy), with this
        mode's prices for the record; None if the pair cannot start now (:meth:`ready`)."""
        operation = self.ready(done, pruned).get((action, agent))
        if operation is None:
            return None
        done_actions = {self._action_of[o] for o in done}
        v_hat, costs, _ = self.price([a for a in self.graph.actions if a not in done_actions])
        cut = self.excluded(pruned)
        agents = self.allowed[action] - {a for (act, a) in cut if act == action}
        return Decision(time=time, repetition=repetition, v_now=np.array(v_now), v_hat=v_hat, costs=costs,
                        action=action, agent=agent, operation=operation, had_choice=len(agents) > 1,
                        basis=self.basis)

    def decide(self, v_now: np.ndarray, done: list[str], pruned: set[tuple[str, str]], time: float,
               repetition: int) -> Decision | None:
        done_actions = {self._action_of[o] for o in done}
        remaining = [a for a in self.graph.actions if a not in done_actions]
        if not remaining:
            return None
        v_hat, costs, added = self.price(remaining)
        cut = self.base_pruned | pruned
        step = next_step(self.graph, done, costs=costs, pruned=cut, planner=self.planner, added=added or None,
                         rule=self.tie)
        if step is None:
            return None
        agents = self.allowed[step.action] - {a for (act, a) in cut if act == step.action}
        return Decision(
            time=time, repetition=repetition, v_now=np.array(v_now), v_hat=v_hat, costs=costs,
            action=step.action, agent=step.agent, operation=step.operation, had_choice=len(agents) > 1,
            basis=self.basis,
        )

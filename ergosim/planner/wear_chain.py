"""Wear chained along a plan: each worker action priced from the wear the plan's earlier actions leave.

The paper prices every worker hyper-arc from the wear *now* (eq. 9-11): V̂ = 1 − α(1 − V(t_k)). Those
prices do not depend on the order of the plan's actions, so a plan that puts the worker's riskiest action
first costs the same as one that puts it last. The look-ahead instead walks the plan and predicts V after
each of its actions:

- the worker does action a:  V ← 1 − α_a (1 − V)                (eq. 9, from the V the plan has reached),
  priced c = Σ_i γ_i(V)                                        (eq. 10-11: V̂_i, + Γ where V̂_i ≥ V_th,i);
- the worker rests s seconds: V ← V e^{−(r/C) s}                (eq. 5, the recovery branch of eq. 3),
  while a robot acts (its predicted duration) or while the worker waits for another agent;
- a robot does the action: its constant cost c_r               (§4).

Two time terms are added to the paper's form: ``takt_weight`` × the seconds by which the plan's predicted
end passes the takt (those the plan adds: an overrun already incurred is the same for every plan), and
``time_weight`` × the plan's predicted duration (its critical path when agents work in parallel). With
both weights 0 and every action priced from V(t_k), the cost is the paper's.

A plan ends with its repetition; the wear it leaves is priced as the next repetition would see it
(``next_weight``, :func:`next_cost`), so rest at a repetition's end counts as much as rest at its start.

Arrays: p risk channels (the five KWear joints), A actions (the graph's ``actions`` order), N agents (the
graph's ``agents`` order). Times in seconds, costs dimensionless.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ergosim.ergonomics.cost import CostParams
from ergosim.ergonomics.kwear import KWearParams
from ergosim.errors import ConfigError

__all__ = ["WearModel", "SequencePrice", "rest_factor", "worker_prices", "next_cost", "price_sequence",
           "takt_penalty"]


def rest_factor(seconds, rest_rate: float):
    """e^{−(r/C) s}: what eq. 5 multiplies V by over ``seconds`` of rest (scalar or array)."""
    return np.exp(-rest_rate * np.asarray(seconds, dtype=float))


def takt_penalty(end, deadline: float, weight: float):
    """``weight`` × the seconds by which ``end`` passes ``deadline`` (0 before it)."""
    return weight * np.maximum(0.0, np.asarray(end, dtype=float) - deadline)


@dataclass(frozen=True, eq=False)
class WearModel:
    """What the look-ahead prices a plan with, for one worker and its robots.

    ``alpha`` (A, p): the worker's calibrated α per action (eq. 9; rows of actions the worker may not do
    are 1, no wear). ``rest_rate``: r/C [1/s] of eq. 5. ``cost``: Γ, V_th and c_r (eq. 10-11).
    ``agent_cost`` (N,): c_r of each robot, NaN for the worker. ``duration`` (A, N): expected duration of
    each (action, agent) [s], 0 where unknown. ``rest`` (A, N): the seconds of that duration the worker
    rests while a robot acts (a robot's handover ends with the worker taking the part: that take is not
    rest; its wear is not predicted). ``takt`` [s], ``takt_weight`` [cost per s past the takt],
    ``time_weight`` [cost per s of the plan's duration]. ``next_weight``: weight of the wear the plan leaves
    to the next repetition (:func:`next_cost`); ``robot_ok`` (A,): actions some robot may do. ``leave``
    (A, N): the seconds a robot still needs after the operation is done before it is free again (its way
    home after letting the part go, in parallel execution; default 0: the operation ends with the robot
    home).
    """

    actions: tuple[str, ...]
    agents: tuple[str, ...]
    human: int
    alpha: np.ndarray
    rest_rate: float
    cost: CostParams
    agent_cost: np.ndarray
    duration: np.ndarray
    rest: np.ndarray
    takt: float = math.inf
    takt_weight: float = 0.0
    time_weight: float = 0.0
    next_weight: float = 0.0
    robot_ok: np.ndarray | None = None
    leave: np.ndarray | None = None
    v_th: np.ndarray = field(init=False, repr=False)
    action_index: dict = field(init=False, repr=False)
    agent_index: dict = field(init=False, repr=False)

    def __post_init__(self) -> None:
        a, n = len(self.actions), len(self.agents)
        alpha = np.array(self.alpha, dtype=float)
        if alpha.ndim != 2 or alpha.shape[0] != a or not np.all((alpha > 0) & (alpha <= 1)):
            raise ConfigError(f"alpha must be ({a}, p) values in (0, 1], got shape {alpha.shape}",
                              where="WearModel.alpha")
        for name in ("duration", "rest"):
            arr = np.array(getattr(self, name), dtype=float)
            if arr.shape != (a, n) or not np.all(np.isfinite(arr) & (arr >= 0)):
                raise ConfigError(f"{name} must be ({a}, {n}) finite seconds >= 0", where=f"WearModel.{name}")
            object.__setattr__(self, name, arr)
        leave = np.zeros((a, n)) if self.leave is None else np.array(self.leave, dtype=float)
        if leave.shape != (a, n) or not np.all(np.isfinite(leave) & (leave >= 0)):
            raise ConfigError(f"leave must be ({a}, {n}) finite seconds >= 0", where="WearModel.leave")
        object.__setattr__(self, "leave", leave)
        robot_ok = np.ones(a, dtype=bool) if self.robot_ok is None else np.array(self.robot_ok, dtype=bool)
        if robot_ok.shape != (a,):
            raise ConfigError(f"robot_ok must be ({a},) booleans", where="WearModel.robot_ok")
        object.__setattr__(self, "robot_ok", robot_ok)
        for name in ("rest_rate", "takt_weight", "time_weight", "next_weight"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ConfigError(f"{name} must be finite and >= 0, got {value!r}", where=f"WearModel.{name}")
        if not self.takt > 0:
            raise ConfigError(f"takt must be > 0 s, got {self.takt!r}", where="WearModel.takt")
        th = np.broadcast_to(np.asarray(self.cost.v_th, dtype=float), (alpha.shape[1],)).copy()
        object.__setattr__(self, "alpha", alpha)
        object.__setattr__(self, "agent_cost", np.array(self.agent_cost, dtype=float))
        object.__setattr__(self, "v_th", th)
        object.__setattr__(self, "action_index", {x: i for i, x in enumerate(self.actions)})
        object.__setattr__(self, "agent_index", {x: i for i, x in enumerate(self.agents)})

    @classmethod
    def build(cls, actions: Sequence[str], agents: Sequence[str], human: str, *,
              alphas: Mapping[str, object], kwear: KWearParams, cost: CostParams,
              durations: Mapping[tuple[str, str], float] | None = None,
              takes: Mapping[tuple[str, str], float] | None = None,
              robot_costs: Mapping[str, float] | None = None, takt: float = math.inf,
              takt_weight: float = 0.0, time_weight: float = 0.0, next_weight: float = 0.0,
              robot_actions: Sequence[str] | None = None,
              leaves: Mapping[tuple[str, str], float] | None = None) -> WearModel:
        """From the run's dictionaries: ``alphas`` action -> (p,) α; ``durations`` (action, agent) -> s;
        ``takes`` (action, robot) -> the worker's seconds at the end of a robot's handover; ``robot_costs``
        robot -> c_r (default ``cost.robot_cost`` for every agent but ``human``); ``robot_actions``: the
        actions some robot may do (default all); ``leaves`` (action, robot) -> the robot's seconds after
        the operation is done (default none)."""
        actions, agents = tuple(actions), tuple(agents)
        if human not in agents:
            raise ConfigError(f"unknown human agent {human!r}; agents are {list(agents)}", where="WearModel")
        p = len(next(iter(alphas.values()))) if alphas else 5
        alpha = np.ones((len(actions), p))
        for i, a in enumerate(actions):
            if a in alphas:
                alpha[i] = np.asarray(alphas[a], dtype=float)
        duration = np.zeros((len(actions), len(agents)))
        for (a, agent), seconds in (durations or {}).items():
            if a in actions and agent in agents:
                duration[actions.index(a), agents.index(agent)] = seconds
        rest = duration.copy()
        rest[:, agents.index(human)] = 0.0
        for (a, agent), seconds in (takes or {}).items():
            if a in actions and agent in agents:
                i, j = actions.index(a), agents.index(agent)
                rest[i, j] = max(0.0, duration[i, j] - seconds)
        leave = np.zeros_like(duration)
        for (a, agent), seconds in (leaves or {}).items():
            if a in actions and agent in agents and agent != human:
                leave[actions.index(a), agents.index(agent)] = seconds
        agent_cost = np.array([math.nan if x == human else float((robot_costs or {}).get(x, cost.robot_cost))
                               for x in agents])
        robot_ok = None if robot_actions is None else np.array([a in set(robot_actions) for a in actions])
        return cls(actions, agents, agents.index(human), alpha, kwear.r / kwear.C, cost, agent_cost, duration,
                   rest, takt=takt, takt_weight=takt_weight, time_weight=time_weight, next_weight=next_weight,
                   robot_ok=robot_ok, leave=leave)

    def price(self, v_hat: np.ndarray) -> np.ndarray:
        """Eq. 10-11 for predictions (..., p): Σ_i V̂_i + Γ·[V̂_i ≥ V_th,i] (as
        :func:`~ergosim.ergonomics.cost.human_cost`, without its per-call checks: the searches call it per
        step)."""
        over = v_hat >= self.v_th
        return v_hat.sum(axis=-1) + self.cost.gamma * over.sum(axis=-1)


def next_cost(model: WearModel, v) -> np.ndarray:
    """The wear a plan leaves, priced as the next repetition: ``next_weight`` × Σ over the actions of the
    cheaper of the worker's order-free price from ``v`` (..., p) (eq. 9-11) and the cheapest robot's c_r
    (where a robot may do it) -> (...). Without it, rest at a repetition's end would be worth nothing to the
    plan and rest at its start everything: the look-ahead would give robots the first actions."""
    if model.next_weight == 0:
        return np.zeros(np.shape(v)[:-1])
    robot = np.nanmin(model.agent_cost) if np.isfinite(model.agent_cost).any() else np.inf
    cap = np.where(model.robot_ok, robot, np.inf)
    return model.next_weight * np.minimum(worker_prices(model, v), cap).sum(axis=-1)


def worker_prices(model: WearModel, v: np.ndarray) -> np.ndarray:
    """The paper's order-free prices from wear ``v`` (..., p): eq. 9-11 for every action -> (..., A)."""
    v_hat = 1.0 - model.alpha * (1.0 - np.asarray(v, dtype=float)[..., None, :])
    return model.price(v_hat)


@dataclass(frozen=True)
class SequencePrice:
    """A sequential plan priced along its chain: ``total`` = ``ergonomic`` (Σ worker prices, eq. 10-11 on
    the chained V̂) + ``robot`` (Σ c_r) + ``takt`` + ``time`` + ``next`` (:func:`next_cost` of ``v_end``);
    ``v_hat`` (k, p) the V after each step (for a robot step, after its rest); ``v_end`` (p,); ``end``: the
    predicted time after the plan, from the repetition's start [s]."""

    total: float
    ergonomic: float
    robot: float
    takt: float
    time: float
    next: float
    v_hat: np.ndarray
    v_end: np.ndarray
    end: float


def price_sequence(model: WearModel, v0, elapsed: float, steps: Sequence[tuple[str, str]]) -> SequencePrice:
    """Price ``steps`` ((action, agent) in execution order, one agent at a time) from wear ``v0`` (p,) at
    ``elapsed`` seconds into the repetition: the chain of the module docstring."""
    v = np.array(v0, dtype=float)
    t = float(elapsed)
    ergonomic = robot = 0.0
    trail = []
    for action, agent in steps:
        i, j = model.action_index[action], model.agent_index[agent]
        if j == model.human:
            v = 1.0 - model.alpha[i] * (1.0 - v)
            ergonomic += float(model.price(v))
        else:
            v = v * math.exp(-model.rest_rate * model.rest[i, j])
            robot += float(model.agent_cost[j])
        t += model.duration[i, j]
        trail.append(v.copy())
    takt = float(takt_penalty(t, model.takt, model.takt_weight) - takt_penalty(elapsed, model.takt,
                                                                                  model.takt_weight))
    time = model.time_weight * (t - elapsed)
    after = float(next_cost(model, v))
    return SequencePrice(ergonomic + robot + takt + time + after, ergonomic, robot, takt, time, after,
                         np.array(trail).reshape(len(trail), v.size), v, t)

"""Hyper-arc costs from predicted risk (paper eq. 2, 10, 11) and the static RULA baseline rule.

Human hyper-arc (eq. 10-11): c = sum_i gamma_i with gamma_i = V_hat_i, plus Gamma when V_hat_i >= V_th,i.
Robot hyper-arc: a constant c_r, which should satisfy V_th < c_r < V_max + Gamma (paper §4); otherwise a
:class:`CostRangeWarning` is issued. The result is the ``{(action, agent): cost}`` mapping that the
planner's ``graph.plan(done=..., costs=..., pruned=...)`` consumes.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ergosim.errors import ConfigError

__all__ = [
    "CostRangeWarning",
    "CostParams",
    "gamma_terms",
    "human_cost",
    "hyperarc_costs",
    "risk_costs",
    "rula_baseline_params",
    "rula_baseline_agent",
    "G_MAX_PAPER",
]

G_MAX_PAPER = 9.0
"""G_max of the paper's RULA baseline (§7.1): the maximum of Table A; the grand score stops at 7."""


class CostRangeWarning(UserWarning):
    """Cost parameters outside the paper's recommended range (V_th < c_r < V_max + Gamma, Gamma > V_max)."""


@dataclass(frozen=True)
class CostParams:
    """Cost model constants. ``v_th``: V_th, scalar or per channel (tuple); ``gamma``: Gamma;
    ``robot_cost``: c_{h,w_r}; ``v_max``: the largest value the risk can take (KWear: 0.993).

    Paper values: experiment 1 Gamma = 100, V_th = 0.8, c_r = 50; experiment 2 c_r = 2.5.
    """

    gamma: float = 100.0
    v_th: float | tuple[float, ...] = 0.8
    robot_cost: float = 50.0
    v_max: float = 0.993

    def __post_init__(self) -> None:
        th = np.atleast_1d(np.asarray(self.v_th, dtype=float))
        for name, ok in (("gamma", math.isfinite(self.gamma) and self.gamma > 0),
                         ("v_th", th.size > 0 and bool(np.all(np.isfinite(th) & (th > 0)))),
                         ("robot_cost", math.isfinite(self.robot_cost) and self.robot_cost > 0),
                         ("v_max", math.isfinite(self.v_max) and 0 < self.v_max <= 1)):
            if not ok:
                raise ConfigError(f"{name} = {getattr(self, name)!r} is out of range (gamma, robot_cost > 0; "
                                  f"v_th > 0; 0 < v_max <= 1)", where=f"CostParams.{name}")
        if not isinstance(self.v_th, (int, float)):
            object.__setattr__(self, "v_th", tuple(float(x) for x in th))
        v_th_max = float(th.max())
        if not v_th_max < self.robot_cost < self.v_max + self.gamma:
            warnings.warn(f"robot cost c_r = {self.robot_cost} is outside V_th < c_r < V_max + Gamma "
                          f"({v_th_max} < c_r < {self.v_max + self.gamma}): the threshold no longer decides "
                          f"the allocation as in the paper (§4)", CostRangeWarning, stacklevel=3)
        if not self.gamma > self.v_max:
            warnings.warn(f"Gamma = {self.gamma} should exceed V_max = {self.v_max} (paper §4)",
                          CostRangeWarning, stacklevel=3)


def gamma_terms(v_hat, params: CostParams) -> np.ndarray:
    """gamma_i of eq. 11 for predictions v_hat (..., p): V_hat_i, + Gamma where V_hat_i >= V_th,i."""
    v = np.asarray(v_hat, dtype=float)
    th = np.asarray(params.v_th, dtype=float)
    if th.ndim and th.shape[0] != v.shape[-1]:
        raise ConfigError(f"v_th has {th.shape[0]} values but the risk has {v.shape[-1]} channels",
                          where="CostParams.v_th")
    return v + params.gamma * (v >= th)


def human_cost(v_hat, params: CostParams) -> np.ndarray:
    """Human hyper-arc cost (eq. 10-11): sum over the last axis of :func:`gamma_terms`; (..., p) -> (...)."""
    return gamma_terms(v_hat, params).sum(axis=-1)


def hyperarc_costs(v_hat: Mapping[str, object], humans: str | Sequence[str], robots: Iterable[str],
                   params: CostParams) -> dict[tuple[str, str], float]:
    """``{(action, agent): cost}`` for the planner. v_hat: action -> (p,) predicted risk if the human
    executes it; every human agent gets eq. 10-11, every robot the constant ``params.robot_cost``."""
    humans = (humans,) if isinstance(humans, str) else tuple(humans)
    robots = tuple(robots)
    actions = list(v_hat)
    out: dict[tuple[str, str], float] = {}
    if not actions:
        return out
    costs = human_cost(np.array([np.asarray(v_hat[a], dtype=float) for a in actions]), params)
    for a, c in zip(actions, costs.tolist()):
        for h in humans:
            out[(a, h)] = c
        for r in robots:
            out[(a, r)] = params.robot_cost
    return out


def risk_costs(index, actions: Iterable[str], humans: str | Sequence[str], robots: Iterable[str],
               params: CostParams) -> dict[tuple[str, str], float]:
    """:func:`hyperarc_costs` for candidate ``actions`` predicted by a
    :class:`~ergosim.ergonomics.risk_index.RiskIndex` from its current state (eq. 9 for KWear)."""
    return hyperarc_costs({a: index.predict(a) for a in actions}, humans, robots, params)


def rula_baseline_params(robot_cost: float = 50.0, gamma: float = 100.0, g_th: float | None = None,
                         g_max: float = G_MAX_PAPER) -> CostParams:
    """Cost constants for :class:`~ergosim.ergonomics.risk_index.StaticRulaIndex` (risk G/g_max):
    V_th = g_th / g_max, with g_th = 0.8 g_max by default (7.2 with the paper's g_max = 9), V_max = 1."""
    g_th = 0.8 * g_max if g_th is None else g_th
    return CostParams(gamma=gamma, v_th=g_th / g_max, robot_cost=robot_cost, v_max=1.0)


def rula_baseline_agent(g_action: float, g_th: float = 0.8 * G_MAX_PAPER) -> str:
    """The static RULA rule itself: ``"robot"`` when G(a_k) >= g_th, else ``"human"``."""
    return "robot" if g_action >= g_th else "human"

"""Allocation modes and risk indices, each registered in one place.

A :class:`Mode` brings everything that differs between modes: the risk index whose prediction prices the
worker's hyper-arcs (or none), the pruning of hyper-arcs before every decision (paper §2.2), whether the
worker waits for the takt, and the decision's reason text. A risk index is registered by name with a
factory that builds it, and its cost rule, for one subject's run.

Bundled modes:

- ``hrc``: KWear-driven allocation (eq. 9-11), the paper's framework;
- ``rula``: the static RULA baseline of §7.1 (a constant G(a_k) per action against G_th);
- ``h-only``: the worker does everything and waits for the takt (§7.2's H only);
- ``r-only``: every action a robot may do goes to a robot;
- ``kwear-lookahead``: the paper's KWear costs chained along the plan, with recovery and the takt; the next
  (action, agent) starts the cheapest sequence (:mod:`ergosim.twin.lookahead_allocator`).

Add a mode with :func:`register_mode` (a new module that calls it is enough), a risk index with
:func:`register_risk_index`. A mode that decides differently from AO* on the order-free costs brings its own
allocator factories (``allocator``, ``team_allocator``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping

import numpy as np

from ergosim.ergonomics.cost import CostParams, rula_baseline_params
from ergosim.ergonomics.risk_index import RiskIndex, StaticRulaIndex
from ergosim.errors import ConfigError
from ergosim.plugins import note_caller
from ergosim.viz.reason import allocation_reason

__all__ = ["Mode", "RiskIndexEntry", "IndexContext", "register_mode", "register_risk_index", "get_mode",
           "mode_or_default", "mode_names", "risk_index_names", "get_risk_index"]


@dataclasses.dataclass(frozen=True)
class IndexContext:
    """What a risk-index factory may use: the scenario protocol, the subject's online KWear index (fed by
    the plant every ergonomics tick) and its calibration (α, G(a_k), η)."""

    protocol: object
    kwear: RiskIndex
    calibration: object


Pruning = Callable[[Mapping[str, set[str]], str, tuple[str, ...]], set[tuple[str, str]]]
"""(allowed agents per action, the human agent, the robot agents) -> pruned (action, agent) pairs."""


@dataclasses.dataclass(frozen=True)
class RiskIndexEntry:
    """``build(ctx)`` -> (the index, its cost rule); ``reason(action, agent, v_hat, costs, index, cost, human,
    robots)`` -> the decision's text."""

    name: str
    build: Callable[[IndexContext], tuple[RiskIndex, CostParams]]
    reason: Callable[..., str]


@dataclasses.dataclass(frozen=True)
class Mode:
    """An allocation mode. ``risk_index``: registered index name, or None (costs from the task file);
    ``prune``: hyper-arcs removed before every decision; ``waits_for_takt``: the worker starts a repetition
    only at its takt slot.

    What the outputs make of it: ``uses_robot`` False (the worker alone) leaves the mode out of the
    allocation histogram and, unless something failed, out of the printed allocation tables;
    ``table_key``: the key of the mode's H/R table under ``allocation_table`` in summary.json (paper
    Table 1), None for none; ``paired_with``: a mode this one is compared with, subject by subject
    (Wilcoxon signed-rank on the load proxies, paper §7.2), when both are run."""

    name: str
    description: str
    risk_index: str | None = None
    prune: Pruning | None = None
    waits_for_takt: bool = False
    uses_robot: bool = True
    table_key: str | None = None
    paired_with: str | None = None
    allocator: Callable[..., object] | None = None
    """Builds the mode's sequential allocator from (graph, mode, index=, cost=, planner=); None: the paper's
    :class:`~ergosim.twin.allocator.Allocator` (AO* on the order-free costs)."""
    team_allocator: Callable[..., object] | None = None
    """Builds its parallel decisions from (allocator, early=, margin=); None: the team rule of issue 17
    (:class:`~ergosim.twin.team_allocator.TeamAllocator`)."""

    def pruned(self, allowed: Mapping[str, set[str]], human: str,
               robots: tuple[str, ...]) -> set[tuple[str, str]]:
        return set() if self.prune is None else self.prune(allowed, human, robots)

    def reason(self, action: str, agent: str, v_hat, costs, index, cost, human: str,
               robots: tuple[str, ...]) -> str:
        if self.risk_index is None:
            return f"{action} → {agent}: {self.name} mode"
        return _INDICES[self.risk_index].reason(action, agent, v_hat, costs, index, cost, human, robots)


_MODES: dict[str, Mode] = {}
_INDICES: dict[str, RiskIndexEntry] = {}


def register_mode(mode: Mode) -> None:
    """Make ``mode`` available by name (``--mode``, a scenario's ``modes``), in worker processes too."""
    note_caller()
    _MODES[mode.name] = mode


def register_risk_index(entry: RiskIndexEntry) -> None:
    """Make a risk index available by name to the modes, in worker processes too."""
    note_caller()
    _INDICES[entry.name] = entry


def mode_names() -> tuple[str, ...]:
    return tuple(_MODES)


def risk_index_names() -> tuple[str, ...]:
    return tuple(_INDICES)


def mode_or_default(name: str) -> Mode:
    """The registered mode ``name``, or a plain :class:`Mode` of that name (outputs of a mode no longer
    registered are still summarised)."""
    return _MODES.get(name) or Mode(name, "unregistered mode")


def get_mode(name: str) -> Mode:
    try:
        return _MODES[name]
    except KeyError:
        raise ConfigError(f"unknown mode {name!r}; modes: {', '.join(_MODES)}", where="mode") from None


def get_risk_index(name: str) -> RiskIndexEntry:
    try:
        return _INDICES[name]
    except KeyError:
        raise ConfigError(f"unknown risk index {name!r}; indices: {', '.join(_INDICES)}",
                          where="mode") from None


# -- the bundled risk indices ------------------------------------------------------------------------------
def _kwear(ctx: IndexContext) -> tuple[RiskIndex, CostParams]:
    cfg = ctx.protocol
    return ctx.kwear, CostParams(gamma=cfg.gamma, v_th=cfg.v_th, robot_cost=cfg.robot_cost,
                                 v_max=ctx.kwear.params.v_max)


def _kwear_reason(action, agent, v_hat, costs, index, cost, human, robots) -> str:
    vh = np.asarray(v_hat[action])
    return allocation_reason((action, agent), v_hat=v_hat, costs=costs,
                             v_th=np.broadcast_to(np.asarray(cost.v_th, dtype=float), vh.shape))


def _rula(ctx: IndexContext) -> tuple[RiskIndex, CostParams]:
    cfg = ctx.protocol
    return (StaticRulaIndex(ctx.calibration.rula_scores, g_max=cfg.rula_g_max),
            rula_baseline_params(cfg.robot_cost, cfg.gamma, g_th=cfg.rula_threshold, g_max=cfg.rula_g_max))


def _rula_reason(action, agent, v_hat, costs, index, cost, human, robots) -> str:
    hc = costs.get((action, human))
    rc = min((costs[(action, r)] for r in robots if (action, r) in costs), default=float("nan"))
    th = float(np.max(cost.v_th))
    vh = np.asarray(v_hat[action])
    rel = "≥" if vh[int(np.argmax(vh))] >= th else "<"
    g_max = index.g_max
    return (f"{action} → {agent}: RULA G={vh[0] * g_max:g} {rel} G_th {th * g_max:g}"
            f" (human cost {hc:.2f}, robot cost {rc:.2f})")


register_risk_index(RiskIndexEntry("kwear", _kwear, _kwear_reason))
register_risk_index(RiskIndexEntry("rula-static", _rula, _rula_reason))


# -- the bundled modes ---------------------------------------------------------------------------------------
def _human_only(allowed, human, robots) -> set[tuple[str, str]]:
    return {(action, a) for action, agents in allowed.items() for a in agents if a != human}


def _robot_first(allowed, human, robots) -> set[tuple[str, str]]:
    return {(action, human) for action, agents in allowed.items() if agents & set(robots)}


register_mode(Mode("hrc", "KWear-driven allocation (paper eq. 9-11)", risk_index="kwear", table_key="kwear",
                   paired_with="h-only"))
register_mode(Mode("rula", "static RULA baseline (paper §7.1, Table 1)", risk_index="rula-static",
                   table_key="rula"))
register_mode(Mode("h-only", "the worker does everything and waits for the takt (paper §7.2)",
                   prune=_human_only, waits_for_takt=True, uses_robot=False))
register_mode(Mode("r-only", "every action a robot may do goes to a robot", prune=_robot_first))


def _lookahead(*args, **kwargs):
    from ergosim.twin.lookahead_allocator import LookaheadAllocator  # noqa: PLC0415 - it imports this module

    return LookaheadAllocator(*args, **kwargs)


def _lookahead_team(*args, **kwargs):
    from ergosim.twin.lookahead_team_allocator import LookaheadTeamAllocator  # noqa: PLC0415 - as above

    return LookaheadTeamAllocator(*args, **kwargs)


register_mode(Mode("kwear-lookahead", "KWear costs chained along the plan, with recovery and the takt",
                   risk_index="kwear", table_key="kwear-lookahead", paired_with="hrc", allocator=_lookahead,
                   team_allocator=_lookahead_team))

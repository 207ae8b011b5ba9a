"""The bundled allocation modes and risk indices, registered in :mod:`ergosim.twin.modes`'s registries when
either is first read (``Registry(builtins=...)``), in this order:

- ``hrc``: KWear-driven allocation (eq. 9-11), the paper's framework;
- ``rula``: the static RULA baseline of §7.1 (a constant G(a_k) per action against G_th);
- ``h-only``: the worker does everything and waits for the takt (§7.2's H only);
- ``r-only``: every action a robot may do goes to a robot;
- ``hrc-reba``: the same framework with KWear on REBA's part scores (the legs a sixth joint);
- ``reba``: a static REBA baseline (the REBA score G(a_k) against ``reba_threshold``);
- ``kwear-lookahead``: the paper's KWear costs chained along the plan, with recovery and the takt; the next
  (action, agent) starts the cheapest sequence (:mod:`ergosim.twin.lookahead_allocator`).

A mode of one's own is one module that calls :func:`~ergosim.twin.modes.register_mode` the same way.
"""

from __future__ import annotations

from ergosim.ergonomics.cost import CostParams
from ergosim.ergonomics.risk_index import REBA_G_MAX, RiskIndex, StaticRebaIndex, StaticRulaIndex
from ergosim.twin.lookahead_allocator import LookaheadAllocator
from ergosim.twin.lookahead_team_allocator import LookaheadTeamAllocator
from ergosim.twin.modes import IndexContext, Mode, RiskIndexEntry, register_mode, register_risk_index

__all__: list[str] = []


# -- the bundled risk indices ------------------------------------------------------------------------------
def _kwear(ctx: IndexContext) -> tuple[RiskIndex, CostParams]:
    return ctx.kwear, ctx.protocol.cost.params(ctx.kwear.params.v_max)


def _rula(ctx: IndexContext) -> tuple[RiskIndex, CostParams]:
    cost = ctx.protocol.cost
    return StaticRulaIndex(ctx.calibration.rula_scores, g_max=cost.rula_g_max), cost.rula_params()


def _reba(ctx: IndexContext) -> tuple[RiskIndex, CostParams]:
    return StaticRebaIndex(ctx.calibration.grand_scores), ctx.protocol.cost.reba_params(REBA_G_MAX)


register_risk_index(RiskIndexEntry("kwear", _kwear))
register_risk_index(RiskIndexEntry("rula-static", _rula))
register_risk_index(RiskIndexEntry("kwear-reba", _kwear, features="reba"))
register_risk_index(RiskIndexEntry("reba-static", _reba, features="reba"))


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
register_mode(Mode("hrc-reba", "KWear on REBA part scores, legs included (eq. 9-11 on REBA)",
                   risk_index="kwear-reba", table_key="kwear_reba", paired_with="h-only"))
register_mode(Mode("reba", "static REBA baseline (G(a_k) >= reba_threshold goes to the robot)",
                   risk_index="reba-static", table_key="reba"))
register_mode(Mode("kwear-lookahead", "KWear costs chained along the plan, with recovery and the takt",
                   risk_index="kwear", table_key="kwear-lookahead", paired_with="hrc",
                   allocator=LookaheadAllocator, team_allocator=LookaheadTeamAllocator))

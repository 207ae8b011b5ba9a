"""Allocation modes and risk indices: what a mode is, and the one registry of each.

A :class:`Mode` brings everything that differs between modes: the risk index whose prediction prices the
worker's hyper-arcs (or none), the pruning of hyper-arcs before every decision (paper §2.2) and whether the
worker waits for the takt. A risk index is registered by name with a factory that builds it, and its cost
rule, for one subject's run. A decision records why as data (:class:`~ergosim.twin.allocator.Basis`); the
words are :mod:`ergosim.viz.reason`'s.

The bundled modes and indices are :mod:`ergosim.twin.catalogue`'s, registered when either registry is
first read. Add a mode with :func:`register_mode` (a new module that calls it is enough), a risk index with
:func:`register_risk_index`. A mode that decides differently from AO* on the order-free costs brings its own
allocator factories (``allocator``, ``team_allocator``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

from ergosim.ergonomics.calibration import Calibration
from ergosim.ergonomics.cost import CostParams
from ergosim.ergonomics.risk_index import KWearIndex, RiskIndex
from ergosim.registry import Registry

if TYPE_CHECKING:
    from ergosim.twin.protocol import SessionConfig

__all__ = ["Mode", "RiskIndexEntry", "IndexContext", "MODES", "RISK_INDICES", "register_mode",
           "register_risk_index", "get_mode", "mode_or_default", "mode_names", "risk_index_names",
           "get_risk_index"]


@dataclasses.dataclass(frozen=True)
class IndexContext:
    """What a risk-index factory may use: the session's protocol, the subject's online KWear index on the
    index's feature (fed by the plant every ergonomics tick; on RULA's part scores for an index on raw
    angles) and its calibration on that feature (α, G(a_k), η)."""

    protocol: SessionConfig
    kwear: KWearIndex
    calibration: Calibration


Pruning = Callable[[Mapping[str, set[str]], str, tuple[str, ...]], set[tuple[str, str]]]
"""(allowed agents per action, the human agent, the robot agents) -> pruned (action, agent) pairs."""


@dataclasses.dataclass(frozen=True)
class RiskIndexEntry:
    """``build(ctx)`` -> (the index, its cost rule) for one subject's run; ``features``: the posture feature
    the index reads (the worker's online KWear of the run, its calibration and its tick columns follow it:
    ``rula`` or ``reba``; an index on ``angles`` runs beside the RULA KWear;
    :mod:`ergosim.ergonomics.features`). A decision's words are :mod:`ergosim.viz.reason`'s
    (``register_reason``)."""

    name: str
    build: Callable[[IndexContext], tuple[RiskIndex, CostParams]]
    features: str = "rula"


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


MODES: Registry[Mode] = Registry("mode", where="mode", builtins="ergosim.twin.catalogue")
"""The allocation modes by name (``--mode``, a scenario's ``modes``)."""
RISK_INDICES: Registry[RiskIndexEntry] = Registry("risk index", plural="risk indices", where="mode",
                                                  builtins="ergosim.twin.catalogue")
"""The risk indices by name (a mode's ``risk_index``)."""


def register_mode(mode: Mode) -> None:
    """Make ``mode`` available by name (``--mode``, a scenario's ``modes``), in worker processes too."""
    MODES.register(mode.name, mode)


def register_risk_index(entry: RiskIndexEntry) -> None:
    """Make a risk index available by name to the modes, in worker processes too."""
    RISK_INDICES.register(entry.name, entry)


def mode_names() -> tuple[str, ...]:
    return MODES.names()


def risk_index_names() -> tuple[str, ...]:
    return RISK_INDICES.names()


def mode_or_default(name: str) -> Mode:
    """The registered mode ``name``, or a plain :class:`Mode` of that name (outputs of a mode no longer
    registered are still summarised)."""
    return MODES[name] if name in MODES else Mode(name, "unregistered mode")


def get_mode(name: str) -> Mode:
    return MODES.get(name)


def get_risk_index(name: str) -> RiskIndexEntry:
    return RISK_INDICES.get(name)

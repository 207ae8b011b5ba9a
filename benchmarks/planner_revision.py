"""The look-ahead planner of another git revision, loaded beside this one: ``scripts/bench_planner.py
--lookahead --baseline REV`` times both in one process, decision by decision (:mod:`benchmarks.revision`).

Only the search modules (:data:`SEARCH_MODULES`) are the revision's; everything else (the graph, the
:class:`~ergosim.planner.wear_chain.WearModel`, the plan records) is this revision's, so both planners price
the same objects.
"""

from __future__ import annotations

import types

from benchmarks.revision import modules_at

__all__ = ["SEARCH_MODULES", "planner_at"]

SEARCH_MODULES = ("transitions", "pilot", "chain_pricing", "lookahead", "lookahead_team")
"""The look-ahead's search modules, in import order (each imports only earlier ones among them)."""


def planner_at(rev: str) -> types.SimpleNamespace:
    """``lookahead_plan`` and ``lookahead_team`` as git revision ``rev`` of this repository has them.

    Raises:
        ConfigError: ``rev`` is not a revision of the repository, or lacks one of the search modules.
    """
    mods = modules_at(rev, "ergosim.planner", SEARCH_MODULES)
    return types.SimpleNamespace(lookahead_plan=mods["lookahead"].lookahead_plan,
                                 lookahead_team=mods["lookahead_team"].lookahead_team)

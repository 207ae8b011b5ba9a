"""The look-ahead planner of another git revision, loaded beside this one: ``scripts/bench_planner.py
--lookahead --baseline REV`` times both in one process, decision by decision, so that both see the same
machine load (the only fair speed ratio on a shared machine).

The search modules (:data:`SEARCH_MODULES`) are read with ``git show REV:path`` and executed under private
module names, their imports of one another redirected to those copies; everything else (the graph, the
:class:`~ergosim.planner.wear_chain.WearModel`, the plan records) is this revision's, so both planners price
the same objects.
"""

from __future__ import annotations

import re
import subprocess
import sys
import types
from pathlib import Path

from ergosim.errors import ConfigError

__all__ = ["SEARCH_MODULES", "planner_at"]

SEARCH_MODULES = ("transitions", "pilot", "chain_pricing", "lookahead", "lookahead_team")
"""The look-ahead's search modules, in import order (each imports only earlier ones among them)."""

ROOT = Path(__file__).resolve().parents[2]


def planner_at(rev: str) -> types.SimpleNamespace:
    """``lookahead_plan`` and ``lookahead_team`` as git revision ``rev`` of this repository has them.

    Raises:
        ConfigError: ``rev`` is not a revision of the repository, or lacks one of the search modules.
    """
    tag = re.sub(r"\W", "_", rev)
    names = {m: f"_rev_{tag}_{m}" for m in SEARCH_MODULES}
    pattern = re.compile(r"\bergosim\.planner\.(" + "|".join(SEARCH_MODULES) + r")\b")
    mods = {}
    for m in SEARCH_MODULES:
        path = f"ergosim/planner/{m}.py"
        out = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:{path}"], check=False,
                             capture_output=True, text=True)
        if out.returncode:
            raise ConfigError(f"cannot read {path} at revision {rev!r}: {out.stderr.strip()}",
                              where="--baseline")
        mod = types.ModuleType(names[m])
        sys.modules[mod.__name__] = mod  # dataclasses look their module up by name
        src = pattern.sub(lambda hit: names[hit.group(1)], out.stdout)
        exec(compile(src, f"{rev}:{path}", "exec"), mod.__dict__)  # noqa: S102 - our own code, at rev
        mods[m] = mod
    return types.SimpleNamespace(lookahead_plan=mods["lookahead"].lookahead_plan,
                                 lookahead_team=mods["lookahead_team"].lookahead_team)

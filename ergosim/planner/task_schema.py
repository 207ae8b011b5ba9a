"""The task file's tables (docs/task_format.md) as a schema: the keys each table takes, and the tree that
``--set task.PATH=VALUE`` walks (:func:`ergosim.schema.document.override`).

Paths follow the file's tables: ``name``, ``description``, ``parts``, ``agents.<agent>.<kind|cost>``,
``liaisons.<action>.<agents|cost.<agent>|parts>`` (a liaison is named by its action label),
``operations.<name>.<agents|cost.<agent>|action|joins|father>``. A ``--set`` string becomes the TOML value
the field takes: names split at commas (``agents=human``), children as ``A+B,C`` (``joins``), a number
(``cost``), else a string. The task reader (:mod:`ergosim.planner.taskfile`) checks the result like the file.
"""

from __future__ import annotations

from ergosim.schema.document import Keyed, Listed, Named, Tree, table
from ergosim.schema.values import JOINS, NUMBER, RAW, Names, Text

__all__ = ["TASK", "TopTable", "AgentTable", "LiaisonTable", "OperationTable"]

_S, _N = Text(empty=True), Names()
TopTable = table("TopTable", ("agents", "operations", "liaisons", "precedence"), name=_S, description=_S,
                 parts=_N, agents=RAW, operations=RAW, liaisons=RAW, precedence=RAW)
AgentTable = table("AgentTable", kind=_S, cost=NUMBER)
LiaisonTable = table("LiaisonTable", ("cost",), parts=_N, action=_S, agents=_N, cost=RAW)
OperationTable = table("OperationTable", ("cost",), name=_S, action=_S, joins=JOINS, father=_N, agents=_N,
                       cost=RAW)

_COSTS = {"cost": Keyed(NUMBER, of="agents")}
TASK = Tree(TopTable, {
    "agents": Named(Tree(AgentTable)),
    "liaisons": Listed(Tree(LiaisonTable, _COSTS), label="action"),
    "operations": Listed(Tree(OperationTable, _COSTS), label="name"),
})
"""The task file as a tree of tables, for overrides."""

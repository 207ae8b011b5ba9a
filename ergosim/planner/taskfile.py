"""Task files (TOML): explicit operations, liaisons with precedence constraints, or both mixed.

See docs/task_format.md for the format. Every problem raises one :class:`~ergosim.errors.TaskFileError`
(or :class:`~ergosim.errors.InfeasiblePlanError` when the task has no feasible plan) whose text names
the file, the entry and what was expected.
"""

from __future__ import annotations

import os
import stat
import tomllib
from pathlib import Path
from typing import Any

from ergosim.errors import InfeasiblePlanError, TaskFileError
from ergosim.planner.agents import Agent, Operation, check_cost, check_name
from ergosim.planner.graph import AndOrGraph
from ergosim.planner.liaisons import Liaison, generate_operations, liaison_groups
from ergosim.planner.limits import check_operation_count, check_part_count
from ergosim.planner.task_schema import AgentTable, LiaisonTable, OperationTable, TopTable
from ergosim.planner.validation import format_parts
from ergosim.schema.document import check_keys

__all__ = ["load_task", "parse_task", "task_from_dict", "MAX_TASK_BYTES"]

MAX_TASK_BYTES = 64 << 20
"""Largest task file read [bytes]; a task at the operation limit (MAX_OPERATIONS) is far smaller."""


def load_task(path: str | os.PathLike[str]) -> AndOrGraph:
    """Read and build the task file at ``path`` (a regular file of at most :data:`MAX_TASK_BYTES`)."""
    p = Path(path)
    try:
        st = p.stat()
        if not stat.S_ISREG(st.st_mode):
            what = "a directory" if stat.S_ISDIR(st.st_mode) else "not a regular file (a device or a pipe?)"
            raise TaskFileError(f"{what}; expected a task file (.toml)", where=str(path))
        if st.st_size > MAX_TASK_BYTES:
            raise TaskFileError(f"{st.st_size} bytes, more than the limit of {MAX_TASK_BYTES} "
                                "(ergosim.planner.taskfile.MAX_TASK_BYTES)", where=str(path))
        with p.open("rb") as f:  # read at most the limit, should the file grow meanwhile
            data = f.read(MAX_TASK_BYTES + 1)
        text = data[:MAX_TASK_BYTES].decode("utf-8")
    except FileNotFoundError:
        raise TaskFileError("no such task file", where=str(path)) from None
    except (OSError, UnicodeDecodeError) as err:
        raise TaskFileError(f"cannot read the task file: {err}", where=str(path)) from None
    if len(data) > MAX_TASK_BYTES:
        raise TaskFileError(f"more than the limit of {MAX_TASK_BYTES} bytes", where=str(path))
    return parse_task(text, source=str(path))


def parse_task(text: str, source: str = "<task>") -> AndOrGraph:
    """Build the AND/OR graph of the task file contents ``text``; ``source`` names it in messages."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise TaskFileError(f"invalid TOML: {err}", where=source) from None
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise TaskFileError("nested too deeply to be a task file (arrays or inline tables inside each other "
                            "hundreds of levels deep)", where=source) from None
    return _Builder(doc, source).build()


def task_from_dict(doc: dict[str, Any], source: str = "<task>") -> AndOrGraph:
    """Build the AND/OR graph of an already parsed task document (e.g. a scenario's inline ``[task]``)."""
    return _Builder(doc, source).build()


def _few(items, n: int = 12) -> str:
    """A list for a message, cut after ``n`` items (a task may have thousands of parts)."""
    items = list(items)
    if len(items) <= n:
        return str(items)
    return f"[{', '.join(map(repr, items[:n]))}, ... ({len(items)} in all)]"


def _fail(what: str, where: str) -> TaskFileError:
    return TaskFileError(what, where=where)


class _Builder:
    def __init__(self, doc: dict[str, Any], source: str) -> None:
        self.doc = doc
        self.source = source

    def at(self, entry: str) -> str:
        return f"{self.source}: {entry}"

    def build(self) -> AndOrGraph:
        doc = self.doc
        check_keys(TopTable, doc, self.source, error=TaskFileError)
        name = doc.get("name", Path(self.source).stem)
        if not isinstance(name, str) or not name:
            raise _fail(f"name must be a non-empty string, got {name!r}", self.at("name"))
        self.parts = self.read_parts()
        self.agents = self.read_agents()
        ops, origins = self.read_operations()
        liaisons = self.read_liaisons()
        self.check_actions_unique(ops, liaisons)
        precedence = self.read_precedence(liaisons)
        if not ops and not liaisons and len(self.parts) > 1:
            raise _fail("a task needs [[operations]] or [[liaisons]]", self.source)
        explicit = {}
        for op in ops:
            explicit.setdefault(self.mask(op.father), []).append([self.mask(c) for c in op.children])
        self.check_connected(ops, liaisons)
        generated = generate_operations(
            self.parts,
            liaisons,
            precedence,
            [a.name for a in self.agents],
            explicit_children=explicit,
            where=self.at("precedence"),
        )
        for op, first in generated:
            origins[op.name] = f"liaisons[{first}] (operation {op.name!r})"
        actions = []
        for key in doc:  # actions in the order they first appear in the file
            if key == "liaisons":
                actions += [lia.action for lia in liaisons]
            elif key == "operations":
                actions += [op.action for op in ops]
        return AndOrGraph(
            name,
            self.parts,
            self.agents,
            ops + [op for op, _ in generated],
            actions=list(dict.fromkeys(actions)),
            source=self.source,
            origins=origins,
        )

    def mask(self, parts: tuple[str, ...]) -> int:
        index = self.part_index
        return sum(1 << index[p] for p in parts)

    def read_parts(self) -> list[str]:
        parts = self.doc.get("parts")
        if not isinstance(parts, list) or not parts:
            raise _fail(f"parts must be a non-empty list of part names, got {parts!r}", self.at("parts"))
        check_part_count(len(parts), self.at("parts"), TaskFileError)
        seen: set[str] = set()
        for i, part in enumerate(parts):
            problem = check_name(part, "a part name")
            if problem:
                raise _fail(problem, self.at(f"parts[{i}]"))
            if part in seen:
                raise _fail(f"duplicate part name {part!r}", self.at(f"parts[{i}]"))
            seen.add(part)
        # part -> position: every later lookup is a dict access, so reading stays linear in the file's size
        self.part_index = {p: i for i, p in enumerate(parts)}
        return parts

    def read_agents(self) -> list[Agent]:
        table = self.doc.get("agents")
        if not isinstance(table, dict) or not table:
            raise _fail(
                "agents must be a table of [agents.<name>] tables, with at least one", self.at("agents")
            )
        agents = []
        for name, spec in table.items():
            at = self.at(f"agents.{name}")
            check_keys(AgentTable, spec, at, error=TaskFileError)
            cost = spec.get("cost", 1.0)
            problem = check_name(name, "an agent name") or check_cost(cost, "cost")
            if problem:
                raise _fail(problem, at)
            kind = spec.get("kind")
            if kind not in ("human", "robot"):
                raise _fail(f"kind must be 'human' or 'robot', got {kind!r}", at)
            agents.append(Agent(name, kind, float(cost)))
        return agents

    def read_part_list(self, value: Any, what: str, at: str) -> tuple[str, ...]:
        if not isinstance(value, list) or not all(isinstance(p, str) for p in value):
            raise _fail(f"{what} must be a list of part names, got {value!r}", at)
        index = self.part_index
        for part in value:
            if part not in index:
                raise _fail(f"unknown part {part!r} in {what}; parts are {_few(self.parts)}", at)
        return tuple(sorted(value, key=index.__getitem__))

    def read_agent_costs(self, entry: dict[str, Any], at: str) -> tuple[tuple[str, ...], tuple[float, ...]]:
        """The allowed agents (default: all) and their costs (fixed ``cost`` entries or agent defaults)."""
        names = [a.name for a in self.agents]
        allowed = entry.get("agents", names)
        if not isinstance(allowed, list) or not all(isinstance(a, str) for a in allowed):
            raise _fail(f"agents must be a list of agent names, got {allowed!r}", at)
        for agent in allowed:
            if agent not in names:
                raise _fail(f"unknown agent {agent!r}; agents are {names}", at)
        if len(set(allowed)) != len(allowed):
            raise _fail(f"an agent is listed twice in {allowed}", at)
        fixed = entry.get("cost", {})
        if not isinstance(fixed, dict):
            raise _fail(f"cost must be a table agent = cost, got {fixed!r}", at)
        for agent, value in fixed.items():
            if agent not in names:
                raise _fail(f"unknown agent {agent!r} in cost; agents are {names}", at)
            if agent not in allowed:
                raise _fail(f"cost given for agent {agent!r}, who may not do this (agents = {allowed})", at)
            problem = check_cost(value, f"cost.{agent}")
            if problem:
                raise _fail(problem, at)
        order = [a for a in names if a in allowed]
        default = {a.name: a.cost for a in self.agents}
        return tuple(order), tuple(float(fixed.get(a, default[a])) for a in order)

    def entries(self, key: str) -> list[dict[str, Any]]:
        value = self.doc.get(key, [])
        if not isinstance(value, list) or not all(isinstance(e, dict) for e in value):
            raise _fail(f"{key} must be an array of tables ([[{key}]])", self.at(key))
        return value

    def read_operations(self) -> tuple[list[Operation], dict[str, str]]:
        ops, origins = [], {}
        entries = self.entries("operations")
        check_operation_count(len(entries), self.at("operations"), TaskFileError)
        for i, entry in enumerate(entries):
            name = entry.get("name")
            at = self.at(f"operations[{i}]" + (f" {name!r}" if isinstance(name, str) else ""))
            check_keys(OperationTable, entry, at, error=TaskFileError)
            if not isinstance(name, str) or not name:
                raise _fail(f"name must be a non-empty string, got {name!r}", at)
            if name in origins:
                raise _fail(f"duplicate operation name {name!r} (first at {origins[name]})", at)
            joins = entry.get("joins")
            if not isinstance(joins, list):
                raise _fail(f"joins must be a list of children (lists of parts), got {joins!r}", at)
            children = tuple(self.read_part_list(c, f"joins[{k}]", at) for k, c in enumerate(joins))
            union = tuple(sorted({p for c in children for p in c}, key=self.part_index.__getitem__))
            father = self.read_part_list(entry["father"], "father", at) if "father" in entry else union
            agents, costs = self.read_agent_costs(entry, at)
            action = entry.get("action", name)
            ops.append(Operation(name, action, father, children, agents, costs))
            origins[name] = f"operations[{i}] {name!r}"
        return ops, origins

    def read_liaisons(self) -> list[Liaison]:
        liaisons, pairs = [], {}
        for i, entry in enumerate(self.entries("liaisons")):
            at = self.at(f"liaisons[{i}]")
            check_keys(LiaisonTable, entry, at, error=TaskFileError)
            parts = self.read_part_list(entry.get("parts"), "parts", at)
            if len(parts) != 2 or parts[0] == parts[1]:
                raise _fail(f"a liaison connects exactly two different parts, got {list(entry['parts'])}", at)
            if parts in pairs:
                raise _fail(
                    f"duplicate liaison between {parts[0]!r} and {parts[1]!r} (first at {pairs[parts]})", at
                )
            pairs[parts] = f"liaisons[{i}]"
            action = entry.get("action")
            if not isinstance(action, str) or not action or "," in action or "+" in action:
                raise _fail(f"action must be a non-empty label without ',' or '+', got {action!r}", at)
            agents, costs = self.read_agent_costs(entry, at)
            liaisons.append(Liaison(parts[0], parts[1], action, agents, costs))
        return liaisons

    def check_actions_unique(self, ops: list[Operation], liaisons: list[Liaison]) -> None:
        """One label = one physical action: no two hand-written operations or liaisons share an action (the
        operations generated from one liaison do, as they are its one join made in different orders)."""
        first: dict[str, str] = {}
        entries = [(f"operations[{i}] {op.name!r}", op.action) for i, op in enumerate(ops)]
        entries += [(f"liaisons[{i}]", lia.action) for i, lia in enumerate(liaisons)]
        for at, action in entries:
            if action in first:
                raise _fail(f"action {action!r} is also the action of {first[action]}: one label is one "
                            "physical action; give each its own label", self.at(at))
            first[action] = at

    def read_precedence(self, liaisons: list[Liaison]) -> list[tuple[str, str]]:
        known = {lia.action for lia in liaisons}
        pairs = []
        for i, entry in enumerate(self.entries("precedence")):
            at = self.at(f"precedence[{i}]")
            if set(entry) != {"before", "after"}:
                raise _fail("a precedence constraint has exactly the keys before and after", at)
            sides = []
            for key in ("before", "after"):
                value = entry[key]
                value = [value] if isinstance(value, str) else value
                if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
                    raise _fail(f"{key} must be an action label or a list of them, got {entry[key]!r}", at)
                for action in value:
                    if action not in known:
                        raise _fail(
                            f"unknown action {action!r} in {key}: precedence orders liaison actions "
                            f"({sorted(known)})",
                            at,
                        )
                sides.append(value)
            for before in sides[0]:
                for after in sides[1]:
                    if before == after:
                        raise _fail(f"action {before!r} cannot come before itself", at)
                    pairs.append((before, after))
        return pairs

    def check_connected(self, ops: list[Operation], liaisons: list[Liaison]) -> None:
        """Every part is in some entry; without a hand-written root operation, liaisons connect them all."""
        used = {p for op in ops for p in op.father} | {p for lia in liaisons for p in (lia.a, lia.b)}
        for i, part in enumerate(self.parts):
            if len(self.parts) > 1 and part not in used:
                raise InfeasiblePlanError(
                    f"no feasible plan: part {part!r} can never be joined: "
                    "no liaison or operation includes it",
                    where=self.at(f"parts[{i}] {part!r}"),
                )
        everything = tuple(self.parts)
        if not liaisons or any(op.father == everything for op in ops):
            return
        groups = liaison_groups(self.parts, liaisons)
        if len(groups) > 1:
            raise InfeasiblePlanError(
                f"no feasible plan: the liaisons leave the parts in unconnected groups "
                f"{' '.join(format_parts(g) for g in groups)} and no operation joins the full assembly",
                where=self.at("liaisons"),
            )

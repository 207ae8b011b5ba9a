"""A file format as a tree of pydantic tables, the check of one table, and the one dotted-path override.

A format (the workcell, the task) is a :class:`Tree`: its table (a :class:`Table` model, whose fields are
:mod:`ergosim.schema.values` kinds) and its sub-tables, each a table of its own (``[worker]``), a table of
named tables (``[parts.NAME]``: :class:`Named`), an array of tables named by one of their fields
(``[[liaisons]]`` by ``action``: :class:`Listed`) or numbers keyed by the names of another table
(``cost.<agent>``: :class:`Keyed`). :func:`check_table` validates a TOML table against its model and turns
pydantic's errors into one :class:`~ergosim.errors.ErgosimError` naming the file and the entry;
:func:`override` sets ``--set`` values by dotted path (``parts.L.xy``, ``liaisons.a2.cost.robot``) in a
copy of a document, each string converted by the kind of the field it sets.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Callable, Mapping
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError, create_model

from ergosim.errors import ConfigError, ErgosimError
from ergosim.schema.values import Invalid, Kind

__all__ = ["Table", "table", "Tree", "Named", "Listed", "Keyed", "check_keys", "check_table", "kinds",
           "settable", "paths", "override"]


class Table(BaseModel):
    """A table of a file: its fields are kinds (``Annotated[Any, NUMBER]``); a field declared
    ``Field(frozen=True)`` names its table (a furniture's ``type``) and is not set by an override."""

    model_config = ConfigDict(extra="forbid")


def table(title: str, fixed: tuple[str, ...] = (), /, **fields: Kind) -> type[Table]:
    """A :class:`Table` model named ``title`` with ``fields`` (key -> kind, in the file's order), each
    optional; the ``fixed`` ones name their table and are not set by an override."""
    return create_model(title, __base__=Table, **{
        key: (Annotated[Any, kind], Field(None, frozen=key in fixed)) for key, kind in fields.items()})


def kinds(model: type[Table]) -> dict[str, Kind]:
    """Field -> kind of a table model, in declaration order."""
    fields = model.model_fields.items()
    return {name: next(m for m in f.metadata if isinstance(m, Kind)) for name, f in fields}


def settable(model: type[Table]) -> list[str]:
    """The fields of ``model`` an override may set."""
    return [name for name, f in model.model_fields.items() if not f.frozen]


def check_keys(model: type[Table], given: Any, where: str, required: tuple[str, ...] = (),
               error: type[ErgosimError] = ConfigError) -> None:
    """``given`` is a table with only keys of ``model`` and every ``required`` one; else one ``error`` at
    ``where``."""
    if not isinstance(given, dict):
        raise error(f"expected a table, got {given!r}", where=where)
    unknown = sorted(set(given) - set(model.model_fields))
    if unknown:
        raise error(f"unknown key {unknown[0]!r}; valid keys: {', '.join(model.model_fields)}", where=where)
    missing = [k for k in required if k not in given]
    if missing:
        raise error(f"missing key {missing[0]!r}", where=where)


def check_table(model: type[Table], given: Any, where: str, required: tuple[str, ...] = (),
                error: type[ErgosimError] = ConfigError, top: bool = False) -> dict[str, Any]:
    """The fields the table ``given`` gives (name -> checked value, in its order), validated by ``model``;
    ``required`` fields must be given. A problem is one ``error``: at ``where`` for a table that is none,
    an unknown or a missing key, at ``where.FIELD`` for a bad value (the first in the table's order;
    ``where: FIELD`` for the ``top`` table of a file, ``where`` being the file)."""
    check_keys(model, given, where, required, error)
    try:
        checked = model.model_validate(given)
    except ValidationError as err:
        order = list(given)
        first = min(err.errors(), key=lambda e: order.index(e["loc"][0]) if e["loc"] else -1)
        what = first["ctx"]["what"] if first["type"] == "ergosim" else first["msg"]
        raise error(what, where=(": " if top else ".").join([where, *map(str, first["loc"][:1])])) from None
    return {k: getattr(checked, k) for k in given}


@dataclasses.dataclass(frozen=True)
class Tree:
    """A table (``model``; a function of the document's table when its fields depend on it, as a
    furniture's on its ``type``) and its sub-tables by key."""

    model: type[Table] | Callable[[Mapping[str, Any]], type[Table]]
    children: Mapping[str, Named | Listed | Keyed | Tree] = dataclasses.field(default_factory=dict)

    def table(self, doc: Mapping[str, Any]) -> type[Table]:
        return self.model if isinstance(self.model, type) else self.model(doc)


@dataclasses.dataclass(frozen=True)
class Named:
    """A table of named tables, each a ``tree``: ``[parts.L]``."""

    tree: Tree


@dataclasses.dataclass(frozen=True)
class Listed:
    """An array of tables, each a ``tree``, named in a path by its ``label`` field: ``[[liaisons]]`` by
    ``action``."""

    tree: Tree
    label: str


@dataclasses.dataclass(frozen=True)
class Keyed:
    """Values of ``kind`` keyed by the names of the document's table ``of`` (``cost.<agent>``)."""

    kind: Kind
    of: str


def _entries(child: Named | Listed, node: Any) -> list[tuple[str, Any]]:
    """(name, table) of the entries of a sub-table that exist in the document."""
    if isinstance(child, Named):
        return [(k, v) for k, v in node.items() if isinstance(v, dict)] if isinstance(node, dict) else []
    rows = node if isinstance(node, list) else []
    return [(e[child.label], e) for e in rows if isinstance(e, dict) and isinstance(e.get(child.label), str)]


def paths(tree: Tree, doc: Mapping[str, Any], root: Mapping[str, Any] | None = None) -> list[str]:
    """Every dotted path of ``doc`` an override may set: the fields of its tables and of the entries that
    exist, in the schema's order."""
    root = doc if root is None else root
    out = [k for k in settable(tree.table(doc)) if k not in tree.children]
    for key, child in tree.children.items():
        if isinstance(child, Keyed):
            out += [f"{key}.{name}" for name in (root.get(child.of) or {})]
        elif isinstance(child, Tree):
            out += [f"{key}.{p}" for p in paths(child, doc.get(key) or {}, root)]
        else:
            for name, entry in _entries(child, doc.get(key)):
                inner = paths(child.tree, entry, root)
                out += [f"{key}.{name}.{p}" for p in inner
                        if not (isinstance(child, Listed) and p == child.label)]
    return out


def override(tree: Tree, doc: Mapping[str, Any], values: Mapping[str, Any], where: str,
             error: type[ErgosimError] = ConfigError, said: Callable[[str], str] = str,
             unknown: Callable[[str, list[str]], str] | None = None) -> dict[str, Any]:
    """A deep copy of ``doc`` with ``values`` (dotted path -> a ``--set`` string, or a value already typed)
    set. A string is converted by the kind of the field it sets, its errors naming ``said(path)`` (the key
    as the user gave it); a path that is not in :func:`paths` is an error, ``unknown(path, paths)`` its
    message (default: some valid paths)."""
    out = copy.deepcopy(dict(doc))
    for path, raw in values.items():
        kind = _kind_at(tree, out, path.split("."), out)
        if kind is None:
            valid = paths(tree, out)
            what = unknown(path, valid) if unknown else \
                f"unknown key {path!r}; valid keys include: {', '.join(valid[:12])}, ..."
            raise error(what, where=where)
        try:
            value = kind.parse(raw, said(path)) if isinstance(raw, str) else raw
        except Invalid as err:
            raise error(err.what, where=where) from None
        _set(tree, out, path.split("."), list(value) if isinstance(value, tuple) else value)
    return out


def _kind_at(tree: Tree, node: Any, parts: list[str], root: Mapping[str, Any]) -> Kind | None:
    if not isinstance(node, dict) or not parts:
        return None
    head, rest = parts[0], parts[1:]
    child = tree.children.get(head)
    if child is None:
        model = tree.table(node)
        return kinds(model)[head] if not rest and head in settable(model) else None
    if isinstance(child, Keyed):
        return child.kind if len(rest) == 1 and rest[0] in (root.get(child.of) or {}) else None
    if isinstance(child, Tree):
        return _kind_at(child, node.get(head) or {}, rest, root)
    if not rest:
        return None
    entry = dict(_entries(child, node.get(head))).get(rest[0])
    if entry is None or isinstance(child, Listed) and rest[1:] == [child.label]:
        return None
    return _kind_at(child.tree, entry, rest[1:], root)


def _set(tree: Tree, node: dict, parts: list[str], value: Any) -> None:
    head, rest = parts[0], parts[1:]
    child = tree.children.get(head)
    if not rest:
        node[head] = value
    elif isinstance(child, Keyed):
        table = node.get(head)
        node[head] = table = dict(table) if isinstance(table, dict) else {}
        table[rest[0]] = value
    elif isinstance(child, Tree):
        _set(child, node.setdefault(head, {}), rest, value)
    else:
        entry = dict(_entries(child, node[head]))[rest[0]]
        _set(child.tree, entry, rest[1:], value)

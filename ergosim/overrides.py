"""Override fields of a frozen config dataclass by name, from ``KEY=VALUE`` strings (``--set``).

Configuration is code (frozen dataclasses with ``default_config()``); a field's type annotation gives its
value kind (:func:`ergosim.schema.values.kind_of`), the same kinds that convert the ``--set`` strings of the
workcell and task files (:func:`ergosim.schema.document.override`), so every file and config gets the same
conversions and errors.
"""

from __future__ import annotations

import dataclasses
import functools
import typing
from collections.abc import Iterable, Mapping
from typing import Any

from ergosim.errors import ConfigError
from ergosim.schema.document import Tree, kinds, override, table
from ergosim.schema.values import Invalid, finite_float, kind_of

__all__ = ["parse_assignments", "apply_overrides", "field_names", "flat_values", "replace_flat",
           "finite_float",
           "list_fields"]



def parse_assignments(items: Iterable[str], *, where: str = "--set") -> dict[str, str]:
    """``["a=1", "scene.b=x"]`` -> ``{"a": "1", "scene.b": "x"}``; a malformed item is a ConfigError."""
    out: dict[str, str] = {}
    for item in items:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ConfigError(f"expected KEY=VALUE, got {item!r}", where=where)
        out[key] = value.strip()
    return out


def field_names(cfg: Any) -> tuple[str, ...]:
    """The keys a user sets on ``cfg``: its fields, and the fields of its groups (fields that are frozen
    dataclasses themselves) by their own names, which are unique."""
    return tuple(_flat_fields(type(cfg)))


def list_fields(cls: type) -> frozenset[str]:
    """The flat keys of the config dataclass ``cls`` that hold a tuple (a list in a file, a comma list in
    ``--set``)."""
    return frozenset(k for k, (_, hint) in _flat_fields(cls).items() if typing.get_origin(hint) is tuple)


def _flat_fields(cls: type) -> dict[str, tuple[str | None, Any]]:
    """Flat key -> (the group field holding it, or None; its type hint), in declaration order."""
    out: dict[str, tuple[str | None, Any]] = {}
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        if not f.init or f.name.startswith("_"):
            continue
        hint = hints[f.name]
        if dataclasses.is_dataclass(hint):
            inner = typing.get_type_hints(hint)
            out.update((g.name, (f.name, inner[g.name])) for g in dataclasses.fields(hint)
                       if g.init and not g.name.startswith("_"))
        else:
            out[f.name] = (None, hint)
    return out


def flat_values(cfg: Any) -> dict[str, Any]:
    """Every settable field of ``cfg`` by its flat key (see :func:`field_names`)."""
    return {k: getattr(cfg if group is None else getattr(cfg, group), k)
            for k, (group, _) in _flat_fields(type(cfg)).items()}


def replace_flat(cfg: Any, changes: Mapping[str, Any]) -> Any:
    """A copy of ``cfg`` with ``changes`` (flat key -> value, already typed) applied to it and its groups."""
    fields = _flat_fields(type(cfg))
    top: dict[str, Any] = {}
    groups: dict[str, dict[str, Any]] = {}
    for key, value in changes.items():
        if key not in fields:
            raise TypeError(f"{type(cfg).__name__} has no field {key!r}")
        group = fields[key][0]
        if group is None:
            top[key] = value
        else:
            groups.setdefault(group, {})[key] = value
    top.update({g: dataclasses.replace(getattr(cfg, g), **v) for g, v in groups.items()})
    return dataclasses.replace(cfg, **top)


@functools.cache
def _config_tree(cls: type) -> Tree:
    """The config dataclass ``cls`` as one table of its flat keys, each of the kind its annotation gives."""
    return Tree(table(cls.__name__, **{k: kind_of(hint) for k, (_, hint) in _flat_fields(cls).items()}))


def apply_overrides(cfg: Any, overrides: Mapping[str, Any], *, where: str = "--set") -> Any:
    """A copy of the frozen dataclass ``cfg`` with ``overrides`` (by flat key, :func:`field_names`) applied
    and type-converted, by the one override of every file format (:func:`ergosim.schema.document.override`)
    over the table of its fields.

    Unknown keys raise :class:`ConfigError` listing the valid ones. If the dataclass defines
    ``validate()``, it runs on the result (range checks live with the config they guard).
    """
    if not overrides:
        return cfg
    tree = _config_tree(type(cfg))
    valid = ", ".join(_flat_fields(type(cfg)))
    doc = override(tree, {}, overrides, where,
                   unknown=lambda key, _: f"unknown key {key!r}; valid keys: {valid}")
    kinds_of = kinds(tree.table(doc))
    try:  # a value set as it was given (from a file) is checked here; a parsed string again, to its tuple
        changes = {key: kinds_of[key].check(value, key) for key, value in doc.items()}
    except Invalid as err:
        raise ConfigError(err.what, where=where) from None
    new = replace_flat(cfg, changes)
    validate = getattr(new, "validate", None)
    if callable(validate):
        validate(where=where)
    return new

"""Override fields of a frozen config dataclass by name, from ``KEY=VALUE`` strings (``--set``).

Configuration is code (frozen dataclasses with ``default_config()``); this module is the single place
that turns user strings into typed field values, so every scene and scenario gets the same errors.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Iterable, Mapping
from typing import Any

from ergosim.errors import ConfigError, ErgosimError, shown

__all__ = ["parse_assignments", "apply_overrides", "field_names", "flat_values", "replace_flat",
           "finite_float",
           "list_fields"]



def finite_float(raw: Any, name: str, *, where: str, error: type[ErgosimError] = ConfigError) -> float:
    """``raw`` (a number, or text such as a ``--set`` value) as a finite float, for every reader of user
    input. An error is one message form, ``NAME='RAW' is not a number`` (or ``... is not a finite number``),
    raised as ``error`` at ``where``; ``true``/``false`` are not numbers."""
    value = None
    if not isinstance(raw, bool):
        try:
            value = float(raw)
        except OverflowError:  # an integer beyond the largest float (10**400 is valid TOML)
            value = math.inf
        except (TypeError, ValueError):
            pass
    if value is None:
        raise error(f"{name}={shown(raw)} is not a number", where=where)
    if not math.isfinite(value):
        raise error(f"{name}={shown(raw)} is not a finite number", where=where)
    return value


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


def _convert(raw: Any, annotation: Any, key: str, where: str) -> Any:
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin in (typing.Union, getattr(__import__("types"), "UnionType", None)):
        errors = []
        for arg in args:
            if arg is type(None):
                if isinstance(raw, str) and raw.lower() in ("none", "null", ""):
                    return None
                continue
            try:
                return _convert(raw, arg, key, where)
            except ConfigError as err:
                errors.append(err.what)
        raise ConfigError(f"{key}={raw!r}: " + "; ".join(errors), where=where)
    if origin is typing.Literal:
        if raw in args:
            return raw
        raise ConfigError(f"{key}={raw!r} is not one of {', '.join(map(str, args))}", where=where)
    if origin is tuple:
        return _tuple(raw, args, key, where)
    if annotation is bool:
        if isinstance(raw, bool):
            return raw
        low = str(raw).lower()
        if low in ("1", "true", "yes", "on"):
            return True
        if low in ("0", "false", "no", "off"):
            return False
        raise ConfigError(f"{key}={raw!r} is not a boolean (true/false)", where=where)
    if annotation is int:
        try:
            return int(str(raw), 10) if not isinstance(raw, int) else raw
        except ValueError:
            raise ConfigError(f"{key}={raw!r} is not an integer", where=where) from None
    if annotation is float:
        return finite_float(raw, key, where=where)
    if annotation is str:
        return str(raw)
    return raw


def _tuple(raw: Any, args: tuple, key: str, where: str) -> tuple:
    """``"0.1,0.8"`` -> (0.1, 0.8). A fixed-length tuple must get exactly its number of values; a tuple of
    pairs (``tuple[tuple[str, float], ...]``) is written ``name:value,name:value``."""
    variable = len(args) == 2 and args[1] is Ellipsis
    elem = args[0] if args else str
    nested = typing.get_origin(elem) is tuple
    if isinstance(raw, (tuple, list)):
        parts = list(raw)
    else:
        text = str(raw).strip()
        parts = [p.strip() for p in text.split(",")] if text else []
        if any(not p for p in parts):
            raise ConfigError(f"{key}={raw!r} has an empty value between commas", where=where)
        if nested:
            parts = [p.split(":") for p in parts]
    if not variable and args and len(parts) != len(args):
        n, got = len(args), len(parts)
        raise ConfigError(f"{key}={raw!r} has {got} value{'s' if got != 1 else ''}, expected {n} "
                          f"(comma-separated, e.g. {key}={','.join(['0'] * n)})", where=where)
    width = len(typing.get_args(elem))
    if nested and any(not isinstance(p, (tuple, list)) or len(p) != width for p in parts):
        raise ConfigError(f"{key}={raw!r}: expected name:value pairs separated by commas, e.g. "
                          f"{key}=upper_arm:1.1,forearm:0.95", where=where)
    types = args if not variable and args else (elem,) * len(parts)
    return tuple(_convert(p, t, key, where) for p, t in zip(parts, types, strict=True))


def apply_overrides(cfg: Any, overrides: Mapping[str, Any], *, where: str = "--set") -> Any:
    """A copy of the frozen dataclass ``cfg`` with ``overrides`` (by flat key, :func:`field_names`) applied
    and type-converted.

    Unknown keys raise :class:`ConfigError` listing the valid ones. If the dataclass defines
    ``validate()``, it runs on the result (range checks live with the config they guard).
    """
    if not overrides:
        return cfg
    fields = _flat_fields(type(cfg))
    changes: dict[str, Any] = {}
    for key, raw in overrides.items():
        if key not in fields:
            raise ConfigError(f"unknown key {key!r}; valid keys: {', '.join(fields)}", where=where)
        changes[key] = _convert(raw, fields[key][1], key, where)
    new = replace_flat(cfg, changes)
    validate = getattr(new, "validate", None)
    if callable(validate):
        validate(where=where)
    return new

"""The value kinds of the file formats: what a TOML value must be, and how a ``--set`` string becomes one.

A kind checks a value read from a file (:meth:`Kind.check`, giving the Python value: tuples for vectors)
and converts the text of an override (:meth:`Kind.parse`, giving the TOML value a file would hold, or the
Python value for a config dataclass). A kind is also a pydantic type: written as ``Annotated[Any, NUMBER]``
in a schema model it validates that field, and a mistake becomes one line naming the field
(:mod:`ergosim.schema.document`). :func:`kind_of` gives the kind of a plain annotation (``float``,
``tuple[float, float]``, ``Literal[...]``), so a frozen config dataclass is overridden by the same code.
"""

from __future__ import annotations

import abc
import math
import types
import typing
from typing import Any

from pydantic_core import PydanticCustomError, core_schema

from ergosim.errors import ConfigError, ErgosimError, shown

__all__ = ["Kind", "Text", "Names", "Flag", "Number", "Integer", "Numbers", "Axis", "Pairs", "Choice",
           "Either", "Joins", "Raw", "TEXT", "NAMES", "FLAG", "NUMBER", "AXIS", "PAIRS", "JOINS", "RAW",
           "AXES",
           "finite_float", "kind_of", "Invalid"]

AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0),
        "-x": (-1.0, 0.0, 0.0), "-y": (0.0, -1.0, 0.0), "-z": (0.0, 0.0, -1.0)}
"""Axis names a slot's ``axis`` may be given by, as unit vectors."""


class Invalid(ValueError):
    """A value of the wrong kind; ``what`` is the message (the caller knows where it is)."""

    def __init__(self, what: str) -> None:
        super().__init__(what)
        self.what = what


def finite_float(raw: Any, name: str, *, where: str, error: type[ErgosimError] = ConfigError) -> float:
    """``raw`` (a number, or text such as a ``--set`` value) as a finite float, for every reader of user
    input. An error is one message form, ``NAME='RAW' is not a number`` (or ``... is not a finite number``),
    raised as ``error`` at ``where``; ``true``/``false`` are not numbers."""
    try:
        return _finite(raw, name)
    except Invalid as err:
        raise error(err.what, where=where) from None


def _finite(raw: Any, name: str) -> float:
    value = None
    if not isinstance(raw, bool):
        try:
            value = float(raw)
        except OverflowError:  # an integer beyond the largest float (10**400 is valid TOML)
            value = math.inf
        except (TypeError, ValueError):
            pass
    if value is None:
        raise Invalid(f"{name}={shown(raw)} is not a number")
    if not math.isfinite(value):
        raise Invalid(f"{name}={shown(raw)} is not a finite number")
    return value


def _items(raw: str, key: str) -> list[str]:
    """The comma-separated values of an override string; an empty one between commas is an error."""
    items = [s.strip() for s in raw.split(",")] if raw.strip() else []
    if any(not s for s in items):
        raise Invalid(f"{key}={raw!r} has an empty value between commas")
    return items


class Kind(abc.ABC):
    """A value kind. :meth:`check` a file's value (``name``: the field, for messages), :meth:`parse` an
    override string (``key``: the key as the user wrote it)."""

    @abc.abstractmethod
    def check(self, raw: Any, name: str) -> Any:
        """The checked value of ``raw``, or :class:`Invalid` saying what is wrong."""

    def parse(self, raw: str, key: str) -> Any:
        return self.check(raw, key)

    def __get_pydantic_core_schema__(self, source: Any, handler: Any) -> core_schema.CoreSchema:
        def validate(value: Any, info: core_schema.ValidationInfo) -> Any:
            try:
                return self.check(value, info.field_name or "value")
            except Invalid as err:
                raise PydanticCustomError("ergosim", "{what}", {"what": err.what}) from None

        return core_schema.with_info_plain_validator_function(validate)


class Text(Kind):
    """A non-empty string (``empty``: the empty string too)."""

    def __init__(self, empty: bool = False) -> None:
        self.empty = empty

    def check(self, raw: Any, name: str) -> str:
        if not isinstance(raw, str) or not (raw or self.empty):
            raise Invalid(f"expected a non-empty string, got {shown(raw)}")
        return raw

    def parse(self, raw: str, key: str) -> str:
        return raw


class Names(Kind):
    """A list of non-empty names; an override gives them separated by commas."""

    def __init__(self, empty: bool = True) -> None:
        self.empty = empty

    def check(self, raw: Any, name: str) -> tuple[str, ...]:
        items = raw.split(",") if isinstance(raw, str) else raw
        if not isinstance(items, list | tuple) or not all(isinstance(s, str) and s.strip() for s in items):
            raise Invalid(f"expected a list of names, got {shown(raw)}")
        return tuple(s.strip() for s in items)

    def parse(self, raw: str, key: str) -> list[str]:
        return [s.strip() for s in raw.split(",") if s.strip()]


class Flag(Kind):
    """true or false (an override also 1/0, yes/no, on/off)."""

    def check(self, raw: Any, name: str) -> bool:
        if isinstance(raw, bool):
            return raw
        low = str(raw).lower()
        if low in ("1", "true", "yes", "on"):
            return True
        if low in ("0", "false", "no", "off"):
            return False
        raise Invalid(f"{name}={shown(raw)} is not a boolean (true/false)")


class Number(Kind):
    """A finite number, as a float."""

    def check(self, raw: Any, name: str) -> float:
        return _finite(raw, name)


class Integer(Kind):
    """An integer (an override: its decimal digits)."""

    def check(self, raw: Any, name: str) -> int:
        if isinstance(raw, int) and not isinstance(raw, bool):
            return raw
        try:
            return int(str(raw), 10)
        except ValueError:
            raise Invalid(f"{name}={raw!r} is not an integer") from None


class Numbers(Kind):
    """``n`` finite numbers (``n`` None: any number of them); an override gives them separated by commas
    (``0.2,0.8``)."""

    def __init__(self, n: int | None) -> None:
        self.n = n

    def check(self, raw: Any, name: str) -> tuple[float, ...]:
        items = [s for s in raw.split(",") if s.strip()] if isinstance(raw, str) else raw
        if not isinstance(items, list | tuple):
            raise Invalid(f"expected {self.n} numbers, got {shown(raw)}")
        if self.n is not None and len(items) != self.n:
            raise Invalid(f"expected {self.n} numbers, got {len(items)} ({raw!r})")
        return tuple(_finite(x, name) for x in items)

    def parse(self, raw: str, key: str) -> list[float]:
        items = _items(raw, key)
        if self.n is not None and len(items) != self.n:
            got = len(items)
            raise Invalid(f"{key}={raw!r} has {got} value{'s' if got != 1 else ''}, expected {self.n} "
                          f"(comma-separated, e.g. {key}={','.join(['0'] * self.n)})")
        return [_finite(v, key) for v in items]


class Axis(Kind):
    """A direction: an axis name of :data:`AXES`, or 3 numbers (made a unit vector)."""

    def check(self, raw: Any, name: str) -> tuple[float, float, float]:
        if isinstance(raw, str):
            if raw not in AXES:
                raise Invalid(f"expected one of {', '.join(AXES)} or 3 numbers, got {raw!r}")
            return AXES[raw]
        v = Numbers(3).check(raw, name)
        n = math.sqrt(sum(x * x for x in v))
        if n < 1e-9:
            raise Invalid("the axis must not be zero")
        return tuple(x / n for x in v)

    def parse(self, raw: str, key: str) -> Any:
        return raw.strip() if raw.strip() in AXES else Numbers(3).parse(raw, key)


class Pairs(Kind):
    """(name, number) pairs: ``[[segment, factor], ...]`` in a file, ``name:value,name:value`` in an
    override."""

    def check(self, raw: Any, name: str) -> tuple[tuple[str, float], ...]:
        if not isinstance(raw, list | tuple) or not all(
                isinstance(p, list | tuple) and len(p) == 2 and isinstance(p[0], str) for p in raw):
            raise Invalid(f"expected [[segment, factor], ...] (a list of name, number pairs), got "
                          f"{shown(raw)}")
        return tuple((s, _finite(f, s)) for s, f in raw)

    def parse(self, raw: str, key: str) -> list[list[Any]]:
        pairs = [s.split(":") for s in _items(raw, key)]
        if not pairs or any(len(p) != 2 or not p[0].strip() for p in pairs):
            raise Invalid(f"{key}={raw!r}: expected name:value pairs separated by commas, e.g. "
                          f"{key}=upper_arm:1.1,forearm:0.95")
        return [[s.strip(), _finite(v.strip(), s.strip())] for s, v in pairs]


class Joins(Kind):
    """An operation's children: lists of part names; an override writes them ``A+B,C``."""

    def check(self, raw: Any, name: str) -> Any:
        return raw  # the task reader checks the parts against the task's

    def parse(self, raw: str, key: str) -> list[list[str]]:
        return [[p.strip() for p in child.split("+") if p.strip()] for child in raw.split(",")]


class Choice(Kind):
    """One of ``values`` (a ``Literal``)."""

    def __init__(self, values: tuple[Any, ...]) -> None:
        self.values = values

    def check(self, raw: Any, name: str) -> Any:
        if raw in self.values:
            return raw
        raise Invalid(f"{name}={raw!r} is not one of {', '.join(map(str, self.values))}")


class Either(Kind):
    """The first of ``kinds`` that takes the value; ``none``: None is allowed (text: none, null or empty)."""

    def __init__(self, kinds: tuple[Kind, ...], none: bool) -> None:
        self.kinds, self.none = kinds, none

    def check(self, raw: Any, name: str) -> Any:
        return self._first(raw, name, lambda kind: kind.check(raw, name))

    def parse(self, raw: str, key: str) -> Any:
        return self._first(raw, key, lambda kind: kind.parse(raw, key))

    def _first(self, raw: Any, name: str, take) -> Any:
        if self.none and (raw is None or isinstance(raw, str) and raw.lower() in ("none", "null", "")):
            return None
        errors = []
        for kind in self.kinds:
            try:
                return take(kind)
            except Invalid as err:
                errors.append(err.what)
        raise Invalid(f"{name}={raw!r}: " + "; ".join(errors))


class _Tuple(Kind):
    """A fixed tuple of kinds, or ``(kind, ...)`` of any length: a config dataclass's tuple field."""

    def __init__(self, kinds: tuple[Kind, ...], variable: bool) -> None:
        self.kinds, self.variable = kinds, variable

    def check(self, raw: Any, name: str) -> tuple:
        parts = list(raw) if isinstance(raw, tuple | list) else _items(str(raw), name)
        return self._typed(parts, raw, name, lambda kind, p: kind.check(p, name))

    def parse(self, raw: str, key: str) -> tuple:
        return self._typed(_items(raw, key), raw, key, lambda kind, p: kind.parse(p, key))

    def _typed(self, parts: list, raw: Any, key: str, take) -> tuple:
        if not self.variable and len(parts) != len(self.kinds):
            n, got = len(self.kinds), len(parts)
            raise Invalid(f"{key}={raw!r} has {got} value{'s' if got != 1 else ''}, expected {n} "
                          f"(comma-separated, e.g. {key}={','.join(['0'] * n)})")
        kinds = self.kinds * len(parts) if self.variable else self.kinds
        return tuple(take(kind, p) for kind, p in zip(kinds, parts, strict=True))


class _PairTuple(Pairs):
    """``tuple[tuple[str, float], ...]`` of a config dataclass: pairs, as a tuple."""

    def parse(self, raw: str, key: str) -> tuple[tuple[str, float], ...]:
        return tuple((s, v) for s, v in super().parse(raw, key))


class _Str(Kind):
    def check(self, raw: Any, name: str) -> str:
        return str(raw)


class Raw(Kind):
    """Any value, as it is (a sub-table the reader checks itself)."""

    def check(self, raw: Any, name: str) -> Any:
        return raw


TEXT, NAMES, FLAG, NUMBER, AXIS, PAIRS, JOINS, RAW = (
    Text(), Names(), Flag(), Number(), Axis(), Pairs(), Joins(), Raw())


def kind_of(annotation: Any) -> Kind:
    """The kind of a plain type annotation (a config dataclass's field): ``float``, ``int``, ``bool``,
    ``str``, ``Literal[...]``, ``X | None``, ``tuple[float, float]``, ``tuple[str, ...]``,
    ``tuple[tuple[str, float], ...]``."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin in (typing.Union, types.UnionType):
        return Either(tuple(kind_of(a) for a in args if a is not type(None)), none=type(None) in args)
    if origin is typing.Literal:
        return Choice(args)
    if origin is tuple:
        variable = len(args) == 2 and args[1] is Ellipsis
        if variable and typing.get_origin(args[0]) is tuple:
            return _PairTuple()
        return _Tuple(tuple(kind_of(a) for a in (args[:1] if variable else args)) or (RAW,), variable)
    return {bool: FLAG, int: Integer(), float: NUMBER, str: _Str()}.get(annotation, RAW)

"""One registry type for every extension point: scenarios, workcells, modes, risk indices, action kinds.

A :class:`Registry` is a dict of named items with ``register``, ``names`` and ``get`` (mujoco_playground's
registries). ``get`` of an unknown name is one :class:`~ergosim.errors.ConfigError` listing the valid names;
``registry[name]`` is a plain ``KeyError``, for code that has already checked the name. Registering notes
the calling module (:func:`ergosim.plugins.note_caller`), so worker processes import it too and a new
extension is one module whatever the number of processes. ``builtins`` names the module that registers the
bundled items (a catalogue apart from the registry, so the registry's module imports none of what the
items are built from); it is imported the first time the registry is used.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterator
from typing import Generic, TypeVar

from ergosim.errors import ConfigError
from ergosim.plugins import note_caller

__all__ = ["Registry"]

T = TypeVar("T")


class Registry(Generic[T]):
    """Named ``T`` s of one ``kind`` (e.g. ``"mode"``), in registration order.

    ``where`` names the input an unknown name came from in messages (``"mode"``, ``"scene"``); ``hint`` is
    added to them (``"or the path of a scenario file"``); ``plural`` defaults to ``kind + "s"``;
    ``builtins``: the module that registers the bundled items, imported on first use (they come first).
    """

    def __init__(self, kind: str, *, where: str, plural: str | None = None, hint: str = "",
                 builtins: str | None = None) -> None:
        self.kind = kind
        self.plural = plural or f"{kind}s"
        self.where = where
        self.hint = hint
        self._builtins = builtins
        self._entries: dict[str, T] = {}

    @property
    def _items(self) -> dict[str, T]:
        """The items, the bundled ones registered first."""
        if self._builtins is not None:
            module, self._builtins = self._builtins, None
            importlib.import_module(module)
        return self._entries

    def register(self, name: str, item: T) -> None:
        """Make ``item`` available as ``name`` (replacing an earlier one of that name), in worker processes
        too."""
        note_caller()
        self._items[name] = item

    def unregister(self, name: str) -> None:
        """Forget ``name`` (nothing happens if it is not registered)."""
        self._items.pop(name, None)

    def names(self) -> tuple[str, ...]:
        return tuple(self._items)

    def get(self, name: str) -> T:
        """The item ``name``; a ConfigError naming the valid ones if there is none."""
        try:
            return self._items[name]
        except KeyError:
            hint = f" ({self.hint})" if self.hint else ""
            raise ConfigError(f"unknown {self.kind} {name!r}; valid {self.plural}: {', '.join(self._items)}"
                              f"{hint}", where=self.where) from None

    def __getitem__(self, name: str) -> T:
        return self._items[name]

    def __contains__(self, name: object) -> bool:
        return name in self._items

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def items(self):
        return self._items.items()

    def values(self):
        return self._items.values()

    def __repr__(self) -> str:
        return f"Registry({self.kind!r}: {', '.join(self._items)})"

"""Packages whose public names are imported on first use (PEP 562), so importing the package stays cheap.

``ergosim.twin`` and ``ergosim.experiment`` re-export their public API in ``__all__`` like every package,
but importing them eagerly would load MuJoCo, the scenes and matplotlib for ``ergosim --help``.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any

__all__ = ["lazy_exports"]


def lazy_exports(package: str, exports: Mapping[str, str]) -> Callable[[str], Any]:
    """The ``__getattr__`` of ``package``: ``exports`` maps each public name to the submodule defining it."""

    def __getattr__(name: str) -> Any:
        module = exports.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(f"{package}.{module}"), name)

    return __getattr__

"""Where extensions come from: the modules that registered a mode, a risk index, an action kind, a scenario
or a workcell, so that worker processes can import them too.

A run with ``--jobs N`` simulates subjects in fresh ``spawn`` processes, which import ergosim but not the
user's module that called :func:`~ergosim.twin.modes.register_mode` (or the other ``register_*``). Each
registration (:class:`~ergosim.registry.Registry`) notes the module it was called from
(:func:`note_caller`); a worker process imports those modules (:func:`import_extensions`) before it runs,
so a new mode is one new module whatever the number of processes. A script run as ``__main__`` is re-run
by ``spawn`` itself and is not noted.
"""

from __future__ import annotations

import importlib
import logging
import sys

__all__ = ["note_caller", "extension_modules", "import_extensions"]

log = logging.getLogger(__name__)

_MODULES: list[str] = []


def note_caller() -> None:
    """Note the module that registered something: the first caller outside ergosim's registering code (a
    :class:`~ergosim.registry.Registry` and the ``register_*`` functions around it), unless it is ergosim's
    own or a ``__main__`` script."""
    frame = sys._getframe(1)
    while frame is not None and _registering(frame):
        frame = frame.f_back
    name = frame.f_globals.get("__name__", "") if frame is not None else ""
    if name and name.split(".")[0] != "ergosim" and name not in ("__main__", "__mp_main__"):
        if name not in _MODULES:
            _MODULES.append(name)


def _registering(frame) -> bool:
    module = frame.f_globals.get("__name__", "")
    return module == "ergosim.registry" or (module.startswith("ergosim.")
                                            and frame.f_code.co_name.startswith("register"))


def extension_modules() -> tuple[str, ...]:
    """The modules noted so far, in the order they first registered something."""
    return tuple(_MODULES)


def import_extensions(names: tuple[str, ...]) -> None:
    """Import ``names`` (from :func:`extension_modules` of the parent process); each registers again."""
    for name in names:
        log.debug("importing extension module %s", name)
        importlib.import_module(name)

"""Diagnostics through the standard :mod:`logging` module, under the ``ergosim`` logger.

Every module logs to ``logging.getLogger(__name__)``: what it is doing at DEBUG (which scenario, which
files, each finished subject or unit), notes a user may want at INFO (the wall time of a run) and problems at
WARNING. As a library ergosim configures nothing (a ``NullHandler``); the command line calls
:func:`configure` with ``--verbose`` (DEBUG, each line with its level and module), the default (INFO) or
``--quiet`` (WARNING). What a command prints as its result (tables, where the files are) and its errors
are not diagnostics and are printed as they are.
"""

from __future__ import annotations

import logging
import sys

__all__ = ["configure", "configured_level", "LOGGER"]

LOGGER = "ergosim"


class _Stderr(logging.Handler):
    """Writes to the ``sys.stderr`` of the moment (a test or a caller may replace it between runs)."""

    def emit(self, record: logging.LogRecord) -> None:
        try:
            sys.stderr.write(self.format(record) + "\n")
            sys.stderr.flush()
        except Exception:  # noqa: BLE001 - logging must never break the program
            self.handleError(record)


def configure(level: int) -> None:
    """Send the ``ergosim`` logger's records of ``level`` and above to stderr (once, however often it is
    called): the bare message, or at DEBUG the level and the module before it."""
    logger = logging.getLogger(LOGGER)
    for h in [h for h in logger.handlers if isinstance(h, _Stderr)]:
        logger.removeHandler(h)
    handler = _Stderr()
    handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s" if level <= logging.DEBUG
                                           else "%(message)s"))
    logger.addHandler(handler)
    logger.setLevel(level)
    logger.propagate = False


def configured_level() -> int | None:
    """The level :func:`configure` set in this process, or None (a library caller's own logging rules),
    for worker processes to take over."""
    logger = logging.getLogger(LOGGER)
    return logger.level if any(isinstance(h, _Stderr) for h in logger.handlers) else None

"""One error family for everything a user can get wrong.

Every error carries where it happened (a file, a table entry, a CLI option) and what was expected, so the
CLI can print it as a single line without a traceback.
"""

from __future__ import annotations

__all__ = [
    "one_line_warnings",
    "ErgosimError",
    "TaskFileError",
    "InfeasiblePlanError",
    "ConfigError",
    "ModelError",
    "RecordingError",
    "RenderError",
    "shown",
]


def shown(raw: object) -> str:
    """``repr(raw)`` for a one-line message; an integer of hundreds of digits (TOML allows any) is given by
    its size."""
    if isinstance(raw, int) and not isinstance(raw, bool) and abs(raw) >= 10**30:
        return f"an integer of {len(str(abs(raw)))} digits"
    return repr(raw)


class ErgosimError(Exception):
    """Base class. ``str(err)`` is one line: ``<where>: <what>``."""

    def __init__(self, what: str, *, where: str | None = None) -> None:
        self.what = " ".join(str(what).split())
        self.where = where
        super().__init__(f"{where}: {self.what}" if where else self.what)


class TaskFileError(ErgosimError):
    """A task file (TOML) that cannot be read or is inconsistent."""


class InfeasiblePlanError(ErgosimError):
    """The AND/OR graph has no complete plan from the current configuration."""


class ConfigError(ErgosimError):
    """A bad scene, scenario or cost parameter (e.g. an unknown ``--set`` key)."""


class ModelError(ErgosimError):
    """A MuJoCo/URDF model that cannot be found, built or compiled."""


class RecordingError(ErgosimError):
    """A motion-capture recording (e.g. BVH) that cannot be parsed."""


class RenderError(ErgosimError):
    """An offscreen picture or video that cannot be rendered or encoded (no OpenGL context, no encoder)."""


def _one_line(message, category, filename, lineno, line=None) -> str:
    return f"ergosim: warning: {' '.join(str(message).split())}\n"


def one_line_warnings() -> None:
    """Print warnings as ``ergosim: warning: <message>``, one line, without the source line Python quotes
    (which otherwise lands inside a progress bar); the CLI and its worker processes call it."""
    import warnings  # noqa: PLC0415

    warnings.formatwarning = _one_line

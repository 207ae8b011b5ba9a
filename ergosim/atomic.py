"""Atomic output files: write to a temporary sibling, fsync, then rename over the target.

A reader (or an interrupted run) therefore sees either the old file or the complete new one, never a
truncated one. Only a regular file is ever replaced: a device node, a FIFO or a socket at the target is
refused (:func:`check_output_file`), since a rename over ``/dev/full`` replaces the device itself.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

from ergosim.errors import ConfigError

__all__ = ["atomic_open", "write_text", "write_bytes", "write_json", "check_output_file"]


def check_output_file(path: str | os.PathLike[str], where: str) -> Path:
    """Refuse, with one line naming ``where`` (the option), an output path that cannot take a new file:
    one that exists and is not a regular file (a directory, a device node, a FIFO, a socket), or one whose
    nearest existing folder is not a directory ergosim may write into. Missing folders are fine (they are
    created). Returns the path."""
    target = Path(path)
    if target.is_dir():
        raise ConfigError(f"{target} is a directory; expected the path of the file to write", where=where)
    if target.exists() and not target.is_file():
        raise ConfigError(f"{target} exists and is not a regular file (a device, a FIFO or a socket); "
                          "refusing to replace it", where=where)
    parent = next((p for p in (target.parent, *target.parent.parents) if p.exists()), Path("."))
    if not parent.is_dir():
        raise ConfigError(f"cannot create {target}: {parent} is a file, not a folder", where=where)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ConfigError(f"cannot write into {parent}: permission denied", where=where)
    return target


@contextlib.contextmanager
def atomic_open(path: str | os.PathLike[str], mode: str = "w") -> Iterator[IO[Any]]:
    """Open a temporary file beside ``path``; on success it replaces ``path`` atomically."""
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_open supports 'w' and 'wb', not {mode!r}")
    target = check_output_file(path, where=str(path))
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        # mkstemp creates 0600; give the file the permissions a plain open() would (0666 & ~umask).
        os.chmod(tmp, 0o666 & ~_umask())
        with os.fdopen(fd, mode, **({} if "b" in mode else {"encoding": "utf-8", "newline": ""})) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: str | os.PathLike[str], text: str) -> None:
    with atomic_open(path, "w") as f:
        f.write(text)


def write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    with atomic_open(path, "wb") as f:
        f.write(data)


def write_json(path: str | os.PathLike[str], obj: Any) -> None:
    """JSON with sorted keys and a trailing newline, so equal results give equal bytes."""
    write_text(path, json.dumps(obj, indent=2, sort_keys=True, allow_nan=False) + "\n")

"""A run owns its output folder: a manifest written first, stale results of earlier runs removed.

``ergosim run`` writes ``run.json`` into ``--out`` before the first tick. Writing it is also the check that
the folder can be written: a read-only directory, or a path that is an existing file, is refused with one
line before any simulation time is spent. Files that an earlier ergosim run left in the folder (the names
listed in its ``run.json``, and every name ergosim writes) are removed, so no result of another run can be
read as this run's; other files are left alone. ``run.json`` is rewritten when the run ends, with its
``status``:

- ``running``: the run is in progress, or the process was killed (SIGKILL, power loss);
- ``complete``: every subject finished and every repetition was completed;
- ``abandoned``: every subject finished, but at least one repetition was abandoned (exit status 3);
- ``interrupted``: Ctrl-C or SIGTERM; the files hold the subjects that finished;
- ``failed``: an error stopped the run; the files hold the subjects that finished.

and ``files``, the outputs of this run. Only a ``complete`` run's files are the whole experiment;
``summary.json`` says the same in ``complete`` and ``status``.
"""

from __future__ import annotations

import contextlib
import errno
import fnmatch
import json
import logging
import os
from pathlib import Path

from ergosim import __version__
from ergosim.atomic import write_json
from ergosim.errors import ConfigError
from ergosim.experiment.outputs import OUTPUTS

__all__ = ["MANIFEST", "RUN_STATUSES", "OUTPUT_PATTERNS", "RunFolder"]

log = logging.getLogger(__name__)

MANIFEST = "run.json"
RUN_STATUSES = ("running", "complete", "abandoned", "interrupted", "failed")
OUTPUT_PATTERNS = (MANIFEST, *(f for o in OUTPUTS for f in o.files))
"""Names ``ergosim run`` writes into its folder (glob patterns: the manifest and every output's); an earlier
run's are removed at start."""


class RunFolder:
    """The output folder of one run. :meth:`claim` before the first tick, :meth:`finish` at the end.

    ``where`` names the folder in messages (the CLI option, ``--out``).
    """

    def __init__(self, path: str | os.PathLike[str], *, scenario: str, seed: int,
                 where: str = "--out") -> None:
        self.path = Path(path)
        self.scenario = scenario
        self.seed = seed
        self.where = where
        self.created = False
        self.removed: list[str] = []

    def claim(self, config: dict | None = None) -> None:
        """Check the folder can be written, remove an earlier run's results, write the manifest."""
        path = self.path
        if path.exists() and not path.is_dir():
            raise ConfigError(f"{path} exists and is not a directory", where=self.where)
        missing = [p for p in (path, *path.parents) if not p.exists()]
        try:
            path.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise ConfigError(f"cannot create {path}: {_why(err)}", where=self.where) from None
        self._made = missing  # the directories this run created, deepest first
        self.created = bool(missing)
        if not os.access(path, os.W_OK | os.X_OK):
            self._undo_mkdir()
            raise ConfigError(f"cannot write into {path}: permission denied", where=self.where)
        self.removed = self._remove_stale()
        if self.removed:
            log.debug("removed %d file(s) an earlier run left in %s: %s", len(self.removed), path,
                      ", ".join(self.removed))
        self.config = config or {}
        try:
            self._write("running", [])
        except OSError as err:
            self._undo_mkdir()
            raise ConfigError(f"cannot write into {path}: {_why(err)}", where=self.where) from None

    def _remove_stale(self) -> list[str]:
        names = set()
        manifest = self.path / MANIFEST
        with contextlib.suppress(OSError, ValueError, TypeError, AttributeError):
            names.update(str(n) for n in json.loads(manifest.read_text(encoding="utf-8")).get("files", []))
        for entry in self.path.iterdir():
            if entry.is_file() and any(fnmatch.fnmatch(entry.name, p) for p in OUTPUT_PATTERNS):
                names.add(entry.name)
        removed = []
        for name in sorted(names):
            target = self.path / name
            # only plain names inside the folder: a hand-edited manifest cannot point elsewhere
            if Path(name).name != name or not target.is_file():
                continue
            try:
                target.unlink()
            except OSError as err:
                raise ConfigError(f"cannot remove {target}, left by an earlier run: {_why(err)}",
                                  where=self.where) from None
            removed.append(name)
        return removed

    def _write(self, status: str, files: list[str], reason: str = "") -> None:
        write_json(self.path / MANIFEST, {
            "format": "ergosim-run/1",
            "ergosim": __version__,
            "scenario": self.scenario,
            "seed": self.seed,
            "status": status,
            "reason": reason,
            "files": sorted(set(files) - {MANIFEST}),
            "removed_from_earlier_run": self.removed,
            "config": self.config,
        })

    def finish(self, status: str, reason: str = "") -> None:
        """Rewrite the manifest with the final ``status`` and the files now in the folder of this run."""
        if status not in RUN_STATUSES:
            raise ValueError(f"unknown run status {status!r}")
        files = [e.name for e in self.path.iterdir()
                 if e.is_file() and any(fnmatch.fnmatch(e.name, p) for p in OUTPUT_PATTERNS)]
        self._write(status, files, reason)

    def discard(self) -> None:
        """Undo :meth:`claim` when the run failed before it wrote any result: remove the manifest and the
        directories this run created, so an early error leaves nothing behind."""
        with contextlib.suppress(FileNotFoundError):
            (self.path / MANIFEST).unlink()
        self._undo_mkdir()

    def _undo_mkdir(self) -> None:
        for d in getattr(self, "_made", []):
            try:
                d.rmdir()
            except OSError:
                break  # not empty (someone else's file), or gone: leave it and its parents


def _why(err: OSError) -> str:
    if err.errno in (errno.EACCES, errno.EPERM):
        return "permission denied"
    if err.errno == errno.EROFS:
        return "read-only file system"
    return err.strerror or str(err)

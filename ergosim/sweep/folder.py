"""A sweep's output folder: one small file per finished unit, the manifest, a lock.

::

    DIR/sweep.json           manifest: the sweep, its status, unit counts (rewritten as the sweep goes)
    DIR/sweep.toml           the sweep file as it was run
    DIR/units/<id>.json      one finished unit each, written atomically the moment it arrives
    DIR/results.parquet      one row per unit of the sweep (consolidated from units/)
    DIR/allocations.parquet  one row per attempt of every unit
    DIR/cells.parquet        per-cell statistics, for the cells whose every unit finished
    DIR/response_*.png, DIR/heatmap_*.png

A unit's file is its only record, so killing the sweep at any moment loses at most the units running then;
a re-run over the same folder skips every unit whose file is there. Unit files are named by the unit's
content hash (:func:`~ergosim.sweep.units.unit_id`): units of an edited sweep file that are unchanged are
found again, and files of other sweeps in the folder are left alone. One sweep at a time writes into a
folder (an advisory lock on ``DIR/.lock``).
"""

from __future__ import annotations

import contextlib
import fcntl
import fnmatch
import json
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from ergosim import __version__
from ergosim.atomic import write_json, write_text
from ergosim.errors import ConfigError
from ergosim.experiment.run_folder import MANIFEST as RUN_MANIFEST
from ergosim.sweep.units import UNIT_FORMAT

__all__ = ["SweepFolder", "SWEEP_MANIFEST", "SWEEP_STATUSES", "PLOT_PATTERNS"]

SWEEP_MANIFEST = "sweep.json"
SWEEP_STATUSES = ("running", "complete", "incomplete", "interrupted", "failed")
"""``complete``: every unit finished and none failed or was abandoned; ``incomplete``: every unit finished,
some failed or were abandoned (exit 3); ``interrupted``: Ctrl-C or SIGTERM (finished units kept);
``failed``: an error stopped the sweep; ``running``: in progress, or killed."""
PLOT_PATTERNS = ("response_*.png", "heatmap_*.png")


class SweepFolder:
    """The folder of one sweep; :meth:`claim` before the first unit, :meth:`close` at the end."""

    def __init__(self, path: str | os.PathLike[str], where: str = "--out") -> None:
        self.path = Path(path)
        self.units = self.path / "units"
        self.where = where
        self._lock: Any = None

    def claim(self) -> None:
        """Create the folder, check it is writable and not a run folder, take the lock, tidy leftovers."""
        path = self.path
        if path.exists() and not path.is_dir():
            raise ConfigError(f"{path} exists and is not a directory", where=self.where)
        if (path / RUN_MANIFEST).is_file():
            raise ConfigError(f"{path} is the folder of an `ergosim run` ({RUN_MANIFEST}); give a sweep its "
                              "own", where=self.where)
        try:
            self.units.mkdir(parents=True, exist_ok=True)
            self._lock = open(path / ".lock", "a+")  # noqa: SIM115 - held until close()
        except OSError as err:
            raise ConfigError(f"cannot write into {path}: {err.strerror or err}", where=self.where) from None
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self._lock.close()
            self._lock = None
            raise ConfigError(f"another ergosim sweep is writing into {path}; wait for it or give another "
                              "folder", where=self.where) from None
        for tmp in self.units.glob(".*.tmp"):  # a unit being written when the sweep was killed
            with contextlib.suppress(OSError):
                tmp.unlink()
        for entry in path.iterdir():  # figures of an earlier sweep into this folder
            if entry.is_file() and any(fnmatch.fnmatch(entry.name, p) for p in PLOT_PATTERNS):
                entry.unlink()

    def close(self) -> None:
        if self._lock is not None:
            with contextlib.suppress(OSError):
                fcntl.flock(self._lock, fcntl.LOCK_UN)
            self._lock.close()
            self._lock = None

    def unit_path(self, unit_id: str) -> Path:
        return self.units / f"{unit_id}.json"

    def write_unit(self, doc: dict) -> None:
        write_json(self.unit_path(doc["id"]), doc)

    def finished(self, ids: Iterable[str]) -> dict[str, dict]:
        """The unit documents already in the folder among ``ids``; an unreadable file counts as not done
        (it is run again and replaced)."""
        out = {}
        for uid in ids:
            p = self.unit_path(uid)
            if not p.is_file():
                continue
            try:
                doc = json.loads(p.read_text(encoding="utf-8"))
            except (OSError, UnicodeDecodeError, ValueError):
                continue
            if isinstance(doc, dict) and doc.get("format") == UNIT_FORMAT and doc.get("id") == uid:
                out[uid] = doc
        return out

    def write_sweep_file(self, text: str) -> None:
        write_text(self.path / "sweep.toml", text)

    def write_manifest(self, doc: dict) -> None:
        write_json(self.path / SWEEP_MANIFEST, {"format": "ergosim-sweep/1", "ergosim": __version__, **doc})

    def plots(self) -> list[str]:
        return sorted(e.name for e in self.path.iterdir()
                      if e.is_file() and any(fnmatch.fnmatch(e.name, p) for p in PLOT_PATTERNS))

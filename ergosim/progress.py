"""A dependency-free progress bar on stderr for long runs."""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["Progress"]


class Progress:
    """``Progress(total, label)``; call :meth:`advance` per finished unit, :meth:`close` at the end.

    On a terminal the bar redraws in place; otherwise (CI logs, pipes) it prints a line at every 10 %.
    """

    def __init__(self, total: int, label: str, *, stream: TextIO | None = None, enabled: bool = True):
        self.total = max(int(total), 1)
        self.label = label
        self.done = 0
        self.stream = stream if stream is not None else sys.stderr
        self.enabled = enabled
        self._tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._start = time.monotonic()
        self._last_decile = -1

    def advance(self, n: int = 1, note: str = "") -> None:
        self.done = min(self.done + n, self.total)
        if not self.enabled:
            return
        frac = self.done / self.total
        elapsed = time.monotonic() - self._start
        eta = elapsed / frac - elapsed if frac > 0 else 0.0
        if self._tty:
            filled = int(30 * frac)
            bar = "#" * filled + "-" * (30 - filled)
            msg = f"\r{self.label} [{bar}] {self.done}/{self.total} {elapsed:5.0f}s eta {eta:4.0f}s {note}"
            self.stream.write(msg[:160])
            self.stream.flush()
        elif int(frac * 10) > self._last_decile:
            self._last_decile = int(frac * 10)
            self.stream.write(f"{self.label}: {self.done}/{self.total} ({frac:4.0%}) {elapsed:.0f}s {note}\n")
            self.stream.flush()

    def close(self) -> None:
        if self.enabled and self._tty:
            self.stream.write("\n")
            self.stream.flush()

"""Ctrl-C and SIGTERM stop a run the same way, and worker processes stay quiet when they do.

The main process turns SIGINT and SIGTERM into :class:`Interrupted` (a KeyboardInterrupt), so the run's
``finally`` writes every finished subject whichever signal came. Worker processes ignore both signals (a
terminal's Ctrl-C reaches the whole process group; ``timeout`` signals the group too): the main process
stops them with :func:`stop_pool`, so no worker prints a traceback.
"""

from __future__ import annotations

import contextlib
import logging
import signal
import threading
from collections.abc import Iterator

from ergosim.logs import configure

__all__ = ["Interrupted", "interrupt_on_signals", "signals_ignored", "quiet_worker", "stop_pool",
           "stop_reason", "STOP_SIGNALS"]

log = logging.getLogger(__name__)

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Interrupted(KeyboardInterrupt):
    """The run was stopped by signal ``signum``; the CLI exits with 128 + signum."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def stop_reason(err: BaseException) -> tuple[str, str]:
    """(status, reason) of a run that ``err`` stopped, as run.json records it: ``interrupted`` by a signal
    or Ctrl-C, else ``failed`` with the error."""
    if isinstance(err, Interrupted):
        return "interrupted", f"stopped by {err}"
    if isinstance(err, KeyboardInterrupt):
        return "interrupted", "stopped by SIGINT"
    return "failed", f"{type(err).__name__}: {err}"


def _raise(signum, _frame) -> None:
    raise Interrupted(signum)


@contextlib.contextmanager
def interrupt_on_signals() -> Iterator[None]:
    """Inside the block SIGINT and SIGTERM raise :class:`Interrupted` (main thread only, else a no-op)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, _raise) for s in STOP_SIGNALS}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def quiet_worker(log_level: int | None = None) -> None:
    """Initializer of a worker process: ignore SIGINT and SIGTERM (the main process stops the workers), and
    log as the main process does (``log_level``: :func:`ergosim.logs.configured_level`, None: as is)."""
    for s in STOP_SIGNALS:
        signal.signal(s, signal.SIG_IGN)
    if log_level is not None:
        configure(log_level)


@contextlib.contextmanager
def signals_ignored() -> Iterator[None]:
    """Ignore the stop signals while worker processes start, so they inherit SIG_IGN from the first
    instruction (Python keeps an ignored SIGINT ignored at start-up); a signal in this window is lost."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in STOP_SIGNALS}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def stop_pool(pool) -> None:
    """Kill the worker processes of a ``concurrent.futures.ProcessPoolExecutor`` and drop its queued jobs."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for p in processes:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            p.kill()
    pool.shutdown(wait=False, cancel_futures=True)
    for p in processes:
        with contextlib.suppress(OSError, ValueError, AttributeError, AssertionError):
            p.join(timeout=5.0)

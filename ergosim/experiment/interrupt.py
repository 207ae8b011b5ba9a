"""Ctrl-C and SIGTERM stop a run the same way, and worker processes stay quiet when they do.

The main process turns SIGINT and SIGTERM into :class:`Interrupted` (a KeyboardInterrupt), so the run's
``finally`` writes every finished subject whichever signal came. While a run writes its final results it
*holds* the signals instead (:class:`StopSignals`): a signal then is acted on once the files, and the
status they carry, are whole, so an exit status of 130 or 143 always comes with outputs that say
``interrupted``. The first signal that stops a run holds the later ones too, so a second Ctrl-C cannot cut
the clean-up short.

Worker processes ignore both signals (a terminal's Ctrl-C reaches the whole process group; ``timeout``
signals the group too): the main process stops them with :func:`stop_pool`, so no worker prints a
traceback. They inherit SIG_IGN from the main process while they start (:func:`signals_ignored`).

A Python callback that C code calls (MuJoCo's warning handler) must never raise: the exception would
unwind through C++ frames and abort the process ("libc++abi: terminating"). Such calls run inside
:func:`ergosim.held_signals.signals_held`.
"""

from __future__ import annotations

import contextlib
import logging
import signal
import threading
from collections.abc import Iterator

from ergosim.errors import one_line_warnings
from ergosim.held_signals import STOP_SIGNALS
from ergosim.logs import configure

__all__ = ["Interrupted", "StopSignals", "interrupt_on_signals", "signals_ignored",
           "quiet_worker", "stop_pool", "stop_reason", "STOP_SIGNALS"]

log = logging.getLogger(__name__)


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


class StopSignals:
    """The stop signals inside :func:`interrupt_on_signals`.

    While ``holding`` is false a signal raises :class:`Interrupted` (and sets ``holding``: the run is
    stopping). While it is true a signal is kept in ``held`` (the first one) for :meth:`release`. Set
    ``holding`` with a plain assignment where no signal may slip in between: an attribute store runs no
    signal handler, a call may.
    """

    def __init__(self, holding: bool = False) -> None:
        self.holding = holding
        self.held: int | None = None

    def handle(self, signum: int, _frame=None) -> None:
        if self.holding:
            if self.held is None:
                self.held = signum
            return
        self.holding = True
        raise Interrupted(signum)

    def release(self) -> None:
        """Stop holding; a signal held meanwhile raises :class:`Interrupted` now."""
        self.holding = False
        if self.held is not None:
            signum, self.held = self.held, None
            self.handle(signum)


@contextlib.contextmanager
def interrupt_on_signals(holding: bool = False) -> Iterator[StopSignals]:
    """Inside the block SIGINT and SIGTERM raise :class:`Interrupted`, or are held (:class:`StopSignals`;
    ``holding``: from the start). Main thread only; elsewhere the block runs with the signals untouched."""
    stop = StopSignals(holding)
    if threading.current_thread() is not threading.main_thread():
        yield stop
        return
    previous = {}
    try:
        for s in STOP_SIGNALS:
            previous[s] = signal.signal(s, stop.handle)
        yield stop
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def quiet_worker(log_level: int | None = None) -> None:
    """Initializer of a worker process: ignore SIGINT and SIGTERM (the main process stops the workers), log
    as the main process does (``log_level``: :func:`ergosim.logs.configured_level`, None: as is), and print
    warnings as one line (:func:`~ergosim.errors.one_line_warnings`)."""
    for s in STOP_SIGNALS:
        signal.signal(s, signal.SIG_IGN)
    if log_level is not None:
        configure(log_level)
    one_line_warnings()


@contextlib.contextmanager
def signals_ignored() -> Iterator[None]:
    """Ignore the stop signals while worker processes start, so they inherit SIG_IGN from the first
    instruction (Python keeps an ignored SIGINT ignored at start-up). A signal in this window (the fork
    and exec of each worker, milliseconds) is lost: the disposition is the process's, so blocking it in
    the main thread would not keep it for later. Keep the block to the process starts."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    try:
        for s in STOP_SIGNALS:
            previous[s] = signal.signal(s, signal.SIG_IGN)
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

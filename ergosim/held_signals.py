"""Stop signals held while C code may call Python back.

MuJoCo calls a Python function when it warns (``mujoco.set_mju_user_warning``, which
:mod:`ergosim.scenes.build` uses while it attaches the robot and the human). Python runs a signal's handler
in whatever Python code runs next, and that can be the callback: a handler that raises there (Ctrl-C's
KeyboardInterrupt, SIGTERM's :class:`~ergosim.experiment.interrupt.Interrupted`) throws through MuJoCo's C++
frames and the process aborts with "libc++abi: terminating", writing nothing. Inside
:func:`signals_held` the handler only notes the signal; the handler that was there gets it once the C code
has returned.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator

__all__ = ["STOP_SIGNALS", "signals_held"]

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM for the block: the first signal that comes goes to the handler that was
    there when the block is over (a raising handler raises then; SIG_DFL takes its default action; SIG_IGN
    drops it). If the block raises, its error wins. Main thread only (signals are handled there)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    came: list[int] = []
    previous = {}
    try:
        for s in STOP_SIGNALS:
            previous[s] = signal.signal(s, lambda signum, _frame: came.append(signum))
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    if came:
        handler = previous[came[0]]
        if callable(handler):
            handler(came[0], None)
        elif handler == signal.SIG_DFL:
            signal.raise_signal(came[0])

"""What a video frame says at a given simulated time, read from a finished run (nothing is recomputed).

Every field comes from the run's own records: the tick log (repetition, KWear V per joint), the attempts
(:class:`~ergosim.twin.records.Allocation`: which action, which agent, from ``t_start`` to ``t_end``), the
allocator's decisions (:class:`~ergosim.twin.allocator.Decision`) in the words of
:func:`~ergosim.viz.reason.reason_text`, and the failures (:class:`~ergosim.twin.records.Failure`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from ergosim.errors import ConfigError
from ergosim.twin.records import SubjectRun
from ergosim.viz.reason import reason_text

__all__ = ["Event", "FrameInfo", "RunTimeline"]


@dataclasses.dataclass(frozen=True)
class Event:
    """A line the video shows for a while: a decision's reason (``kind`` ``decision``) or a failure
    (``failure``), at simulated time ``time`` [s]."""

    time: float
    kind: str
    text: str
    agent: str = ""


@dataclasses.dataclass(frozen=True)
class FrameInfo:
    """The overlay of one frame. ``time`` [s] of simulated time; ``action``/``agent`` the attempt in
    progress ("" between attempts) and ``action_text`` what it does (e.g. ``insert L``); ``kwear`` (5,) V
    per joint in KWEAR_JOINTS order; ``events``: the latest decisions and failures, oldest first; ``also``:
    the other attempts in progress at the same time (parallel execution), as (action, agent, text)."""

    time: float
    repetition: int
    repetitions: int
    action: str
    agent: str
    action_text: str
    kwear: np.ndarray
    v_th: float
    events: tuple[Event, ...]
    also: tuple[tuple[str, str, str], ...] = ()


class RunTimeline:
    """Look-ups into one :class:`SubjectRun` by simulated time.

    ``action_text``: action label -> a few words on what it does, shown beside the label; ``handovers``:
    the actions a robot hands over to the worker to finish (said when a robot does them).
    """

    def __init__(self, run: SubjectRun, action_text: Mapping[str, str] | None = None,
                 handovers: frozenset[str] = frozenset()) -> None:
        rows = run.ticks.rows
        if len(rows) == 0:
            raise ConfigError("the run has no ticks to show", where="--video")
        self.run = run
        self.t = run.ticks.column("t").copy()
        self.rep = run.ticks.column("repetition").astype(int)
        self.kwear = run.ticks.kwear.copy()
        self.action_text = dict(action_text or {})
        self.handovers = frozenset(handovers)
        starts = [(o.t_start, o.repetition) for o in run.outcomes if np.isfinite(o.t_start)]
        self._rep_start = np.array([t for t, _ in starts])
        self._rep_number = [r for _, r in starts]
        self.repetitions = len(run.outcomes) or int(self.rep.max())
        attempts = [a for a in run.allocations if a.status != "pruned"]
        self._attempts = sorted(attempts, key=lambda a: (a.t_start, a.order))
        events = [Event(d.time, "decision", reason_text(d), d.agent) for d in run.decisions]
        events += [Event(f.time, "failure", f.message, f.agent) for f in run.failures]
        self.events = tuple(sorted(events, key=lambda e: (e.time, e.kind != "failure")))
        self._event_t = np.array([e.time for e in self.events])

    @property
    def start(self) -> float:
        return 0.0

    @property
    def end(self) -> float:
        return float(self.t[-1])

    def window(self, reps: tuple[int, int] | None, tail: float = 1.0) -> tuple[float, float]:
        """Simulated time span [s] of repetitions ``reps`` = (first, last), both included, 1-based: from the
        first one's start to ``tail`` seconds after the last one's end (the whole run for None)."""
        if reps is None:
            return self.start, self.end
        first, last = reps
        spans = {o.repetition: o for o in self.run.outcomes}
        for r in (first, last):
            o = spans.get(r)
            if o is None or not np.isfinite(o.t_start) or not np.isfinite(o.t_end):
                ran = [k for k, v in sorted(spans.items()) if np.isfinite(v.t_start)]
                raise ConfigError(f"repetition {r} was not run (repetitions run: "
                                  f"{', '.join(map(str, ran)) or 'none'})", where="--video-reps")
        return float(spans[first].t_start), min(float(spans[last].t_end) + tail, self.end)

    def at(self, time: float, hold: float, max_events: int = 2) -> FrameInfo:
        """The frame at ``time`` [s]; events stay on screen for ``hold`` seconds of simulated time (or until
        ``max_events`` newer ones push them off)."""
        i = max(int(np.searchsorted(self.t, time, side="right")) - 1, 0)
        kwear = np.array([np.interp(time, self.t, self.kwear[:, j]) for j in range(self.kwear.shape[1])])
        current = [a for a in self._attempts if a.t_start <= time < a.t_end]
        attempt = current[-1] if current else None
        action = attempt.action if attempt else ""
        agent = attempt.agent if attempt else ""
        n = int(np.searchsorted(self._event_t, time, side="right"))
        recent = [e for e in self.events[max(0, n - max_events):n] if time - e.time <= hold]
        also = tuple((a.action, a.agent, self._text(a.action, a.agent)) for a in current[:-1])
        return FrameInfo(time=float(time), repetition=self._repetition(time, i), repetitions=self.repetitions,
                         action=action, agent=agent, action_text=self._text(action, agent), kwear=kwear,
                         v_th=float(self.run.v_th), events=tuple(recent), also=also)

    def _text(self, action: str, agent: str) -> str:
        text = self.action_text.get(action, "")
        if action in self.handovers and self.run.by_robot(agent):
            text += ", handed to the worker"
        return text

    def _repetition(self, time: float, tick: int) -> int:
        """The repetition under way at ``time``: the last one started (from the outcomes), else the tick's."""
        k = int(np.searchsorted(self._rep_start, time, side="right")) - 1
        if k >= 0:
            return self._rep_number[k]
        return max(int(self.rep[tick]), 1)

"""The ergonomics tick (20 Hz by default, as in the paper): mocap frame -> RULA per part -> KWear per joint.

Each tick takes the latest mocap frame at or before the tick time. A dropout (NaN) frame is replaced by the
last valid frame and counted; before any valid frame the wear is not updated. So a NaN never reaches KWear.
While the worker acts the joints wear (paper eq. 3-4, with G_i from RULA, eq. 3); while resting they recover
(eq. 5). V(t_k) at the end of an action is :attr:`ErgonomicsTick.v`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ergosim.ergonomics import part_scores
from ergosim.ergonomics.kwear import kwear_step
from ergosim.ergonomics.rula import rula
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS, array_to_posture
from ergosim.worker.stream import MocapFrames

__all__ = ["TickTrace", "ErgonomicsTick", "risk_scores", "tick_frames"]

_N_RULA = len(ANGLE_NAMES)  # the first 14 columns of a (.., 22) HUMAN_JOINTS frame are the RULA input


def risk_scores(angles: np.ndarray) -> np.ndarray:
    """(n, 22 or 14) valid angles [deg] -> (n, 5) RULA part scores G_i in KWEAR_JOINTS order."""
    a = np.atleast_2d(np.asarray(angles, dtype=float))[:, :_N_RULA]
    return np.asarray(part_scores(rula(array_to_posture(a))), dtype=float).reshape(len(a), len(KWEAR_JOINTS))


def tick_frames(frames: MocapFrames, rate: float = 20.0,
                t_end: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Sample a mocap recording at the tick rate: (k,) tick times [s] and (k, 22) latest frames (may be NaN).

    Tick k is at ``frames.t[0] + (k + 1) / rate`` (the wear of the interval that ends there).
    """
    t0 = frames.t[0]
    end = frames.t[-1] if t_end is None else t_end
    n = int(np.floor((end - t0) * rate + 1e-9))
    ticks = t0 + np.arange(1, n + 1) / rate
    idx = np.searchsorted(frames.t, ticks + 1e-9, side="right") - 1
    return ticks, frames.angles[np.clip(idx, 0, len(frames.t) - 1)]


@dataclass(frozen=True)
class TickTrace:
    """Per-tick record of one stretch of ticks: ``v`` (k, 5) KWear after each tick, ``g`` (k, 5) the part
    scores used (NaN where no valid frame existed yet or the worker rested), ``dropout`` (k,) bool."""

    v: np.ndarray
    g: np.ndarray
    dropout: np.ndarray


class ErgonomicsTick:
    """KWear state of one worker, advanced tick by tick. ``params``: ``KWearParams``; ``rate`` [Hz]."""

    def __init__(self, params: Any, rate: float = 20.0, v0: np.ndarray | None = None) -> None:
        self.params = params
        self.rate = float(rate)
        self.dt = 1.0 / self.rate
        self.v = np.zeros(len(KWEAR_JOINTS)) if v0 is None else np.array(v0, dtype=float)
        self.last_valid: np.ndarray | None = None
        self.dropouts = 0
        self.ticks = 0
        self._nan_g = np.full(len(KWEAR_JOINTS), np.nan)

    def reset(self, v0: np.ndarray | None = None) -> None:
        """Zero wear (or ``v0``) and forget the last frame, e.g. before a calibration execution."""
        self.v = np.zeros(len(KWEAR_JOINTS)) if v0 is None else np.array(v0, dtype=float)
        self.last_valid = None

    def _frame(self, frame: np.ndarray) -> np.ndarray | None:
        if np.isnan(frame[:_N_RULA]).any():
            self.dropouts += 1
            return self.last_valid
        self.last_valid = frame
        return frame

    def step(self, frame: np.ndarray, resting: bool = False) -> np.ndarray:
        """Advance one tick with the latest (22,) or (14,) frame [deg]; returns the (5,) part scores used
        (NaN if none). Resting ticks recover whatever the frame."""
        self.ticks += 1
        frame = self._frame(np.asarray(frame, dtype=float))
        if resting:
            self.v = kwear_step(self.v, np.zeros(len(KWEAR_JOINTS)), self.dt, self.params, resting=True)
            return self._nan_g
        if frame is None:
            return self._nan_g
        g = risk_scores(frame)[0]
        self.v = kwear_step(self.v, g, self.dt, self.params)
        return g

    def run(self, frames: np.ndarray, resting: np.ndarray | bool = False) -> TickTrace:
        """Advance over (k, 22) frames at the tick rate (RULA vectorised once); ``resting`` (k,) or scalar."""
        frames = np.atleast_2d(np.asarray(frames, dtype=float))
        k = len(frames)
        rest = np.broadcast_to(np.asarray(resting, dtype=bool), (k,))
        drop = np.isnan(frames[:, :_N_RULA]).any(axis=1)
        held = np.empty_like(frames)
        have = np.zeros(k, dtype=bool)
        last = self.last_valid
        for i in range(k):  # hold the last valid frame through dropouts
            if not drop[i]:
                last = frames[i]
            if last is not None:
                held[i], have[i] = last, True
        self.last_valid = last
        g = np.full((k, len(KWEAR_JOINTS)), np.nan)
        use = have & ~rest
        if use.any():
            g[use] = risk_scores(held[use])
        v_out = np.empty((k, len(KWEAR_JOINTS)))
        v = self.v
        zero = np.zeros(len(KWEAR_JOINTS))
        for i in range(k):
            if rest[i]:
                v = kwear_step(v, zero, self.dt, self.params, resting=True)
            elif use[i]:
                v = kwear_step(v, g[i], self.dt, self.params)
            v_out[i] = v
        self.v = v
        self.ticks += k
        self.dropouts += int(drop.sum())
        return TickTrace(v_out, g, drop)

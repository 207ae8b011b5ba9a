"""RULA of measured frames, and the replay of a recording through the ergonomics tick (paper eq. 3-5).

:func:`score_frames` scores mocap frames with RULA, vectorised over all frames at once; the running twin
uses it on every measured segment (:mod:`ergosim.twin.worker_track`). :func:`replay` is the one path for
recordings that do not come from the running twin (a BVH file, a stored stream): frames at the mocap rate
-> ticks at the ergonomics rate -> RULA per part -> KWear per joint through
:class:`~ergosim.ergonomics.risk_index.KWearIndex`, so a replay follows the twin's dropout rule exactly: a
NaN frame is a dropout, counted, and V holds while acting; resting ticks recover (eq. 5).

Sampling. Frame i holds from its time stamp until the next frame (the twin plays frame i over one control
period). Tick k (k = 1, 2, ...) closes the interval ((k - 1)/rate, k/rate] after the first frame and takes
the frame in force just before its end: the latest frame stamped strictly before k/rate. For a 60 Hz
recording and 20 Hz ticks that is frame 3k - 1, the frame the twin's loop and its calibration passes use.
A recording of n frames at f Hz lasts n/f seconds and gives floor(n rate / f) ticks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ergosim.ergonomics.kwear import KWearParams, kwear_trajectory
from ergosim.ergonomics.risk_index import KWearIndex
from ergosim.ergonomics.rula import RULA_PARTS, part_scores, rula
from ergosim.errors import ConfigError, RecordingError
from ergosim.posture import ANGLE_NAMES, KWEAR_JOINTS, array_to_posture

__all__ = ["REPLAY_COLUMNS", "ReplayTrace", "score_frames", "tick_indices", "replay", "replay_ticks"]


REPLAY_COLUMNS: tuple[str, ...] = (
    ("t", "acting", "dropout")
    + ANGLE_NAMES
    + tuple(f"rula_{p}" for p in RULA_PARTS)
    + ("rula_grand",)
    + tuple(f"kwear_{j}" for j in KWEAR_JOINTS)
)
"""Columns of :meth:`ReplayTrace.table`: the twin's ``ticks.csv`` columns without ``repetition``."""

_N = len(ANGLE_NAMES)
_M = len(KWEAR_JOINTS)
_TOL = 1e-9


def _angles(frames, where: str) -> np.ndarray:
    a = np.asarray(frames, dtype=float)
    if a.ndim != 2 or a.shape[1] < _N:
        raise RecordingError(f"frames must be (n, {_N}) or (n, 22) angles [deg], got shape {a.shape}",
                             where=where)
    return a[:, :_N]


def score_frames(measured) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """RULA of n measured frames, in one vectorised call.

    measured: (n, 14) angles [deg] in ANGLE_NAMES order, or (n, 22) HUMAN_JOINTS frames (the first 14 columns
    are the RULA input). Returns part scores (n, 7) in :data:`RULA_PARTS` order, grand scores (n,) and the
    KWear inputs G (n, 5) in KWEAR_JOINTS order (paper eq. 3). A row with any NaN angle (a dropout) is NaN
    in all three.
    """
    a = _angles(measured, "score_frames")
    res = rula(array_to_posture(a))
    bad = np.isnan(a).any(axis=1)
    parts = np.stack([np.asarray(getattr(res, p), dtype=float) for p in RULA_PARTS], axis=-1)
    grand = np.array(res.grand, dtype=float)
    g = np.array(part_scores(res), dtype=float).reshape(len(a), _M)
    parts[bad], grand[bad], g[bad] = np.nan, np.nan, np.nan
    return parts, grand, g


def tick_indices(n_frames: int, mocap_rate: float, rate: float = 20.0) -> np.ndarray:
    """(k,) index of the frame each ergonomics tick uses, for ``n_frames`` frames at ``mocap_rate`` [Hz]
    and ticks at ``rate`` [Hz]: the latest frame stamped strictly before the tick (module docstring)."""
    if not (mocap_rate > 0 and rate > 0):
        raise ConfigError(f"rates must be > 0 Hz, got mocap {mocap_rate}, ergonomics {rate}", where="replay")
    n_ticks = int(np.floor(n_frames * rate / mocap_rate + _TOL))
    k = np.arange(1, n_ticks + 1)
    return np.ceil(k * (mocap_rate / rate) - _TOL).astype(np.int64) - 1


@dataclass(frozen=True, eq=False)
class ReplayTrace:
    """Per-tick result of a replay; every array has one row per ergonomics tick.

    ``t`` (k,) tick times [s] (the end of each tick's interval); ``frame`` (k,) index of the frame used;
    ``angles`` (k, 14) its measured angles [deg]; ``rula`` (k, 7) part scores (:data:`RULA_PARTS`),
    ``grand`` (k,) and ``g`` (k, 5) G_i, NaN on dropouts; ``v`` (k, 5) KWear after each tick
    (KWEAR_JOINTS order); ``acting`` (k,) False where the worker rested; ``dropout`` (k,) the frame was a
    dropout; ``dropouts`` their number; ``rate`` the ergonomics rate [Hz].
    """

    t: np.ndarray
    frame: np.ndarray
    angles: np.ndarray
    rula: np.ndarray
    grand: np.ndarray
    g: np.ndarray
    v: np.ndarray
    acting: np.ndarray
    dropout: np.ndarray
    dropouts: int
    rate: float

    @property
    def n(self) -> int:
        return len(self.t)

    @property
    def v_end(self) -> np.ndarray:
        """(5,) KWear after the last tick (zeros-length replay: NaN)."""
        return self.v[-1].copy() if self.n else np.full(_M, np.nan)

    def table(self) -> np.ndarray:
        """(k, len(REPLAY_COLUMNS)) rows in :data:`REPLAY_COLUMNS` order (acting, dropout as 0/1)."""
        return np.column_stack([self.t, self.acting, self.dropout, self.angles, self.rula, self.grand,
                                self.v]) if self.n else np.empty((0, len(REPLAY_COLUMNS)))


def replay(frames, mocap_rate: float, params: KWearParams | None = None, *, rate: float = 20.0,
           resting=False, t0: float = 0.0, index: KWearIndex | None = None) -> ReplayTrace:
    """Replay measured frames through the ergonomics tick: RULA per part, then KWear per joint.

    frames: (n, 14) or (n, 22) measured angles [deg] (NaN rows are dropouts) sampled at ``mocap_rate``
    [Hz], the first at ``t0`` [s]. params: the worker's KWear constants (paper defaults if None).
    rate: ergonomics rate [Hz] (20 Hz in the paper). resting: bool, or (n,) per frame, True where the worker
    is not executing an action (eq. 5 recovery instead of eq. 3-4 wear). index: a
    :class:`KWearIndex` to continue from (its V, counters and action hooks carry over); a fresh one from
    zero wear if None. RULA runs once over all tick frames; only the KWear recursion is per tick.
    """
    a = _angles(frames, "replay")
    n = len(a)
    rest = np.asarray(resting, dtype=bool)
    if rest.ndim and rest.shape != (n,):
        raise ConfigError(f"resting must be a bool or ({n},) per frame, got shape {rest.shape}",
                          where="replay")
    idx = tick_indices(n, mocap_rate, rate)
    return replay_ticks(a[idx], idx, params, rate=rate, acting=~np.broadcast_to(rest, (n,))[idx], t0=t0,
                        index=index)


def replay_ticks(angles, frame, params: KWearParams | None = None, *, rate: float = 20.0, acting=True,
                 t0: float = 0.0, index: KWearIndex | None = None) -> ReplayTrace:
    """:func:`replay` of the tick frames alone: ``angles`` (k, 14) measured angles [deg] of the frames
    ``frame`` (k,) that the ticks use (:func:`tick_indices`), ``acting`` bool or (k,) per tick.

    Without an ``index``, KWear runs from zero wear through
    :func:`~ergosim.ergonomics.kwear.kwear_trajectory`: the same operations as a fresh :class:`KWearIndex`
    tick by tick.
    """
    angles = _angles(angles, "replay")
    k = len(angles)
    frame = np.asarray(frame, dtype=np.int64)
    parts, grand, g = score_frames(angles)
    acting = np.array(np.broadcast_to(np.asarray(acting, dtype=bool), (k,)))
    dropout = np.isnan(angles).any(axis=1)
    dt = 1.0 / rate
    if index is None:
        v = kwear_trajectory(np.zeros(_M), np.where(acting[:, None], g, 0.0), dt,
                             params if params is not None else KWearParams(), resting=~acting)
    else:
        v = np.empty((k, _M))
        zero = np.zeros(_M)
        for i in range(k):  # KWear is a recursion: V(t_k) depends on V(t_{k-1})
            if acting[i]:
                v[i] = index.update(g[i], dt)
            else:
                v[i] = index.update(zero, dt, resting=True)
    t = t0 + np.arange(1, k + 1) / rate
    return ReplayTrace(t, frame, angles, parts, grand, g, v, acting, dropout, int(dropout.sum()), float(rate))

"""The worker's side of the loop: upcoming mocap frames, their RULA scores, and the hand's grasp events.

A *segment* is one stretch of the worker's motion at the mocap rate: an action planned by
:class:`~ergosim.worker.motion.Worker`, or the rest posture held while the robot works or the takt runs.
When a segment is queued it is measured once by the mocap stream (noise, dropouts) and RULA is evaluated
on all its frames at once (vectorised). The loop then consumes it frame by frame: the *true* angles drive
the human's ``qpos``; at the ergonomics rate the *measured* frame's part scores G_i feed KWear.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ergosim.posture import ANGLE_NAMES
from ergosim.worker.ergonomics_tick import score_frames
from ergosim.worker.motion import ActionMotion, Worker
from ergosim.worker.stream import MocapStream

__all__ = ["Segment", "WorkerTrack"]

_N = len(ANGLE_NAMES)


@dataclass(frozen=True)
class Segment:
    """One measured stretch of motion. Arrays have one row per mocap frame.

    ``true`` (n, 22) [deg] drives the model; ``measured`` (n, 14) [deg] is what the suit reports (NaN rows are
    dropouts); ``rula`` (n, 7) part scores in :data:`RULA_PARTS` order and ``grand`` (n,), NaN on dropouts;
    ``g`` (n, 5) KWear inputs G_i (paper eq. 3); ``acting`` tells wear from recovery (eq. 3 vs eq. 5).
    ``qpos`` (n, 22) is ``true`` in radians and ``scores`` (n, 24) the tick-log columns ``acting`` ..
    ``rula_grand``, both computed once per segment: the per-tick loop only copies rows.
    """

    motion: ActionMotion
    true: np.ndarray
    measured: np.ndarray
    rula: np.ndarray
    grand: np.ndarray
    g: np.ndarray
    acting: bool
    grasp_frame: int
    release_frame: int
    qpos: np.ndarray
    scores: np.ndarray

    @property
    def n(self) -> int:
        return len(self.true)


class WorkerTrack:
    """Queues segments for one worker and hands out frames one control tick at a time."""

    def __init__(self, worker: Worker, stream: MocapStream) -> None:
        self.worker = worker
        self.stream = stream
        self.segment: Segment | None = None
        self.index = 0

    def _measure(self, motion: ActionMotion, acting: bool) -> Segment:
        frames = self.stream.measure(motion.angles)
        measured = frames.angles[:, :_N]
        parts, grand, g = score_frames(measured)
        rate = motion.rate
        grasp = int(np.ceil(motion.t_grasp * rate)) if np.isfinite(motion.t_grasp) else -1
        release = int(np.ceil(motion.t_release * rate)) if np.isfinite(motion.t_release) else -1
        scores = np.column_stack([np.full(len(g), float(acting)), np.isnan(g[:, 0]), measured, parts, grand])
        return Segment(motion, motion.angles, measured, parts, grand, g, acting, grasp, release,
                       np.deg2rad(motion.angles), scores)

    def start_action(self, motion: ActionMotion) -> Segment:
        self.segment, self.index = self._measure(motion, acting=True), 0
        return self.segment

    def start_rest(self, seconds: float) -> Segment:
        self.segment, self.index = self._measure(self.worker.rest_motion(seconds), acting=False), 0
        return self.segment

    @property
    def busy(self) -> bool:
        """True while an action segment still has frames to play."""
        return self.segment is not None and self.segment.acting and self.index < self.segment.n

    @property
    def exhausted(self) -> bool:
        return self.segment is None or self.index >= self.segment.n

    def advance(self) -> int:
        """Move to the next frame; returns the index of the frame now current (clamped at the last)."""
        seg = self.segment
        assert seg is not None
        k = min(self.index, seg.n - 1)
        self.index += 1
        return k

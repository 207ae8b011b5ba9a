"""The worker's side of the loop: upcoming mocap frames, their RULA scores, and the hand's grasp events.

A *segment* is one stretch of the worker's motion at the mocap rate: an action planned by
:class:`~ergosim.worker.motion.Worker`, or the rest posture held while the robot works or the takt runs.
When a segment is queued it is measured once by the mocap stream (noise, dropouts) and RULA is evaluated
on all its frames at once (vectorised). The loop then consumes it frame by frame: the *true* angles drive
the human's ``qpos``; at the ergonomics rate the *measured* frame's part scores G_i feed KWear.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ergosim.ergonomics.rula import RULA_PARTS
from ergosim.human.model import body_qpos
from ergosim.posture import ANGLE_NAMES
from ergosim.twin.features import FeatureScorer
from ergosim.worker.ergonomics_tick import score_frames
from ergosim.worker.motion import ActionMotion, Worker
from ergosim.worker.stream import MocapStream
from ergosim.worker.subjects import Subject

__all__ = ["Segment", "WorkerTrack"]

_N = len(ANGLE_NAMES)


# Columns of Segment.scores: the tick-log columns ``acting`` .. ``rula_grand`` (ergosim.twin.records).
_MEASURED = slice(2, 2 + _N)
_RULA = slice(2 + _N, 2 + _N + len(RULA_PARTS))
_GRAND = 2 + _N + len(RULA_PARTS)


@dataclass(frozen=True)
class Segment:
    """One measured stretch of motion. Arrays have one row per mocap frame.

    ``qpos`` (n, 26) [rad, m] is the true posture and stance that drive the model
    (:func:`~ergosim.human.model.body_qpos`); ``scores`` (n, 24) holds the tick-log
    columns ``acting``, ``dropout``, the measured angles, RULA per part and the grand score, computed once
    per segment so the per-tick loop only copies rows; ``g`` (n, 5) KWear inputs G_i (paper eq. 3);
    ``acting`` tells wear from recovery (eq. 3 vs eq. 5); ``static``: every frame has the same true posture
    (a held rest), so the body needs posing once. Views: ``true`` (n, 22) [deg], ``stance`` (n, 4)
    [m, m, deg, deg], ``measured``
    (n, 14) [deg] what the suit reports (NaN rows are dropouts), ``rula`` (n, 7) part scores in
    :data:`RULA_PARTS` order and ``grand`` (n,), NaN on dropouts. Per posture feature, ``g_by`` (n, m) a risk
    index's inputs and ``whole_by`` (n,) the whole-body score (``rula``, always: ``g`` and ``grand``); with
    further features scored (a :class:`~ergosim.twin.features.FeatureScorer`), ``extra`` (n, k) their
    tick-log columns.
    """

    motion: ActionMotion
    qpos: np.ndarray
    scores: np.ndarray
    g: np.ndarray
    acting: bool
    grasp_frame: int
    release_frame: int
    static: bool = False
    extra: np.ndarray | None = None
    g_by: dict = dataclasses.field(default_factory=dict)
    whole_by: dict = dataclasses.field(default_factory=dict)

    @property
    def true(self) -> np.ndarray:
        return self.motion.angles

    @property
    def stance(self) -> np.ndarray:
        return self.motion.stances

    @property
    def measured(self) -> np.ndarray:
        return self.scores[:, _MEASURED]

    @property
    def rula(self) -> np.ndarray:
        return self.scores[:, _RULA]

    @property
    def grand(self) -> np.ndarray:
        return self.scores[:, _GRAND]

    @property
    def n(self) -> int:
        return len(self.qpos)


class WorkerTrack:
    """Queues segments for one worker and hands out frames one control tick at a time."""

    def __init__(self, worker: Worker, stream: MocapStream, scorer: FeatureScorer | None = None) -> None:
        self.worker = worker
        self.stream = stream
        self.scorer = scorer
        """Extra posture features to score (REBA), or None (RULA's only)."""
        self.segment: Segment | None = None
        self.index = 0

    @classmethod
    def for_subject(cls, subject: Subject, rng: np.random.Generator, *, rate: float,
                    dropout_rate: float = 0.0, noise: bool | float = True,
                    scorer: FeatureScorer | None = None) -> WorkerTrack:
        """``subject``'s worker and mocap stream at ``rate`` [Hz], the stream drawing from ``rng``."""
        return cls(Worker(subject, rate=rate),
                   MocapStream(subject, rng, rate=rate, dropout_rate=dropout_rate, noise=noise), scorer)

    def _measure(self, motion: ActionMotion, acting: bool) -> Segment:
        frames = self.stream.measure(motion.angles)
        measured = frames.angles[:, :_N]
        parts, grand, g = score_frames(measured)
        rate = motion.rate
        grasp = int(np.ceil(motion.t_grasp * rate)) if np.isfinite(motion.t_grasp) else -1
        release = int(np.ceil(motion.t_release * rate)) if np.isfinite(motion.t_release) else -1
        scores = np.column_stack([np.full(len(g), float(acting)), np.isnan(g[:, 0]), measured, parts, grand])
        qpos = body_qpos(motion.angles, motion.stances)
        static = bool((qpos == qpos[0]).all())
        if self.scorer is None:
            return Segment(motion, qpos, scores, g, acting, grasp, release, static, None, {"rula": g},
                           {"rula": grand})
        extra, g_by, whole_by = self.scorer.score(measured, motion, acting)
        return Segment(motion, qpos, scores, g, acting, grasp, release, static, extra,
                       {"rula": g, **g_by}, {"rula": grand, **whole_by})

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

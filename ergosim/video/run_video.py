"""A video of one finished subject run: frames rendered from its recorded body poses, the overlay, MP4.

The video is made after the simulation, from what the run recorded (:attr:`SubjectRun.bodies`, the tick
log, the attempts, the decisions and the failures), so making one cannot change any result.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ergosim.errors import ConfigError
from ergosim.progress import Progress
from ergosim.scenes.workcell import Workcell
from ergosim.twin.records import SubjectRun
from ergosim.video.encode import Mp4Writer
from ergosim.video.frames import PoseRenderer, RenderQuality
from ergosim.video.overlay import Overlay
from ergosim.video.poses import PoseTrack
from ergosim.video.render_pool import FrameSpec, RenderPool, default_workers
from ergosim.video.timeline import RunTimeline

__all__ = ["VideoRequest", "VideoStats", "parse_reps", "parse_size", "action_texts", "write_run_video",
           "EVENT_HOLD"]

EVENT_HOLD = 4.0
"""Seconds of video a decision's reason or a failure stays on screen (assumed: time to read one line)."""


@dataclasses.dataclass(frozen=True)
class VideoRequest:
    """What to film: ``subject`` (0-based) in ``mode`` (None: the first mode run), repetitions ``reps`` =
    (first, last) 1-based and inclusive (None: the whole run), ``speed`` × real time, from the workcell's
    camera ``view`` (None: its first), ``width`` × ``height`` px at ``fps`` frames per second."""

    path: Path
    subject: int = 0
    mode: str | None = None
    reps: tuple[int, int] | None = None
    speed: float = 1.0
    view: str | None = None
    width: int = 960
    height: int = 540
    fps: float = 30.0


@dataclasses.dataclass(frozen=True)
class VideoStats:
    """What was written: ``frames`` at ``fps``, covering simulated time ``sim_start``..``sim_end`` [s]; time
    [s] spent rendering the scene, drawing the overlay and encoding, summed over the processes that did it
    (with worker processes they overlap), and ``wall_s`` the wall time of the whole video."""

    path: Path
    frames: int
    fps: float
    sim_start: float
    sim_end: float
    render_s: float
    overlay_s: float
    encode_s: float
    wall_s: float

    @property
    def seconds(self) -> float:
        """Length of the video [s]."""
        return self.frames / self.fps


def parse_reps(text: str, repetitions: int, where: str = "--video-reps") -> tuple[int, int]:
    """``"2"`` -> (2, 2), ``"2:4"`` -> (2, 4), ``"3:"`` -> (3, repetitions), ``":2"`` -> (1, 2); 1-based,
    inclusive, checked against the run's ``repetitions``."""
    head, sep, tail = text.strip().partition(":")
    try:
        first = int(head) if head.strip() else 1
        last = (int(tail) if tail.strip() else repetitions) if sep else first
    except ValueError:
        raise ConfigError(f"expected A:B, A: or A (repetition numbers), got {text!r}", where=where) from None
    if not 1 <= first <= last <= repetitions:
        raise ConfigError(f"repetitions {first}:{last} are not within 1..{repetitions} (first <= last)",
                          where=where)
    return first, last


def parse_size(text: str, where: str = "--video-size") -> tuple[int, int]:
    """``"960x540"`` -> (960, 540): even numbers of pixels from 64 to 3840."""
    w, sep, h = text.lower().partition("x")
    try:
        size = (int(w), int(h))
    except ValueError:
        raise ConfigError(f"expected WIDTHxHEIGHT in pixels, e.g. 960x540, got {text!r}",
                          where=where) from None
    if not sep or not all(64 <= v <= 3840 and v % 2 == 0 for v in size):
        raise ConfigError(f"width and height must be even numbers of pixels in 64..3840, got {text!r}",
                          where=where)
    return size


def action_texts(cell: Workcell) -> dict[str, str]:
    """Action label -> what it does in the cell, e.g. ``a2`` -> ``insert L``."""
    return {label: f"{g.kind} {g.part}" for label, g in cell.actions.items()}


def write_run_video(cell: Workcell, run: SubjectRun, request: VideoRequest, *, header: str = "",
                    window: tuple[float, float] | None = None, progress: bool = False,
                    quality: RenderQuality = RenderQuality(), text_scale: float = 1.0,
                    workers: int | None = None) -> VideoStats:
    """Render ``run`` (recorded with body poses) in ``cell`` (the workcell it ran in) to ``request.path``.

    ``window`` (start, end) [s of simulated time] overrides ``request.reps``. Frame k shows simulated time
    start + k · speed / fps. ``text_scale``: the overlay's size against the frame (see :class:`Overlay`).
    ``workers``: processes that render and overlay frames (:mod:`~ergosim.video.render_pool`; default
    :func:`~ergosim.video.render_pool.default_workers`, 0 renders here); the MP4 is the same either way.
    """
    wall0 = time.perf_counter()
    if run.bodies is None:
        raise ConfigError("the run was not recorded with body poses (run_subject(record_mode=...))",
                          where="--video")
    pos, quat = run.bodies
    if pos.shape[1] != cell.model.nbody:
        raise ConfigError(f"the run has {pos.shape[1]} bodies but the workcell {cell.model.nbody}: not the "
                          "workcell the run ran in", where="--video")
    timeline = RunTimeline(run, action_texts(cell),
                           frozenset(a for a, g in cell.actions.items() if g.handover))
    t0, t1 = window if window is not None else timeline.window(request.reps)
    step = request.speed / request.fps
    n = max(1, int(math.floor((t1 - t0) / step + 1e-9)) + 1)
    track = PoseTrack(timeline.t, pos, quat)
    spec = FrameSpec(cell.model, cell.config.view(request.view), request.width, request.height, quality,
                     header=header, speed=request.speed, text_scale=text_scale)
    hold = EVENT_HOLD * request.speed
    jobs = ((*track.at(t0 + k * step), timeline.at(t0 + k * step, hold)) for k in range(n))
    bar = Progress(n, f"video {Path(request.path).name}: frames", enabled=progress)
    spent = np.zeros(3)
    workers = default_workers() if workers is None else workers
    try:
        with contextlib.ExitStack() as stack:
            writer = stack.enter_context(Mp4Writer(request.path, request.width, request.height,
                                                   fps=request.fps))
            if workers > 0:
                frames = stack.enter_context(RenderPool(spec, workers)).frames(jobs)
            else:
                frames = _render_here(stack.enter_context(spec.renderer()), spec.overlay(), jobs)
            for k, (image, render_s, overlay_s) in enumerate(frames):
                c0 = time.perf_counter()
                writer.write(image)
                spent += (render_s, overlay_s, time.perf_counter() - c0)
                if k % 30 == 29 or k == n - 1:
                    bar.advance(min(30, n - bar.done))
    finally:
        bar.close()
    return VideoStats(Path(request.path), n, request.fps, t0, t0 + (n - 1) * step, *map(float, spent),
                      time.perf_counter() - wall0)


def _render_here(renderer: PoseRenderer, overlay: Overlay, jobs) -> Iterator[tuple[np.ndarray, float, float]]:
    """The frames of ``jobs`` rendered in this process, as :meth:`RenderPool.frames` gives them."""
    for pos, quat, info in jobs:
        c0 = time.perf_counter()
        image = renderer.render(pos, quat)
        c1 = time.perf_counter()
        image = overlay.draw(image, info)
        yield image, c1 - c0, time.perf_counter() - c1

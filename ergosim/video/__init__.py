"""Videos of the twin at work: offscreen MuJoCo frames from a run's recorded poses, an overlay, MP4/GIF.

Typical use (what ``ergosim run ... --video FILE.mp4`` does after the simulation)::

    run = run_subject(scenario, 0, seed, ("hrc",), record_mode="hrc").runs["hrc"]   # keeps body poses
    cell = subject_cell(scenario, scenario_subject(scenario, 0, seed))              # the cell it ran in
    write_run_video(cell, run, VideoRequest(Path("run.mp4"), reps=(1, 1), speed=4))

Frame rendering (:mod:`~ergosim.video.frames`), what a frame says (:mod:`~ergosim.video.timeline`), the
overlay drawing (:mod:`~ergosim.video.overlay`) and the encoder (:mod:`~ergosim.video.encode`) are apart.
"""

from ergosim.video.encode import Mp4Writer, gif_from_mp4, read_mp4
from ergosim.video.frames import PoseRenderer, RenderQuality, open_renderer
from ergosim.video.overlay import Overlay
from ergosim.video.poses import PoseTrack
from ergosim.video.run_video import (
    EVENT_HOLD,
    VideoRequest,
    VideoStats,
    action_texts,
    parse_reps,
    parse_size,
    write_run_video,
)
from ergosim.video.still import first_overlap, render_still
from ergosim.video.timeline import Event, FrameInfo, RunTimeline

__all__ = [
    "EVENT_HOLD",
    "Event",
    "FrameInfo",
    "Mp4Writer",
    "Overlay",
    "PoseRenderer",
    "PoseTrack",
    "RenderQuality",
    "RunTimeline",
    "VideoRequest",
    "VideoStats",
    "action_texts",
    "gif_from_mp4",
    "open_renderer",
    "parse_reps",
    "parse_size",
    "read_mp4",
    "write_run_video",
    "render_still",
    "first_overlap",
]

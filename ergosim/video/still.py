"""A still of a finished run at one instant, with the video's overlay: for pictures of what a run did (the
README's parallel gearbox). Rendered from the run's recorded body poses, like the video."""

from __future__ import annotations

import numpy as np

from ergosim.errors import ConfigError
from ergosim.scenes.workcell import Workcell
from ergosim.twin.records import SubjectRun
from ergosim.video.frames import PoseRenderer
from ergosim.video.overlay import Overlay
from ergosim.video.poses import PoseTrack
from ergosim.video.run_video import action_texts
from ergosim.video.timeline import RunTimeline

__all__ = ["render_still", "first_overlap"]


def render_still(cell: Workcell, run: SubjectRun, time: float, *, view: str | None = None,
                 width: int = 960, height: int = 540, header: str = "") -> np.ndarray:
    """(height, width, 3) uint8 image of ``run`` (recorded with body poses) in ``cell`` at sim ``time`` [s],
    with the overlay (the attempts in progress, KWear, the latest decisions)."""
    if run.bodies is None:
        raise ConfigError("the run was not recorded with body poses", where="render_still")
    handed = frozenset(a for a, g in cell.actions.items() if g.handover)
    timeline = RunTimeline(run, action_texts(cell), handed)
    track = PoseTrack(timeline.t, *run.bodies)
    with PoseRenderer(cell.model, cell.config.view(view), width=width, height=height) as renderer:
        image = renderer.render(*track.at(time))
    return Overlay(width, height, header=header).draw(image, timeline.at(time, hold=8.0))


def first_overlap(run: SubjectRun, after: float = 1.0) -> float | None:
    """A moment [s] when two agents' attempts are in progress at once, ``after`` seconds into the later
    one's start (None if they never overlap)."""
    rows = sorted((a for a in run.allocations if a.done), key=lambda a: a.t_start)
    for i, x in enumerate(rows):
        for y in rows[i + 1:]:
            start = max(x.t_start, y.t_start)
            if x.agent != y.agent and min(x.t_end, y.t_end) > start + after:
                return start + after
    return None

"""Film one subject of a scenario run: rebuild the workcell it ran in, then render its recorded run."""

from __future__ import annotations

import logging

from ergosim.experiment.scenario import Scenario
from ergosim.experiment.subject import SubjectResult, scenario_subject, subject_cell
from ergosim.video.run_video import VideoRequest, VideoStats, write_run_video

__all__ = ["film_subject"]

log = logging.getLogger(__name__)


def film_subject(scenario: Scenario, seed: int, result: SubjectResult, request: VideoRequest, *,
                 progress: bool = False) -> VideoStats:
    """The video of ``result`` (subject ``request.subject`` of ``seed``'s population, run with body poses
    kept for ``request.mode``) in the workcell built for that subject's body: the subject drawn as the
    scenario's protocol draws it (female fraction, pace), so the video shows the body that was simulated."""
    subject = scenario_subject(scenario, result.subject, seed)
    cell = subject_cell(scenario, subject)
    mode = request.mode or scenario.protocol.modes[0]
    header = f"{scenario.name} · subject {result.subject} ({result.name}) · {mode}"
    log.debug("filming subject %d (%s), mode %s, into %s", result.subject, result.name, mode, request.path)
    return write_run_video(cell, result.runs[mode], request, header=header, progress=progress)

"""The README's looping GIF: one HRC repetition of a real run in which the robot takes an action.

:func:`repetition_clip` runs one subject of a scenario in mode ``hrc`` (the real loop, body poses kept),
picks the first repetition in which a robot completed an action, films it (:func:`write_run_video`) and
turns the MP4 into a GIF. Beside the GIF it writes ``<name>.json``: the parameters, the filmed
repetition's attempts and the GIF's SHA-256, so a test can tell that the committed GIF is this function's
output for the simulation as it is.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import tempfile
from pathlib import Path

from ergosim import __version__
from ergosim.atomic import write_json
from ergosim.errors import ConfigError, RenderError
from ergosim.experiment.runner import run_subject
from ergosim.experiment.scenario import load_scenario
from ergosim.experiment.subject import scenario_subject, subject_cell
from ergosim.video.encode import gif_from_mp4
from ergosim.video.run_video import VideoRequest, write_run_video

__all__ = ["ClipSettings", "repetition_clip", "robot_repetition", "MAX_GIF_BYTES"]

MAX_GIF_BYTES = 3_000_000
"""The README's budget for the GIF (issue 16: under 3 MB)."""


@dataclasses.dataclass(frozen=True)
class ClipSettings:
    """``scenario`` run for ``subject`` of ``seed``'s population, ``repetitions`` at most, in mode hrc; the
    video at ``speed`` × real time, ``size`` px, its overlay ``text_scale`` × the video's; the GIF ``width``
    px wide at ``fps``."""

    scenario: str = "multi-subject"
    seed: int = 0
    subject: int = 0
    repetitions: int = 4
    speed: float = 6.0
    size: tuple[int, int] = (640, 360)
    text_scale: float = 1.35
    width: int = 640
    fps: float = 10.0
    colors: int = 128


def robot_repetition(run) -> int:
    """The first repetition in which a robot completed an action (ConfigError if none did)."""
    for a in sorted(run.allocations, key=lambda a: (a.repetition, a.order)):
        if a.done and run.by_robot(a.agent):
            return a.repetition
    raise ConfigError("the robot completed no action in this run: give more repetitions",
                      where="--repetitions")


def _attempts(run, rep: int) -> list[list]:
    return [[a.action, a.agent, a.status, round(a.t_start, 4), round(a.t_end, 4)]
            for a in run.allocations if a.repetition == rep]


def repetition_clip(gif: str | os.PathLike[str], settings: ClipSettings = ClipSettings(), *,
                    progress: bool = False) -> dict:
    """Write the GIF and its ``.json`` provenance; return the provenance (also what is in the file)."""
    gif = Path(gif)
    s = settings
    scenario = load_scenario(s.scenario, {"subjects": str(s.subject + 1), "repetitions": str(s.repetitions),
                                          "modes": "hrc"})
    run = run_subject(scenario, s.subject, s.seed, ("hrc",), record_mode="hrc").runs["hrc"]
    rep = robot_repetition(run)
    cell = subject_cell(scenario, scenario_subject(scenario, s.subject, s.seed))
    gif.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=gif.parent, prefix=f".{gif.name}.") as tmp:
        mp4 = Path(tmp) / "clip.mp4"
        request = VideoRequest(mp4, subject=s.subject, mode="hrc", reps=(rep, rep), speed=s.speed,
                               width=s.size[0], height=s.size[1])
        header = f"{scenario.name} · subject {s.subject} · hrc · seed {s.seed}"
        stats = write_run_video(cell, run, request, header=header, progress=progress, text_scale=s.text_scale)
        gif_from_mp4(mp4, gif, width=s.width, fps=s.fps, colors=s.colors)
    data = gif.read_bytes()
    if len(data) > MAX_GIF_BYTES:
        raise RenderError(f"the GIF is {len(data) / 1e6:.1f} MB, over the {MAX_GIF_BYTES / 1e6:g} MB budget: "
                          "lower --width or --fps, or raise --speed", where=str(gif))
    from PIL import Image  # noqa: PLC0415

    with Image.open(gif) as im:
        frames = im.n_frames
    doc = {
        "made_by": "scripts/make_readme_gif.py",
        "ergosim": __version__,
        "settings": {**dataclasses.asdict(s), "size": list(s.size)},
        "repetition": rep,
        "attempts": _attempts(run, rep),
        "sim_time": [round(stats.sim_start, 4), round(stats.sim_end, 4)],
        "video_frames": stats.frames,
        "gif_frames": frames,
        "bytes": len(data),
        "sha256": hashlib.sha256(data).hexdigest(),
    }
    write_json(gif.with_suffix(".json"), doc)
    return doc

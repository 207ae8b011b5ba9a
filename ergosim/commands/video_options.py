"""The ``--video`` options of ``ergosim run``, and their checks before any simulation time is spent.

Kept apart from :mod:`ergosim.commands.run` so the run command stays about running; the renderer and the
encoder are imported only when a video is asked for (``ergosim --help`` stays fast).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from ergosim.atomic import check_output_file
from ergosim.errors import ConfigError

__all__ = ["add_video_arguments", "video_request", "check_can_render", "video_line"]

_FLAGS = ("video_subject", "video_mode", "video_reps", "video_speed", "video_view", "video_size")
_MAX_SPEED = 1000.0


def add_video_arguments(p: argparse.ArgumentParser, modes: tuple[str, ...]) -> None:
    g = p.add_argument_group("video", "an MP4 of one subject's run in one mode, rendered offscreen after "
                                      "the simulation from its recorded poses (the results are the same with "
                                      "or without it)")
    g.add_argument("--video", metavar="FILE.mp4", help="write the video here")
    g.add_argument("--video-subject", type=int, metavar="N", help="subject filmed, 0-based (default 0)")
    g.add_argument("--video-mode", choices=modes, metavar="MODE", help="mode filmed (default: the first run)")
    g.add_argument("--video-reps", metavar="A:B",
                   help="repetitions A to B, 1-based and inclusive (A, A: and :B too; default: the whole "
                        "run)")
    g.add_argument("--video-speed", type=float, metavar="X", help="X times real time (default 1)")
    g.add_argument("--video-view", metavar="NAME", help="a camera view of the workcell (default: its first)")
    g.add_argument("--video-size", metavar="WxH", help="frame size in pixels (default 960x540)")


def video_request(args: argparse.Namespace, scenario):
    """The checked :class:`~ergosim.video.VideoRequest` of the parsed ``args`` for ``scenario``, or None
    without --video."""
    if args.video is None:
        given = [f for f in _FLAGS if getattr(args, f) is not None]
        if given:
            flag = "--" + given[0].replace("_", "-")
            raise ConfigError("choose what the video shows: give --video FILE.mp4 as well", where=flag)
        return None
    # only a filmed run imports the video (and with it rerun and matplotlib: 0.7 s of start-up)
    from ergosim.video.run_video import VideoRequest, parse_reps, parse_size  # noqa: PLC0415

    cfg = scenario.protocol
    path = Path(args.video)
    if path.suffix.lower() != ".mp4":
        raise ConfigError(f"the video is written as MP4: give a file name ending in .mp4, got {path.name!r}",
                          where="--video")
    check_output_file(path, where="--video")
    subject = 0 if args.video_subject is None else args.video_subject
    if not 0 <= subject < cfg.population.subjects:
        raise ConfigError(f"must be a subject index in 0..{cfg.population.subjects - 1}, got {subject}",
                          where="--video-subject")
    mode = args.video_mode or cfg.modes[0]
    if mode not in cfg.modes:
        raise ConfigError(f"mode {mode!r} is not run; modes run: {', '.join(cfg.modes)}",
                          where="--video-mode")
    reps = None if args.video_reps is None else parse_reps(args.video_reps, cfg.pacing.repetitions)
    speed = 1.0 if args.video_speed is None else args.video_speed
    if not (math.isfinite(speed) and 0 < speed <= _MAX_SPEED):
        raise ConfigError(f"must be a number in (0, {_MAX_SPEED:g}], got {speed:g}", where="--video-speed")
    width, height = parse_size(args.video_size or "960x540")
    try:
        scenario.cell().view(args.video_view)
    except ConfigError as err:  # the message names the cell's views
        raise ConfigError(err.what, where="--video-view") from None
    return VideoRequest(path=path, subject=subject, mode=mode, reps=reps, speed=speed, view=args.video_view,
                        width=width, height=height)


def check_can_render() -> None:
    """Open the encoder and an offscreen OpenGL context once, so a machine that cannot make the video says
    so before the simulation, not after it."""
    import mujoco  # noqa: PLC0415

    from ergosim.video.encode import ffmpeg_exe  # noqa: PLC0415
    from ergosim.video.frames import open_renderer  # noqa: PLC0415

    ffmpeg_exe()
    model = mujoco.MjModel.from_xml_string("<mujoco><worldbody><geom size='.1'/></worldbody></mujoco>")
    open_renderer(model, 64, 64).close()


def video_line(stats, request) -> str:
    """The line ``ergosim run`` prints about the video it made (``stats``: a
    :class:`~ergosim.video.VideoStats`)."""
    return (f"video: {stats.path.resolve()}  ({stats.frames} frames, {stats.seconds:.1f} s at "
            f"×{request.speed:g}, simulated time {stats.sim_start:.1f}-{stats.sim_end:.1f} s; rendered in "
            f"{stats.wall_s:.0f} s)")

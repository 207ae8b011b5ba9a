"""``ergosim report DIR``: write a finished run's report.html again from the files in its folder.

The page is the one ``ergosim run`` writes (:mod:`ergosim.experiment.report`): self-contained, drawn from
run.json, summary.json, the CSV files and the PNGs beside them. ``--video FILE`` embeds or links a video of
the run; without it, an MP4 in the folder is taken.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.errors import ConfigError

__all__ = ["add_parser", "run"]


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("report", help="write a finished run's report.html again from its folder's files",
                       description="Write report.html, one self-contained page of the run (no network), into "
                                   "an `ergosim run` output folder from the files in it.")
    p.add_argument("folder", help="the output folder of `ergosim run` (its --out)")
    p.add_argument("--video", metavar="MP4", help="a video of the run to put in the page (default: an .mp4 "
                                                  "in the folder, if there is one)")
    return p


def run(args) -> int:
    from ergosim.experiment.report import write_report  # noqa: PLC0415 - keep `ergosim --help` fast

    folder = Path(args.folder)
    if not folder.is_dir():
        raise ConfigError(f"{folder} is not a directory", where="ergosim report")
    video = Path(args.video) if args.video else next(iter(sorted(folder.glob("*.mp4"))), None)
    if video is not None and not video.is_file():
        raise ConfigError(f"no video file {video}", where="--video")
    path = write_report(folder, video=video)
    print(f"wrote {path} ({path.stat().st_size / 1e3:.0f} KB)")
    return 0

"""report.html: one self-contained page of a run that an engineer can hand on (no network: inline CSS, the
still and the figures as data URIs, a small video embedded, a large one linked).

It holds the cell's still, what the run says per mode (shares, overruns, the KWear integral), the takt and
the overruns in words, the allocation table per mode, per action G(a_k) and KWear per execution, the wear
timelines and the other figures, failures and refusals, every decision with its reason, and the video when
one was made. It is drawn from the folder's files alone (:mod:`~ergosim.experiment.report.sections`), so
``ergosim report DIR`` writes it again from a finished run.
"""

from __future__ import annotations

import os
from pathlib import Path

from ergosim.atomic import write_text
from ergosim.experiment.report.page import page
from ergosim.experiment.report.sections import read_run, sections

__all__ = ["REPORT_FILE", "STILL_FILE", "write_report", "report_html"]

REPORT_FILE = "report.html"
STILL_FILE = "cell.png"


def report_html(out: str | os.PathLike[str], video: str | os.PathLike[str] | None = None) -> str:
    """The page of the run folder ``out``; ``video``: an MP4 of the run to embed or link."""
    run = read_run(out)
    return page(f"ergosim run: {run.summary.get('scenario')}",
                sections(run, Path(video) if video is not None else None))


def write_report(out: str | os.PathLike[str], video: str | os.PathLike[str] | None = None) -> Path:
    """Write ``out``/report.html atomically; returns its path."""
    path = Path(out) / REPORT_FILE
    write_text(path, report_html(out, video))
    return path

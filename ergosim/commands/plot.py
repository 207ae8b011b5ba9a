"""``ergosim plot DIR``: redraw a finished run's figures from the CSV files in its folder.

Every figure is drawn from the files beside it (``ticks.csv``, ``allocations.csv``, ``subjects.csv``,
``kwear_actions.csv`` and ``run.json``), so a run's plots can be redrawn, e.g. for other subjects, without
running the simulation again.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ergosim.errors import ConfigError

__all__ = ["add_parser", "run", "parse_subjects", "add_plot_subject_argument"]


def add_plot_subject_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument("--plot-subject", metavar="N[,N...]",
                   help="subjects the timelines show, 0-based (default: every subject, a panel each); the "
                        "first one's actions make kwear_actions.png")


def parse_subjects(text: str | None, where: str = "--plot-subject") -> tuple[int, ...] | None:
    """``"0,3"`` -> (0, 3); None -> None (every subject)."""
    if text is None:
        return None
    try:
        subjects = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise ConfigError(f"expected subject indices such as 0 or 0,3, got {text!r}", where=where) from None
    if not subjects or min(subjects) < 0:
        raise ConfigError(f"expected subject indices >= 0 such as 0 or 0,3, got {text!r}", where=where)
    return subjects


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("plot", help="redraw a finished run's figures from the CSV files in its folder",
                       description="Redraw the PNG figures of an `ergosim run` output folder from its CSV "
                                   "files.")
    p.add_argument("folder", help="the output folder of `ergosim run` (its --out)")
    add_plot_subject_argument(p)
    return p


def run(args) -> int:
    from ergosim.experiment.plots import write_plots  # noqa: PLC0415 - keep `ergosim --help` fast

    folder = Path(args.folder)
    if not folder.is_dir():
        raise ConfigError(f"{folder} is not a directory", where="ergosim plot")
    written = write_plots(folder, parse_subjects(args.plot_subject))
    print(f"wrote {len(written)} figures in {folder}: {', '.join(written)}")
    return 0
